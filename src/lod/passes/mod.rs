//! One file per paper step.

pub mod anchors;
pub mod classify;
