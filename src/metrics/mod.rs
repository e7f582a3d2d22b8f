//! Quality metrics: the symmetric Hausdorff distance (max, mean, RMS) between two surfaces,
//! sampled as Metro does, with a BVH for nearest-point queries; and the same sampling applied
//! to what the surfaces show (normals, texture coordinates, colours).

mod attribute_error;
mod bvh;
mod hausdorff;
mod sampling;

pub use attribute_error::{attribute_errors, AttributeError};
pub use bvh::{closest_on_triangle, Bvh, Nearest};
pub use hausdorff::{hausdorff, Hausdorff, HausdorffOptions, OneSided};
pub use sampling::{sample, sample_interior};
