//! Tangents for normal maps, where the file has none: MikkTSpace's, made on the mesh as
//! loaded, so that they ride through simplification like any attribute.
//!
//! A tangent-space normal map is baked against a tangent frame, and glTF 2.0 (§3.7.2.1)
//! names the frame a primitive without `TANGENT` means: MikkTSpace's, computed "using the
//! specified vertex positions, normals, and texture coordinates". A viewer computes it from
//! the mesh it is given; given a simplified mesh, it computes another frame than the one the
//! map was baked against, and the map shades wrongly wherever the two part. Made here, on
//! the full mesh, the frame is the one the map was baked for, and the simplified mesh keeps
//! it at every vertex that survives (half-edge collapses keep the survivor's wedges). GLB
//! output then carries it (and the Khronos validator no longer warns that the tangent space
//! is left to the viewer).
//!
//! The frames are meshoptimizer's `meshopt_generateTangents` in its MikkTSpace-compatible
//! mode (same weighting and fallbacks as the reference implementation, which bakers use).
//! They are per triangle corner: where corners of one vertex get different frames (a mirrored
//! UV island's handedness), the vertex is split, its other attributes copied, as a glTF
//! exporter would write it. A primitive gets frames where its material has a normal texture
//! on `TEXCOORD_0`, it has normals and texture coordinates, finite, and no `TANGENT` of its
//! own.

use crate::mesh::{IndexedMesh, VertexAttribute};

/// Adds MikkTSpace tangents to the primitives of `mesh` whose normal map has none (see the
/// module docs); returns how many primitives got them.
pub(super) fn add(mesh: &mut IndexedMesh) -> usize {
    let wanted = primitives_wanting(mesh);
    let count = wanted.iter().filter(|&&w| w).count();
    if count == 0 {
        return 0;
    }
    let p_count = wanted.len();
    let corners: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&t| wanted[mesh.primitive_of(t) as usize])
        .flat_map(|t| (0..3).map(move |c| 3 * t + c))
        .collect();
    let indices: Vec<u32> = corners.iter().map(|&k| mesh.triangles[k / 3][k % 3]).collect();
    let frames = meshopt::generate_tangents(
        Some(&indices),
        &mesh.positions,
        &mesh.normals,
        &mesh.uvs,
        meshopt::TangentOptions::Compatible,
    );
    // The TANGENT attribute, made where there is none (absent from every primitive).
    let at = match mesh.attributes.iter().position(|a| a.semantic == "TANGENT") {
        Some(at) => at,
        None => {
            let mut tangent = VertexAttribute::zeros("TANGENT", 4, mesh.positions.len());
            tangent.absent = (0..p_count as u32).collect();
            mesh.attributes.push(tangent);
            mesh.attributes.len() - 1
        }
    };
    // Each vertex takes its first corner's frame; a corner with another frame gets a copy of
    // its vertex (one per distinct frame).
    let mut given: Vec<Option<[f32; 4]>> = vec![None; mesh.positions.len()];
    let mut copies: rustc_hash::FxHashMap<(u32, [u32; 4]), u32> = rustc_hash::FxHashMap::default();
    for (&k, frame) in corners.iter().zip(&frames) {
        let v = mesh.triangles[k / 3][k % 3];
        let frame = frame.map(|c| if c.is_finite() { c } else { 0.0 });
        match given[v as usize] {
            None => given[v as usize] = Some(frame),
            Some(f) if f == frame => {}
            Some(_) => {
                let copy = *copies.entry((v, frame.map(f32::to_bits))).or_insert_with(|| {
                    given.push(Some(frame));
                    mesh.push_copy(v)
                });
                mesh.triangles[k / 3][k % 3] = copy;
            }
        }
    }
    let tangent = &mut mesh.attributes[at];
    for (v, frame) in given.iter().enumerate() {
        if let Some(frame) = frame {
            tangent.values[4 * v..4 * v + 4].copy_from_slice(frame);
        }
    }
    tangent.absent.retain(|&p| !wanted[p as usize]);
    count
}

