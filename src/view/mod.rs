//! Cameras (perspective and orthographic) and the conversion of object-space error into
//! screen pixels, for the view-dependent passes (papers/000 §3: "e(V) is scaled using the
//! angle between the view vector and the vertex normal as well as the distance between vertex
//! and camera").
//!
//! ```text
//!   perspective:  eye ─── d ───► p     one unit at distance d covers h / (2 · d · tan(fov_y / 2))
//!                  \ fov_y /           pixels on a viewport h pixels high
//!
//!   orthographic: eye ═══════► p       one unit covers h / height pixels wherever it is:
//!                 ═════════════        `height` world units fill the viewport's height, and
//!                 ═════════════        every point sees the camera along −forward
//! ```
//!
//! An orthographic camera is a perspective one with its eye moved to infinity along
//! −forward: papers/000's boundary planes, which contain the direction from a vertex to the
//! eye, then contain −forward itself ([`Viewpoint::Towards`]), and the facing of a triangle
//! is the sign of its normal against −forward. Shadow-map passes of directional lights, CAD
//! and map views, and 2.5D games draw this way.

use glam::Vec3;

mod check;
mod model_space;

pub use check::ViewError;
pub use model_space::{check_model_matrix, views_through, ModelMatrixError};

/// A view: where the camera is, where it looks, how it projects, and the viewport it renders to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Camera position. For an orthographic view, the plane through it across `forward` is
    /// the near plane: only what lies in front of it is in the frustum.
    pub eye: [f32; 3],
    /// Unit view direction.
    pub forward: [f32; 3],
    /// Unit up vector, orthogonal to `forward`.
    pub up: [f32; 3],
    /// How the camera projects.
    pub projection: Projection,
    /// Viewport size in pixels (width, height).
    pub viewport: (u32, u32),
}

/// How a [`View`] projects the scene onto its viewport.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// A pinhole camera: things shrink with distance.
    Perspective {
        /// Vertical field of view, radians.
        fov_y: f32,
    },
    /// Parallel rays along `forward`: sizes on screen do not depend on distance.
    Orthographic {
        /// World units the viewport's height covers (the width follows from its aspect).
        height: f32,
    },
}

/// Where a view sees each point from, for papers/000's boundary planes and the facing of
/// triangles: the eye of a perspective view, or the direction towards an orthographic one
/// (its eye at infinity). In f64, as the planes are built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Viewpoint {
    /// A perspective camera's eye.
    At([f64; 3]),
    /// The unit direction from the scene towards an orthographic camera (−forward).
    Towards([f64; 3]),
}

impl Viewpoint {
    /// The direction from `x` towards the camera: eye − x, or the fixed direction of an
    /// orthographic view (not normalised in the first case).
    #[inline]
    pub fn seen_from(&self, x: [f64; 3]) -> [f64; 3] {
        match *self {
            Self::At(e) => (glam::DVec3::from(e) - glam::DVec3::from(x)).to_array(),
            Self::Towards(d) => d,
        }
    }
}

impl View {
    /// A camera at `eye` looking at `target`, `up` roughly upwards, vertical field of view in
    /// degrees, viewport in pixels. Falls back to a valid up vector when `up` is parallel to
    /// the view direction.
    pub fn perspective(
        eye: [f32; 3],
        target: [f32; 3],
        up: [f32; 3],
        fov_y_degrees: f32,
        viewport: (u32, u32),
    ) -> Self {
        let forward = (Vec3::from(target) - Vec3::from(eye)).normalize_or_zero();
        let mut right = forward.cross(Vec3::from(up));
        if right.length_squared() < 1e-12 {
            let alt = if forward.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
            right = forward.cross(alt);
        }
        let up = right.normalize_or_zero().cross(forward).normalize_or_zero();
        let projection = Projection::Perspective { fov_y: fov_y_degrees.to_radians() };
        Self { eye, forward: forward.to_array(), up: up.to_array(), projection, viewport }
    }

    /// An orthographic camera at `eye` looking towards `target` (only the direction counts;
    /// `eye` also places the near plane), `up` roughly upwards, with `height` world units
    /// filling the viewport's height. Same fallback for `up` as [`View::perspective`].
    /// `eye` must differ from `target`: with no direction, no face faces the view and the
    /// boundary planes hold nothing back.
    pub fn orthographic(eye: [f32; 3], target: [f32; 3], up: [f32; 3], height: f32, viewport: (u32, u32)) -> Self {
        let p = Self::perspective(eye, target, up, 60.0, viewport);
        Self { projection: Projection::Orthographic { height }, ..p }
    }

    /// The orthographic view with this view's eye, axes and viewport that frames what this
    /// one frames at `distance` from its eye: height 2 · distance · tan(fov_y / 2). An
    /// orthographic view comes back unchanged.
    pub fn orthographic_at(&self, distance: f32) -> Self {
        match self.projection {
            Projection::Perspective { fov_y } => {
                Self { projection: Projection::Orthographic { height: 2.0 * distance * (fov_y * 0.5).tan() }, ..*self }
            }
            Projection::Orthographic { .. } => *self,
        }
    }

