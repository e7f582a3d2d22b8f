//! The bundled bunny painted: area-weighted smooth normals and a colour field with detail the
//! geometry alone does not price. Shared by `examples/attribute_report.rs` and the simplify
//! bench, so attribute-weighted figures need no `../shared`.

#![allow(dead_code)]

use dynlod::IndexedMesh;
use glam::Vec3;

/// The bunny with smooth normals and colours that vary over the surface (bands and a spot),
/// so that both a normal and a colour field have detail the geometry alone does not price.
pub fn painted_bunny() -> IndexedMesh {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let mut m = dynlod::io::load(path).expect("the bundled bunny");
    let mut normals = vec![Vec3::ZERO; m.positions.len()];
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| Vec3::from(m.positions[i as usize]));
        let n = (b - a).cross(c - a);
        for &i in t {
            normals[i as usize] += n;
        }
    }
    m.normals = normals.iter().map(|n| n.normalize_or_zero().to_array()).collect();
    let (lo, hi) = m.bounds();
    let colours = m
        .positions
        .iter()
        .flat_map(|p| {
            let u: [f32; 3] = std::array::from_fn(|k| (p[k] - lo[k]) / (hi[k] - lo[k]));
            let band = 0.5 + 0.5 * (u[1] * 40.0).sin();
            let spot = (-((u[0] - 0.4).powi(2) + (u[1] - 0.6).powi(2)) * 60.0).exp();
            [band, 0.3 + 0.7 * spot, 1.0 - band, 1.0]
        })
        .collect();
    m.attributes.push(dynlod::mesh::VertexAttribute::new("COLOR_0", 4, colours));
    m
}
