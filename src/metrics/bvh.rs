//! A bounding-volume hierarchy over triangles for nearest-point queries (Metro-style
//! distance sampling). Built once by median splits on the longest centroid axis; queried
//! with a best-first descent that prunes boxes farther than the best distance so far.
//!
//! ```text
//!   node: box, [first, count) of triangles when a leaf, else children (left = node + 1)
//!   query(p): visit nearer child first; skip any box whose distance² ≥ best²
//! ```

use glam::Vec3A;

const LEAF: usize = 4;

#[derive(Debug, Clone, Copy)]
struct Node {
    lo: Vec3A,
    hi: Vec3A,
    /// Leaf: first triangle index into `order`; inner: index of the right child.
    index: u32,
    /// Leaf: triangle count; inner: 0.
    count: u32,
}

/// Nearest-point queries against a fixed set of triangles.
#[derive(Debug, Clone)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Triangles in leaf order.
    tris: Vec<[Vec3A; 3]>,
    /// Input index of each triangle in leaf order.
    remap: Vec<u32>,
}

/// Result of a nearest-point query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nearest {
    /// Squared distance to the closest point.
    pub dist2: f32,
    /// The closest point on the surface.
    pub point: [f32; 3],
    /// Triangle it lies on (index into the triangles given to [`Bvh::new`]).
    pub triangle: u32,
}

impl Bvh {
    /// Builds the hierarchy over `triangles` (corner positions).
    pub fn new(triangles: &[[[f32; 3]; 3]]) -> Self {
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let tris: Vec<[Vec3A; 3]> = triangles.iter().map(|t| t.map(Vec3A::from)).collect();
        let centroids: Vec<Vec3A> = tris.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0).collect();
        let mut nodes = Vec::with_capacity(2 * triangles.len() / LEAF + 1);
        if !tris.is_empty() {
            build(&mut nodes, &tris, &centroids, &mut order, 0);
        }
        // Store triangles in leaf order so leaves read contiguous memory.
        let tris = order.iter().map(|&i| tris[i as usize]).collect();
        Self { nodes, tris, remap: order }
    }

    /// Whether there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// The closest point on any triangle to `p` (None when there are no triangles).
    pub fn nearest(&self, p: [f32; 3]) -> Option<Nearest> {
        if self.nodes.is_empty() {
            return None;
        }
        let p = Vec3A::from(p);
        let mut best = (f32::INFINITY, Vec3A::ZERO, 0u32);
        let mut stack: [u32; 64] = [0; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let n = &self.nodes[stack[sp] as usize];
            if box_dist2(n, p) >= best.0 {
                continue;
            }
            if n.count > 0 {
                for i in n.index..n.index + n.count {
                    let q = closest_on_triangle(p, &self.tris[i as usize]);
                    let d = (q - p).length_squared();
                    if d < best.0 {
                        best = (d, q, i);
                    }
                }
                continue;
            }
            let (l, r) = (stack[sp] + 1, n.index);
            let (dl, dr) = (box_dist2(&self.nodes[l as usize], p), box_dist2(&self.nodes[r as usize], p));
            let (near, far) = if dl <= dr { (l, r) } else { (r, l) };
            if sp + 2 <= stack.len() {
                stack[sp] = far;
                stack[sp + 1] = near;
                sp += 2;
            }
        }
        Some(Nearest { dist2: best.0, point: best.1.into(), triangle: self.remap[best.2 as usize] })
    }
}

fn box_dist2(n: &Node, p: Vec3A) -> f32 {
    let d = (n.lo - p).max(p - n.hi).max(Vec3A::ZERO);
    d.length_squared()
}

fn build(nodes: &mut Vec<Node>, tris: &[[Vec3A; 3]], cent: &[Vec3A], order: &mut [u32], first: usize) -> usize {
    let (mut lo, mut hi) = (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY));
    let (mut clo, mut chi) = (lo, hi);
    for &i in order.iter() {
        for v in tris[i as usize] {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        clo = clo.min(cent[i as usize]);
        chi = chi.max(cent[i as usize]);
    }
    let me = nodes.len();
    nodes.push(Node { lo, hi, index: first as u32, count: order.len() as u32 });
    if order.len() <= LEAF {
        return me;
    }
    let ext = chi - clo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&a, &b| cent[a as usize][axis].total_cmp(&cent[b as usize][axis]));
    let (left, right) = order.split_at_mut(mid);
    build(nodes, tris, cent, left, first);
    let r = build(nodes, tris, cent, right, first + mid);
    nodes[me].index = r as u32;
    nodes[me].count = 0;
    me
}

/// The closest point to `p` on triangle `t` (Ericson, Real-Time Collision Detection §5.1.5).
pub fn closest_on_triangle(p: Vec3A, t: &[Vec3A; 3]) -> Vec3A {
    let (a, b, c) = (t[0], t[1], t[2]);
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + ab * v;
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + ac * w;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + (c - b) * w;
    }
    let denom = va + vb + vc;
    if denom == 0.0 || !denom.is_finite() {
        // Degenerate (zero-area) triangle: nearest of its three edges.
        let e = [(a, b), (b, c), (c, a)].map(|(s, e)| closest_on_segment(p, s, e));
        return e.into_iter().min_by(|x, y| (*x - p).length_squared().total_cmp(&(*y - p).length_squared())).unwrap();
    }
    let (v, w) = (vb / denom, vc / denom);
    a + ab * v + ac * w
}

fn closest_on_segment(p: Vec3A, a: Vec3A, b: Vec3A) -> Vec3A {
    let ab = b - a;
    let l = ab.length_squared();
    if l == 0.0 {
        return a;
    }
    a + ab * ((p - a).dot(ab) / l).clamp(0.0, 1.0)
}
