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
        self.pixels_per_unit_at(Vec3::from(p).distance(Vec3::from(self.eye)))
    }

    /// Pixels covered by one unit of length at distance `dist` from the eye (at least 1e-6).
    pub fn pixels_per_unit_at(&self, dist: f32) -> f32 {
        self.viewport.1 as f32 / (2.0 * dist.max(1e-6) * (self.fov_y * 0.5).tan())
    }

    /// Whether a sphere of `radius` around `p` touches the view frustum (no far plane).
    pub fn in_frustum(&self, p: [f32; 3], radius: f32) -> bool {
        let (forward, up) = (Vec3::from(self.forward), Vec3::from(self.up));
        let d = Vec3::from(p) - Vec3::from(self.eye);
        let z = d.dot(forward);
        if z < -radius {
            return false;
        }
        let x = d.dot(forward.cross(up));
        let y = d.dot(up);
        let ty = (self.fov_y * 0.5).tan();
        let tx = ty * self.viewport.0 as f32 / self.viewport.1.max(1) as f32;
        // Distance of the point to each side plane, compared with the radius.
        let inside = |coord: f32, t: f32| (coord.abs() - t * z) / (1.0 + t * t).sqrt() <= radius;
        inside(x, tx) && inside(y, ty)
    }

    /// Cosine between the normal `n` at `p` and the direction from `p` to the eye: 1 facing
    /// the camera, 0 on the silhouette, negative facing away.
    pub fn facing(&self, p: [f32; 3], n: [f32; 3]) -> f32 {
        Vec3::from(n).normalize_or_zero().dot((Vec3::from(self.eye) - Vec3::from(p)).normalize_or_zero())
    }
}
