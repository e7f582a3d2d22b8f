//! Quality metrics: the symmetric Hausdorff distance (max, mean, RMS) between two surfaces,
//! sampled as Metro does, with a BVH for nearest-point queries.

mod bvh;
mod hausdorff;
mod sampling;

pub use bvh::{closest_on_triangle, Bvh, Nearest};
pub use hausdorff::{hausdorff, Hausdorff, HausdorffOptions, OneSided};
pub use sampling::sample;
