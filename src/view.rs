//! A perspective camera and the conversion of object-space error into screen pixels, for the
//! view-dependent passes (papers/000 §3: "e(V) is scaled using the angle between the view
//! vector and the vertex normal as well as the distance between vertex and camera").
//!
//! ```text
//!            eye ──────── d ────────► p          one unit of length at distance d covers
//!             \  fov_y /                          h / (2 · d · tan(fov_y / 2)) pixels on a
//!              \      /                           viewport h pixels high
//! ```

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

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn normalize(a: [f32; 3]) -> [f32; 3] {
    let l = dot(a, a).sqrt();
    if l > 0.0 {
        a.map(|c| c / l)
    } else {
        a
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
        let forward = normalize(sub(target, eye));
        let mut right = cross(forward, up);
        if dot(right, right) < 1e-12 {
            let alt = if forward[1].abs() < 0.9 { [0.0, 1.0, 0.0] } else { [1.0, 0.0, 0.0] };
            right = cross(forward, alt);
        }
        let up = normalize(cross(normalize(right), forward));
        Self { eye, forward, up, fov_y: fov_y_degrees.to_radians(), viewport }
    }

    /// Pixels covered by one unit of length at point `p` (using its distance to the eye, so
    /// the figure does not change as the camera turns).
    pub fn pixels_per_unit(&self, p: [f32; 3]) -> f32 {
        let d = sub(p, self.eye);
        let dist = dot(d, d).sqrt().max(1e-6);
        self.viewport.1 as f32 / (2.0 * dist * (self.fov_y * 0.5).tan())
    }

    /// Whether a sphere of `radius` around `p` touches the view frustum (no far plane).
    pub fn in_frustum(&self, p: [f32; 3], radius: f32) -> bool {
        let d = sub(p, self.eye);
        let z = dot(d, self.forward);
        if z < -radius {
            return false;
        }
        let right = cross(self.forward, self.up);
        let x = dot(d, right);
        let y = dot(d, self.up);
        let ty = (self.fov_y * 0.5).tan();
        let tx = ty * self.viewport.0 as f32 / self.viewport.1.max(1) as f32;
        // Distance of the point to each side plane, compared with the radius.
        let inside = |coord: f32, t: f32| (coord.abs() - t * z) / (1.0 + t * t).sqrt() <= radius;
        inside(x, tx) && inside(y, ty)
    }

    /// Cosine between the normal `n` at `p` and the direction from `p` to the eye: 1 facing
    /// the camera, 0 on the silhouette, negative facing away.
    pub fn facing(&self, p: [f32; 3], n: [f32; 3]) -> f32 {
        dot(normalize(n), normalize(sub(self.eye, p)))
    }
}
