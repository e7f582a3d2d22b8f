//! [`View::check`]: whether a view can be used, and [`ViewError`], what is wrong with one that
//! cannot.
//!
//! A camera with a NaN eye (an uninitialised transform), an eye on its target, a field of view
//! of 0° or a viewport of no pixels gives no pixel scale or no direction: the runtime would
//! keep the whole mesh, or throw all of it away, with nothing to say why. The runtime, the
//! papers/000 rounds and the runtime's cut check their views first and refuse such a frame
//! (`lod::InputError`); [`View::check`] lets a caller check a camera where it is made.

use super::{Projection, View};

/// How far a view's `forward` and `up` may be from unit length and from square to each other:
/// the constructors and [`View::in_model_space`] leave them within a few ulps.
const AXIS_TOLERANCE: f32 = 1e-3;

/// What makes a [`View`] unusable ([`View::check`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ViewError {
    /// The eye is not a finite point (NaN or infinite coordinates).
    #[error("the eye is not a finite point")]
    Eye,
    /// `forward` is not a unit vector: most often the eye and the target coincide.
    #[error("the view has no direction: the eye and the target coincide, or forward is not a unit vector")]
    Direction,
    /// `up` is not a unit vector square to `forward`.
    #[error("the up vector is not a unit vector square to the view direction")]
    Up,
    /// A perspective view's vertical field of view is not strictly between 0° and 180°.
    #[error("the vertical field of view must lie strictly between 0° and 180°")]
    FieldOfView,
    /// An orthographic view's height is not a positive, finite number of world units.
    #[error("an orthographic view's height must be a positive, finite number of world units")]
    Height,
    /// The viewport is zero pixels wide or high.
    #[error("the viewport must be at least one pixel wide and one pixel high")]
    Viewport,
}

impl View {
    /// Whether this view can be used: a finite eye, unit `forward` and `up` square to each
    /// other, a field of view strictly between 0° and 180° (perspective) or a positive, finite
    /// height (orthographic), and a viewport of at least one pixel each way. Every view
    /// [`View::perspective`] and [`View::orthographic`] make from finite figures, with the
    /// eye off the target, a field of view in (0°, 180°) or a positive height, and a nonempty
    /// viewport, passes; so does what [`View::in_model_space`] makes of one.
    pub fn check(&self) -> Result<(), ViewError> {
        let unit = |v: [f32; 3]| {
            let l = glam::Vec3::from(v).length();
            l.is_finite() && (l - 1.0).abs() <= AXIS_TOLERANCE
        };
        if !self.eye.iter().all(|x| x.is_finite()) {
            return Err(ViewError::Eye);
        }
        if !unit(self.forward) {
            return Err(ViewError::Direction);
        }
        if !unit(self.up) || glam::Vec3::from(self.forward).dot(glam::Vec3::from(self.up)).abs() > AXIS_TOLERANCE {
            return Err(ViewError::Up);
        }
        match self.projection {
            Projection::Perspective { fov_y } if !(fov_y > 0.0 && fov_y < std::f32::consts::PI) => {
                return Err(ViewError::FieldOfView);
            }
            Projection::Orthographic { height } if !(height.is_finite() && height > 0.0) => {
                return Err(ViewError::Height);
            }
            _ => {}
        }
        if self.viewport.0 == 0 || self.viewport.1 == 0 {
            return Err(ViewError::Viewport);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const UP: [f32; 3] = [0.0, 1.0, 0.0];

    fn good() -> View {
        View::perspective([0.0, 0.0, 5.0], [0.0; 3], UP, 60.0, (640, 480))
    }

    #[test]
    fn made_views_pass() {
        assert_eq!(good().check(), Ok(()));
        assert_eq!(View::orthographic([3.0, 2.0, 1.0], [0.0; 3], UP, 2.0, (1, 1)).check(), Ok(()));
        // Up along the view direction: the constructor picks another.
        assert_eq!(View::perspective([0.0, 5.0, 0.0], [0.0; 3], UP, 179.0, (1920, 1080)).check(), Ok(()));
    }

    #[test]
    fn each_fault_is_named() {
        let nan = f32::NAN;
        let cases = [
            (View::perspective([nan, 0.0, 5.0], [0.0; 3], UP, 60.0, (640, 480)), ViewError::Eye),
            (View::perspective([f32::INFINITY, 0.0, 5.0], [0.0; 3], UP, 60.0, (640, 480)), ViewError::Eye),
            (View::perspective([1.0; 3], [1.0; 3], UP, 60.0, (640, 480)), ViewError::Direction),
            (View::perspective([0.0, 0.0, 5.0], [0.0; 3], UP, 0.0, (640, 480)), ViewError::FieldOfView),
            (View::perspective([0.0, 0.0, 5.0], [0.0; 3], UP, 180.0, (640, 480)), ViewError::FieldOfView),
            (View::perspective([0.0, 0.0, 5.0], [0.0; 3], UP, -60.0, (640, 480)), ViewError::FieldOfView),
            (View::perspective([0.0, 0.0, 5.0], [0.0; 3], UP, nan, (640, 480)), ViewError::FieldOfView),
            (View::perspective([0.0, 0.0, 5.0], [0.0; 3], UP, 60.0, (0, 480)), ViewError::Viewport),
            (View::perspective([0.0, 0.0, 5.0], [0.0; 3], UP, 60.0, (640, 0)), ViewError::Viewport),
            (View::orthographic([0.0, 0.0, 5.0], [0.0; 3], UP, 0.0, (640, 480)), ViewError::Height),
            (View::orthographic([0.0, 0.0, 5.0], [0.0; 3], UP, -1.0, (640, 480)), ViewError::Height),
            (View::orthographic([0.0, 0.0, 5.0], [0.0; 3], UP, f32::INFINITY, (640, 480)), ViewError::Height),
            (View { forward: [0.0, 0.0, -2.0], ..good() }, ViewError::Direction),
            (View { up: [0.0, 0.0, -1.0], ..good() }, ViewError::Up),
            (View { up: [0.0, 0.5, 0.0], ..good() }, ViewError::Up),
        ];
        for (k, (view, fault)) in cases.into_iter().enumerate() {
            assert_eq!(view.check(), Err(fault), "case {k}: {view:?}");
        }
    }
}
