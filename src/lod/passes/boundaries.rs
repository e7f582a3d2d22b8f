//! The per-triangle boundary planes of papers/000 §4.1–4.3. A candidate V_R may collapse into
//! a neighbour N only if the edge V_R → N crosses none of the planes built from V_R's
//! triangles; the planes are built so that this holds whatever the neighbouring candidates
//! do in the same round, with no communication between them.
//!
//! ```text
//!  test 1 (only V_R moves)        test 2 (V_r1, V_r2 move)          test 3 (all three move)
//!      V1 ------ V2                      V1                          planes through the
//!        \  p   /                      / | \                         centroid S, parallel
//!         \    /     p ∋ V1, V2, E    /  p2 \    p1 ∋ V1 ∥ V_r1V_r2   to each edge at V_r
//!          V_R                      V_r1 --- V_r2 p2 ∋ V1, midpoint    (two per candidate)
//! ```
//! Every plane also contains the direction towards the eye E, so the planes are the
//! silhouettes of the triangle's edges as seen from E: crossing one is what turns the
//! triangle against the view. Without an eye (view-independent simplification) the direction
//! towards the eye is replaced by the triangle's own normal.
//!
//! An edge crosses a plane when its two ends lie strictly on opposite sides; an end on the
//! plane (the target of an edge inside the triangle) does not count.

/// A plane n · x + d = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// Normal (not normalised).
    pub n: [f64; 3],
    /// Offset.
    pub d: f64,
}

/// Which test built a plane: deadlock prevention (§5) needs to know.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Test {
    /// One candidate in the triangle.
    One,
    /// Two candidates.
    Two,
    /// Three candidates.
    Three,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Plane {
    /// The plane through `p` spanned by `u` and `v`; `None` when they are parallel.
    pub fn through(p: [f64; 3], u: [f64; 3], v: [f64; 3]) -> Option<Plane> {
        let n = cross(u, v);
        let scale = dot(u, u).sqrt() * dot(v, v).sqrt();
        (dot(n, n).sqrt() > 1e-12 * scale && scale > 0.0).then(|| Plane { n, d: -dot(n, p) })
    }

    /// Signed side of `x` (scaled distance).
    pub fn side(&self, x: [f64; 3]) -> f64 {
        dot(self.n, x) + self.d
    }

    /// Whether segment a–b has its ends strictly on opposite sides.
    pub fn crosses(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        let (sa, sb) = (self.side(a), self.side(b));
        (sa > 0.0 && sb < 0.0) || (sa < 0.0 && sb > 0.0)
    }
}

/// The boundary planes that triangle `tri` (corners counter-clockwise) puts on the candidate at
/// corner `r`, given which corners are candidates this round. `eye`: the camera position, or
/// `None` for view-independent boundaries. Returns the planes and the test that built them.
pub fn triangle_planes(
    tri: [[f64; 3]; 3],
    candidate: [bool; 3],
    r: usize,
    eye: Option<[f64; 3]>,
) -> (Vec<Plane>, Test) {
    let normal = cross(sub(tri[1], tri[0]), sub(tri[2], tri[0]));
    let to_eye = |x: [f64; 3]| eye.map_or(normal, |e| sub(e, x));
    let (a, b) = ((r + 1) % 3, (r + 2) % 3);
    let k = candidate.iter().filter(|&&c| c).count();
    let planes: Vec<Option<Plane>> = match (k, candidate[a], candidate[b]) {
        (1, _, _) | (_, false, false) => {
            // Test 1: the fixed edge a–b and the eye.
            let p = Plane::through(tri[a], sub(tri[b], tri[a]), to_eye(tri[a]));
            return (p.into_iter().collect(), Test::One);
        }
        (2, ca, _) => {
            // Test 2: the other candidate and the fixed vertex.
            let (other, fixed) = if ca { (a, b) } else { (b, a) };
            let (vr1, vr2, v1) = (tri[r], tri[other], tri[fixed]);
            let mid = [(vr1[0] + vr2[0]) / 2.0, (vr1[1] + vr2[1]) / 2.0, (vr1[2] + vr2[2]) / 2.0];
            let e = to_eye(v1);
            vec![Plane::through(v1, sub(vr1, vr2), e), Plane::through(v1, e, sub(mid, v1))]
        }
        _ => {
            // Test 3: planes through the centroid parallel to the two edges at r.
            let s = [0, 1, 2].map(|k| (tri[0][k] + tri[1][k] + tri[2][k]) / 3.0);
            let e = to_eye(s);
            vec![Plane::through(s, sub(tri[a], tri[r]), e), Plane::through(s, sub(tri[b], tri[r]), e)]
        }
    };
    let test = if k == 2 { Test::Two } else { Test::Three };
    (planes.into_iter().flatten().collect(), test)
}
