//! One file per paper step.

pub mod anchors;
pub mod apply;
pub mod boundaries;
pub mod classify;
pub mod select;
pub mod structure_anchors;
