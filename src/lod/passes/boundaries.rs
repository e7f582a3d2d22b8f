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
//! triangle against the view. An orthographic view has its eye at infinity: the direction
//! is the same from every point, −forward ([`Viewpoint::Towards`]), and the planes are the
//! edges' silhouettes under the parallel projection. Without an eye (view-independent
//! simplification) the direction towards the eye is replaced by the triangle's own normal.
//!
//! Selection (select.rs) refuses a target when the move leaves the candidate's side of a plane
//! of a face that survives the collapse — crossing it or ending on it, which would leave that
//! face edge-on. The faces that hold the target vanish with the collapse and are not tested.

use glam::DVec3;

use crate::view::Viewpoint;

/// A plane n · x + d = 0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Plane {
    /// Normal (not normalised).
    pub n: [f64; 3],
    /// Offset.
    pub d: f64,
    /// Bound on the rounding error of [`Plane::side`] per unit of |x|∞ + |p|∞ (p: the point
    /// the plane was built through); see [`Plane::tolerance`].
    err: f64,
    /// |p|∞ of the point the plane was built through.
    p_mag: f64,
}

/// Relative rounding bound for a side test in f64: a few dozen ulps of the terms summed,
/// far below the f32 resolution of the positions (6e-8) and far above f64's (1.1e-16).
const SIDE_RELATIVE_ERROR: f64 = 1e-12;

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

/// The (at most two) planes one triangle puts on a candidate; dereferences to a slice.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlaneSet {
    planes: [Plane; 2],
    len: usize,
}

impl PlaneSet {
    fn push(&mut self, p: Plane) {
        self.planes[self.len] = p;
        self.len += 1;
    }
}

impl std::ops::Deref for PlaneSet {
    type Target = [Plane];
    fn deref(&self) -> &[Plane] {
        &self.planes[..self.len]
    }
}

fn v(a: [f64; 3]) -> DVec3 {
    DVec3::from(a)
}

impl Plane {
    /// The plane through `p` spanned by `u` and `v`; `None` when they are parallel.
    pub fn through(p: [f64; 3], u: [f64; 3], w: [f64; 3]) -> Option<Plane> {
        let (u, w) = (v(u), v(w));
        let n = u.cross(w);
        let scale = u.length() * w.length();
        let p_mag = v(p).abs().max_element();
        (n.length() > 1e-12 * scale && scale > 0.0).then(|| Plane {
            n: n.to_array(),
            d: -n.dot(v(p)),
            err: SIDE_RELATIVE_ERROR * scale,
            p_mag,
        })
    }

    /// How far from zero [`Plane::side`] of `x` must be to trust its sign: n is a cross
    /// product of the two spanning vectors, so its error scales with |u||w|, and the side
    /// sums products with x and p. A point collinear with two mesh vertices (common on CAD
    /// and scan grids) lands within this band, on either side, by rounding alone.
    pub fn tolerance(&self, x: [f64; 3]) -> f64 {
        self.tolerance_at(v(x).abs().max_element())
    }

    /// [`Plane::tolerance`] of a point whose |x|∞ is `x_mag` (a caller testing one point
    /// against many planes works it out once).
    pub fn tolerance_at(&self, x_mag: f64) -> f64 {
        self.err * (x_mag + self.p_mag)
    }

    /// Signed side of `x` (scaled distance).
    pub fn side(&self, x: [f64; 3]) -> f64 {
        v(self.n).dot(v(x)) + self.d
    }

    /// Whether segment a–b has its ends strictly on opposite sides.
    pub fn crosses(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        let (sa, sb) = (self.side(a), self.side(b));
        (sa > 0.0 && sb < 0.0) || (sa < 0.0 && sb > 0.0)
    }

    /// Whether moving from `a` to `b` leaves a's side: crosses the plane or ends on it. Used
    /// for the planes of faces that survive the collapse: ending on one would leave the face
    /// edge-on (zero area, or seen exactly side-on), from where any later move may turn it
    /// away, one legal step at a time. A start on the plane (a face already edge-on) has no
    /// side to keep. "On the plane" includes the rounding band of [`Plane::tolerance`]: an end
    /// whose side rounding could have decided counts as leaving, which is the safe reading.
    pub fn leaves_side(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        let sa = self.side(a);
        sa != 0.0 && self.side(b) * sa.signum() <= self.tolerance(b)
    }
}

/// The boundary planes that triangle `tri` (corners counter-clockwise) puts on the candidate at
/// corner `r`, given which corners are candidates this round. `eye`: where the camera sees
/// from, or `None` for view-independent boundaries. Returns the planes and the test that
/// built them.
pub fn triangle_planes(tri: [[f64; 3]; 3], candidate: [bool; 3], r: usize, eye: Option<Viewpoint>) -> (PlaneSet, Test) {
    let mut set = PlaneSet::default();
    let test = triangle_planes_into(tri, face_normal(tri), candidate, r, eye, &mut |p| set.push(p));
    (set, test)
}

/// (t1 − t0) × (t2 − t0): the normal [`triangle_planes_into`] expects, its length twice the
/// triangle's area.
pub fn face_normal(tri: [[f64; 3]; 3]) -> DVec3 {
    let [t0, t1, t2] = tri.map(v);
    (t1 - t0).cross(t2 - t0)
}

/// [`triangle_planes`] for a caller that already has the face's [`face_normal`] (selection
/// also builds its quadric from it) and takes the planes one by one: no set is built and
/// copied out per triangle. Hands `out` the same planes in the same order. Inlined: the
/// selection calls it once per face of every candidate.
#[inline]
pub fn triangle_planes_into(
    tri: [[f64; 3]; 3],
    normal: DVec3,
    candidate: [bool; 3],
    r: usize,
    eye: Option<Viewpoint>,
    out: &mut impl FnMut(Plane),
) -> Test {
    let [t0, t1, t2] = tri.map(v);
    let normal = normal.to_array();
    let to_eye = |x: [f64; 3]| eye.map_or(normal, |e| e.seen_from(x));
    let sub = |a: [f64; 3], b: [f64; 3]| (v(a) - v(b)).to_array();
    let (a, b) = ((r + 1) % 3, (r + 2) % 3);
    let k = candidate.iter().filter(|&&c| c).count();
    let planes: [Option<Plane>; 2] = match (k, candidate[a], candidate[b]) {
        (1, _, _) | (_, false, false) => {
            // Test 1: the fixed edge a–b and the eye.
            if let Some(p) = Plane::through(tri[a], sub(tri[b], tri[a]), to_eye(tri[a])) {
                out(p);
            }
            return Test::One;
        }
        (2, ca, _) => {
            // Test 2: the other candidate and the fixed vertex.
            let (other, fixed) = if ca { (a, b) } else { (b, a) };
            let (vr1, vr2, v1) = (tri[r], tri[other], tri[fixed]);
            let mid = ((v(vr1) + v(vr2)) / 2.0).to_array();
            let e = to_eye(v1);
            [Plane::through(v1, sub(vr1, vr2), e), Plane::through(v1, e, sub(mid, v1))]
        }
        _ => {
            // Test 3: planes through the centroid parallel to the two edges at r.
            let s = ((t0 + t1 + t2) / 3.0).to_array();
            let e = to_eye(s);
            [Plane::through(s, sub(tri[a], tri[r]), e), Plane::through(s, sub(tri[b], tri[r]), e)]
        }
    };
    for p in planes.into_iter().flatten() {
        out(p);
    }
    if k == 2 {
        Test::Two
    } else {
        Test::Three
    }
}