    /// Where this view sees points from ([`Viewpoint`]).
    pub fn viewpoint(&self) -> Viewpoint {
        match self.projection {
            Projection::Perspective { .. } => Viewpoint::At(self.eye.map(f64::from)),
            Projection::Orthographic { .. } => Viewpoint::Towards(self.forward.map(|x| -f64::from(x))),
        }
    }

    /// Pixels covered by one unit of length at point `p` (perspective: using its distance to
    /// the eye, so the figure does not change as the camera turns; orthographic: the same
    /// everywhere).
    pub fn pixels_per_unit(&self, p: [f32; 3]) -> f32 {
        Frustum::new(self).pixels_per_unit(p)
    }

    /// Pixels covered by one unit of length at distance `dist` from the eye (at least 1e-6;
    /// orthographic: any distance).
    pub fn pixels_per_unit_at(&self, dist: f32) -> f32 {
        Frustum::new(self).pixels_per_unit_at(dist)
    }

    /// Whether a sphere of `radius` around `p` touches the view frustum (no far plane; for
    /// an orthographic view, the box in front of the eye's plane).
    pub fn in_frustum(&self, p: [f32; 3], radius: f32) -> bool {
        Frustum::new(self).touches_sphere(p, radius)
    }

    /// Cosine between the normal `n` at `p` and the direction from `p` to the eye (for an
    /// orthographic view, −forward): 1 facing the camera, 0 on the silhouette, negative
    /// facing away.
    pub fn facing(&self, p: [f32; 3], n: [f32; 3]) -> f32 {
        Frustum::new(self).facing(p, n)
    }

    /// Whether `other` is this view bit for bit (unlike `==`, which takes 0.0 for −0.0 and
    /// no NaN for itself): every figure worked out from the two views is the same.
    pub fn is_identical(&self, other: &View) -> bool {
        self.bits() == other.bits()
    }

    /// Every figure of the view as bits, in an order for sorting: equal exactly where
    /// [`View::is_identical`].
    fn bits(&self) -> ViewBits {
        let lens = match self.projection {
            Projection::Perspective { fov_y } => (0, fov_y.to_bits()),
            Projection::Orthographic { height } => (1, height.to_bits()),
        };
        let axes = [self.eye, self.forward, self.up].map(|a| a.map(f32::to_bits));
        (axes, lens, self.viewport)
    }
}

/// Cosine between normal `n` at `p` and the direction from `p` to `eye`.
fn facing(eye: Vec3, p: [f32; 3], n: [f32; 3]) -> f32 {
    Vec3::from(n).normalize_or_zero().dot((eye - Vec3::from(p)).normalize_or_zero())
}

/// A view's constants for per-vertex tests, worked out once per frame: the tangents and plane
/// norms of the side planes and the camera axes (the [`View`] methods recompute them on every
/// call). Same formulas, same results bit for bit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frustum {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    height: f32,
    /// Perspective: tan of half the field of view, horizontally and vertically.
    /// Orthographic: half the width and height the viewport covers, in world units.
    tan: [f32; 2],
    /// Perspective: √(1 + tan²) for each, the side planes' normalisation. Unused orthographic.
    norm: [f32; 2],
    /// Orthographic: pixels per world unit, everywhere. `None` for a perspective view.
    ortho: Option<f32>,
}

/// A view's figures as bits ([`View::is_identical`]).
type ViewBits = ([[u32; 3]; 3], (u8, u32), (u32, u32));

/// Up to this many views are compared pairwise; more are sorted by their bits.
const PAIRWISE_UP_TO: usize = 16;

/// The positions in `views` of the views that are not repeats of an earlier one (bit for bit,
/// [`View::is_identical`]), in order, into `keep` (`order`: a list kept for reuse): a view
/// repeated adds nothing to a cut or an update for several views (the largest error and every
/// eye's planes are the same without it). Pairwise for a few views; for many (a mesh drawn by
/// hundreds of instances, where pairwise took 2 ms a frame for 400) by sorting their bits.
pub(crate) fn distinct_into(views: &[View], order: &mut Vec<u32>, keep: &mut Vec<u32>) {
    keep.clear();
    if views.len() <= PAIRWISE_UP_TO {
        let fresh = |&(k, v): &(usize, &View)| !views[..k].iter().any(|w| w.is_identical(v));
        keep.extend(views.iter().enumerate().filter(fresh).map(|(k, _)| k as u32));
        return;
    }
    order.clear();
    order.extend(0..views.len() as u32);
    let bits = |k: u32| views[k as usize].bits();
    // Equal bits together, the earliest first: each run's first is the one kept.
    order.sort_unstable_by(|&a, &b| bits(a).cmp(&bits(b)).then(a.cmp(&b)));
    keep.extend(order.iter().enumerate().filter(|&(i, &k)| i == 0 || bits(order[i - 1]) != bits(k)).map(|(_, &k)| k));
    keep.sort_unstable();
}

