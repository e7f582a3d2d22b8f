//! Quality metrics: the symmetric Hausdorff distance (max, mean, RMS) between two surfaces,
//! sampled as Metro does, with a BVH for nearest-point queries; and the same sampling applied
//! to what the surfaces show (normals, texture coordinates, colours). Two meshes read
//! relative to different origins (`mesh/origin.rs`) are compared in the first one's frame.

mod attribute_error;
mod bvh;
mod hausdorff;
mod sampling;

pub use attribute_error::{attribute_errors, AttributeError};
pub use bvh::{closest_on_triangle, Bvh, Nearest};
pub use hausdorff::{hausdorff, Hausdorff, HausdorffOptions, OneSided};
pub use sampling::{sample, sample_interior};

use crate::mesh::IndexedMesh;

/// `m`'s triangles as corner positions, relative to `origin` (the other mesh's).
fn corners(m: &IndexedMesh, origin: [f64; 3]) -> Vec<[[f32; 3]; 3]> {
    let positions = crate::mesh::origin::rebased(&m.positions, m.origin, origin);
    m.triangles.iter().map(|t| t.map(|i| positions[i as usize])).collect()
}