/// Whether each primitive's material has a normal texture on `TEXCOORD_0`, with normals and
/// texture coordinates (finite, and normals not zero at any of its vertices) and no tangents
/// of its own.
fn primitives_wanting(mesh: &IndexedMesh) -> Vec<bool> {
    let Some(materials) = mesh.gltf_materials.as_ref() else {
        return Vec::new();
    };
    if mesh.normals.is_empty() || mesh.uvs.is_empty() {
        return Vec::new();
    }
    let tangent = mesh.attributes.iter().find(|a| a.semantic == "TANGENT");
    let p_count = mesh.primitives.len().max(1);
    let mut wanted: Vec<bool> = (0..p_count)
        .map(|p| {
            let primitive = mesh.primitives.get(p);
            let normal_map =
                primitive.and_then(|q| q.material).and_then(|k| materials.materials.get(k)).and_then(|m| {
                    let info = m.get("normalTexture")?;
                    (info["texCoord"].as_u64().unwrap_or(0) == 0).then_some(())
                });
            let bare = primitive.is_some_and(|q| q.no_normals || q.no_uvs);
            let has_tangents = tangent.is_some_and(|a| !a.absent.contains(&(p as u32)));
            normal_map.is_some() && !bare && !has_tangents
        })
        .collect();
    // Every vertex of a wanted primitive must have a usable normal and texture coordinates.
    if !wanted.contains(&true) {
        return wanted;
    }
    for t in 0..mesh.triangles.len() {
        let p = mesh.primitive_of(t) as usize;
        let usable = |v: &u32| {
            let (n, uv) = (mesh.normals[*v as usize], mesh.uvs[*v as usize]);
            n.iter().chain(&uv).all(|c| c.is_finite()) && n != [0.0; 3]
        };
        if wanted[p] && !mesh.triangles[t].iter().all(usable) {
            wanted[p] = false;
        }
    }
    wanted
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{GltfMaterials, Primitive};
    use std::sync::Arc;

    /// A quad of two triangles in the xy plane facing +z, its texture coordinates as given,
    /// material 0 with a normal texture.
    fn quad(uvs: [[f32; 2]; 4]) -> IndexedMesh {
        let mut m = IndexedMesh::from_triangles(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        m.normals = vec![[0.0, 0.0, 1.0]; 4];
        m.uvs = uvs.to_vec();
        m.primitives = vec![Primitive { material: Some(0), ..Primitive::default() }];
        m.gltf_materials = Some(Arc::new(GltfMaterials {
            materials: serde_json::json!([{ "normalTexture": { "index": 0 } }]),
            ..GltfMaterials::default()
        }));
        m
    }

    /// u along +x: the tangent is +x; glTF's v runs down the image, so +y on the quad is −v,
    /// and the frame's handedness says which way the bitangent goes.
    #[test]
    fn a_quad_gets_its_u_direction() {
        let mut m = quad([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
        assert_eq!(add(&mut m), 1);
        let t = m.attributes.iter().find(|a| a.semantic == "TANGENT").unwrap();
        assert!(t.absent.is_empty());
        for v in 0..4 {
            let f = t.get(v);
            assert!((f[0] - 1.0).abs() < 1e-6 && f[1].abs() < 1e-6 && f[2].abs() < 1e-6, "{f:?}");
            assert!(f[3] == 1.0 || f[3] == -1.0);
        }
        assert_eq!(m.positions.len(), 4, "no corner disagrees");
        // A second call finds tangents there and adds none.
        assert_eq!(add(&mut m), 0);
    }

    /// Without a normal map, normals or texture coordinates, nothing is made.
    #[test]
    fn only_normal_mapped_primitives_get_frames() {
        let uvs = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
        let mut plain = quad(uvs);
        plain.gltf_materials = Some(Arc::new(GltfMaterials {
            materials: serde_json::json!([{ "name": "no map" }]),
            ..GltfMaterials::default()
        }));
        let mut second_set = quad(uvs);
        second_set.gltf_materials = Some(Arc::new(GltfMaterials {
            materials: serde_json::json!([{ "normalTexture": { "index": 0, "texCoord": 1 } }]),
            ..GltfMaterials::default()
        }));
        let mut flat = quad(uvs);
        flat.normals[2] = [0.0; 3];
        for mut m in [plain, second_set, flat] {
            assert_eq!(add(&mut m), 0);
            assert!(m.attributes.is_empty());
        }
    }

    /// Two triangles sharing an edge whose texture coordinates mirror across it: the shared
    /// vertices' corners disagree in handedness and are split, the copies keeping every
    /// other value.
    #[test]
    fn a_mirrored_seam_splits_its_vertices() {
        // Vertex 1 and 2 are shared; u runs right on the first triangle, left on the second.
        let mut m = IndexedMesh::from_triangles(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 0.0, 0.0]],
            vec![[0, 1, 2], [1, 3, 2]],
        );
        m.normals = vec![[0.0, 0.0, 1.0]; 4];
        m.uvs = vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        m.primitives = vec![Primitive { material: Some(0), ..Primitive::default() }];
        m.gltf_materials = quad([[0.0; 2]; 4]).gltf_materials;
        assert_eq!(add(&mut m), 1);
        let t = m.attributes.iter().find(|a| a.semantic == "TANGENT").unwrap();
        let (a, b) = (t.get(m.triangles[0][0] as usize), t.get(m.triangles[1][1] as usize));
        assert!(a[0] > 0.99 && b[0] < -0.99, "{a:?} {b:?}");
        assert!(m.positions.len() > 4, "the shared vertices were split");
        for v in 4..m.positions.len() {
            let of = (0..4).find(|&w| m.positions[w] == m.positions[v]).unwrap();
            assert_eq!((m.normals[v], m.uvs[v]), (m.normals[of], m.uvs[of]));
        }
        assert!(m.check().is_ok());
    }
}