impl Frustum {
    /// The constants of `view`.
    pub fn new(view: &View) -> Self {
        let (forward, up) = (Vec3::from(view.forward), Vec3::from(view.up));
        // The vertical half extent (a tangent, or world units) widened by the aspect ratio.
        let widen = |y: f32| [y * view.viewport.0 as f32 / view.viewport.1.max(1) as f32, y];
        let (tan, ortho) = match view.projection {
            Projection::Perspective { fov_y } => (widen((fov_y * 0.5).tan()), None),
            Projection::Orthographic { height } => {
                (widen(height.abs() * 0.5), Some(view.viewport.1 as f32 / height.abs().max(1e-30)))
            }
        };
        Self {
            eye: Vec3::from(view.eye),
            forward,
            right: forward.cross(up),
            up,
            height: view.viewport.1 as f32,
            tan,
            norm: [(1.0 + tan[0] * tan[0]).sqrt(), (1.0 + tan[1] * tan[1]).sqrt()],
            ortho,
        }
    }

    /// The eye this frustum was built for ([`View::eye`]), bit for bit.
    pub fn eye(&self) -> [f32; 3] {
        self.eye.to_array()
    }

    /// Whether the view is orthographic (its pixels per unit the same at every distance).
    pub fn is_orthographic(&self) -> bool {
        self.ortho.is_some()
    }

    /// Pixels covered by one unit of length at distance `dist` from the eye (at least 1e-6);
    /// orthographic: the same at any distance.
    pub fn pixels_per_unit_at(&self, dist: f32) -> f32 {
        match self.ortho {
            Some(ppu) => ppu,
            None => self.height / (2.0 * dist.max(1e-6) * self.tan[1]),
        }
    }

    /// Pixels covered by one unit of length at point `p` ([`View::pixels_per_unit`]).
    pub fn pixels_per_unit(&self, p: [f32; 3]) -> f32 {
        match self.ortho {
            Some(ppu) => ppu,
            None => self.pixels_per_unit_at(Vec3::from(p).distance(self.eye)),
        }
    }

    /// Cosine between normal `n` at `p` and the direction to the eye ([`View::facing`]).
    pub fn facing(&self, p: [f32; 3], n: [f32; 3]) -> f32 {
        match self.ortho {
            Some(_) => Vec3::from(n).normalize_or_zero().dot(-self.forward),
            None => facing(self.eye, p, n),
        }
    }

    /// Whether a sphere of `radius` around `p` touches the view frustum (no far plane).
    pub fn touches_sphere(&self, p: [f32; 3], radius: f32) -> bool {
        let d = Vec3::from(p) - self.eye;
        let z = d.dot(self.forward);
        if z < -radius {
            return false;
        }
        if self.ortho.is_some() {
            // A box: the side planes are parallel, `tan` holds their half extents.
            let inside = |coord: f32, k: usize| coord.abs() - self.tan[k] <= radius;
            return inside(d.dot(self.right), 0) && inside(d.dot(self.up), 1);
        }
        // Distance of the point to each side plane, compared with the radius.
        let inside = |coord: f32, k: usize| (coord.abs() - self.tan[k] * z) / self.norm[k] <= radius;
        inside(d.dot(self.right), 0) && inside(d.dot(self.up), 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Many views with repeats (scrambled, −0.0 beside 0.0, one orthographic twin of a
    /// perspective view): sorting their bits keeps the same views, in the same order, as
    /// comparing them pairwise.
    #[test]
    fn many_views_are_told_apart_as_a_few_are() {
        let base = |k: usize| {
            let x = if k == 3 { -0.0 } else { k as f32 * 0.5 };
            let v = View::perspective([x, 1.0, 4.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
            if k % 4 == 1 {
                v.orthographic_at(4.0)
            } else {
                v
            }
        };
        let views: Vec<View> = (0..60).map(|i| base((i * 7) % 13 % 9)).collect();
        let pairwise: Vec<u32> = (0..views.len())
            .filter(|&k| !views[..k].iter().any(|w| w.is_identical(&views[k])))
            .map(|k| k as u32)
            .collect();
        let (mut order, mut keep) = (Vec::new(), Vec::new());
        distinct_into(&views, &mut order, &mut keep);
        assert_eq!(keep, pairwise);
        assert_eq!(keep.len(), 9);
        // A few take the pairwise path: the same.
        distinct_into(&views[..10], &mut order, &mut keep);
        assert_eq!(keep, pairwise.iter().copied().filter(|&k| k < 10).collect::<Vec<_>>());
    }
}
