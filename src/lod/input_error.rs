//! [`InputError`]: what the level-of-detail passes refuse to run on, checked before a frame, a
//! cut or a coarsening touches the mesh.
//!
//! A NaN camera or a negative pixel error has no meaning to coarsen for: taken as it comes,
//! it keeps the whole mesh or throws all of it away without a word. Each entry point checks
//! its views and thresholds first and, where one cannot be used, changes nothing and says
//! why: [`FrameStop::Refused`](super::FrameStop::Refused) from a runtime's update,
//! [`CoarsenStop::Refused`](super::coarsen::CoarsenStop::Refused) from papers/000's rounds,
//! an `Err` from [`Runtime::cut`](super::Runtime::cut).

use crate::view::{View, ViewError};

/// What a level-of-detail pass was given that it cannot use. Nothing was changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// A view fails [`View::check`]; `index` is its place in the views given.
    #[error("view {index}: {error}")]
    View {
        /// The view's place in the list given (0 for a single view).
        index: usize,
        /// What is wrong with it.
        error: ViewError,
    },
    /// The pixel error (or the model-space threshold without a view) is negative or NaN.
    /// Zero keeps everything; infinity removes all the views allow.
    #[error("the pixel error must be a number ≥ 0 (it is negative or NaN)")]
    PixelError,
    /// The hysteresis (τs / τc) is below 1 or NaN.
    #[error("the hysteresis must be a number ≥ 1")]
    Hysteresis,
}

/// Checks `views` in order, then `threshold` (≥ 0, not NaN): the first fault found.
pub(in crate::lod) fn check(views: &[View], threshold: f32) -> Result<(), InputError> {
    for (index, v) in views.iter().enumerate() {
        v.check().map_err(|error| InputError::View { index, error })?;
    }
    if threshold.is_nan() || threshold < 0.0 {
        return Err(InputError::PixelError);
    }
    Ok(())
}
