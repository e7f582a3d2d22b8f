//! A perspective camera and the conversion of object-space error into screen pixels, for the
//! view-dependent passes (papers/000 §3: "e(V) is scaled using the angle between the view
//! vector and the vertex normal as well as the distance between vertex and camera").
//!
//! ```text
//!            eye ──────── d ────────► p          one unit of length at distance d covers
//!             \  fov_y /                          h / (2 · d · tan(fov_y / 2)) pixels on a
//!              \      /                           viewport h pixels high
//! ```

use glam::Vec3;

mod model_space;

pub use model_space::ModelMatrixError;

/// A perspective view: where the camera is, where it looks, and the viewport it renders to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Camera position.
    pub eye: [f32; 3],
    /// Unit view direction.
    pub forward: [f32; 3],
    /// Unit up vector, orthogonal to `forward`.
    pub up: [f32; 3],
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Viewport size in pixels (width, height).
    pub viewport: (u32, u32),
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
        Self { eye, forward: forward.to_array(), up: up.to_array(), fov_y: fov_y_degrees.to_radians(), viewport }
    }

    /// Pixels covered by one unit of length at point `p` (using its distance to the eye, so
    /// the figure does not change as the camera turns).
    pub fn pixels_per_unit(&self, p: [f32; 3]) -> f32 {
        Frustum::new(self).pixels_per_unit(p)
    }

    /// Pixels covered by one unit of length at distance `dist` from the eye (at least 1e-6).
    pub fn pixels_per_unit_at(&self, dist: f32) -> f32 {
        Frustum::new(self).pixels_per_unit_at(dist)
    }

    /// Whether a sphere of `radius` around `p` touches the view frustum (no far plane).
    pub fn in_frustum(&self, p: [f32; 3], radius: f32) -> bool {
        Frustum::new(self).touches_sphere(p, radius)
    }

    /// Cosine between the normal `n` at `p` and the direction from `p` to the eye: 1 facing
    /// the camera, 0 on the silhouette, negative facing away.
    pub fn facing(&self, p: [f32; 3], n: [f32; 3]) -> f32 {
        facing(Vec3::from(self.eye), p, n)
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
    /// tan of half the field of view, horizontally and vertically.
    tan: [f32; 2],
    /// √(1 + tan²) for each, the side planes' normalisation.
    norm: [f32; 2],
}

impl Frustum {
    /// The constants of `view`.
    pub fn new(view: &View) -> Self {
        let (forward, up) = (Vec3::from(view.forward), Vec3::from(view.up));
        let ty = (view.fov_y * 0.5).tan();
        let tx = ty * view.viewport.0 as f32 / view.viewport.1.max(1) as f32;
        Self {
            eye: Vec3::from(view.eye),
            forward,
            right: forward.cross(up),
            up,
            height: view.viewport.1 as f32,
            tan: [tx, ty],
            norm: [(1.0 + tx * tx).sqrt(), (1.0 + ty * ty).sqrt()],
        }
    }

    /// Pixels covered by one unit of length at distance `dist` from the eye (at least 1e-6).
    pub fn pixels_per_unit_at(&self, dist: f32) -> f32 {
        self.height / (2.0 * dist.max(1e-6) * self.tan[1])
    }

    /// Pixels covered by one unit of length at point `p` ([`View::pixels_per_unit`]).
    pub fn pixels_per_unit(&self, p: [f32; 3]) -> f32 {
        self.pixels_per_unit_at(Vec3::from(p).distance(self.eye))
    }

    /// Cosine between normal `n` at `p` and the direction to the eye ([`View::facing`]).
    pub fn facing(&self, p: [f32; 3], n: [f32; 3]) -> f32 {
        facing(self.eye, p, n)
    }

    /// Whether a sphere of `radius` around `p` touches the view frustum (no far plane).
    pub fn touches_sphere(&self, p: [f32; 3], radius: f32) -> bool {
        let d = Vec3::from(p) - self.eye;
        let z = d.dot(self.forward);
        if z < -radius {
            return false;
        }
        // Distance of the point to each side plane, compared with the radius.
        let inside = |coord: f32, k: usize| (coord.abs() - self.tan[k] * z) / self.norm[k] <= radius;
        inside(d.dot(self.right), 0) && inside(d.dot(self.up), 1)
    }
}
