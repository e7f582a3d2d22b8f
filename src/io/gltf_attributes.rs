//! The further vertex attributes a glTF primitive may have and a mesh carries
//! ([`VertexAttribute`]): texture coordinate sets past the first (`TEXCOORD_1`, ... :
//! lightmaps, occlusion and detail maps), vertex colours (`COLOR_n`) and tangents
//! (`TANGENT`), glTF 2.0 §3.7.2.1. A flattening load carries no joints or weights (their
//! skins are not carried) nor application-specific `_NAME` attributes, whose component types
//! a FLOAT copy would change; a scene-keeping load (`gltf_scene`) carries them as they are
//! ([`verbatim`], [`read_values`]), with every morph target's attributes.
//!
//! Under a node's transform, tangents turn with the matrix and keep unit length; a mirroring
//! transform flips their handedness (w), since the bitangent a renderer rebuilds from the
//! transformed normal and tangent would otherwise point the wrong way. Untransformed values
//! stay bit-exact. A colour set that is RGB in some primitives and RGBA in others is kept as
//! RGBA, with an alpha of 1 where the source had none (what glTF means by RGB).

use glam::{Mat3, Mat4, Vec3};

use super::gltf_accessor::read;
use crate::mesh::VertexAttribute;

/// The name under which a scene-keeping load (`gltf_scene`) carries `semantic` as it is:
/// joints, weights and application-specific `_NAME` attributes, which no simplification
/// interpolates (a half-edge collapse keeps its survivor's values).
pub(super) fn verbatim(semantic: &gltf::Semantic) -> Option<String> {
    match semantic {
        gltf::Semantic::Joints(_) | gltf::Semantic::Weights(_) | gltf::Semantic::Extras(_) => {
            Some(semantic.to_string())
        }
        _ => None,
    }
}

/// The values of an attribute of `n` vertices (checked by `unreadable` first), as many
/// components as its accessor has (one to four); `None` when they cannot be read or are not
/// `n`. Attributes carried as they are ([`verbatim`], morph targets) are read this way.
pub(super) fn read_values(
    name: &str,
    accessor: gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
    n: usize,
) -> Option<VertexAttribute> {
    use gltf::accessor::Dimensions as D;
    let (components, values) = match accessor.dimensions() {
        D::Scalar => (1, super::gltf_accessor::read_scalars(accessor, buffers).filter(|v| v.len() == n)?),
        D::Vec2 => (2, read::<2>(accessor, buffers).filter(|v| v.len() == n)?.concat()),
        D::Vec3 => (3, read::<3>(accessor, buffers).filter(|v| v.len() == n)?.concat()),
        D::Vec4 => (4, read::<4>(accessor, buffers).filter(|v| v.len() == n)?.concat()),
        _ => return None,
    };
    Some(VertexAttribute::new(name, components, values))
}

/// The name under which a mesh carries `semantic`, if it carries it as a further attribute.
pub(super) fn carried(semantic: &gltf::Semantic) -> Option<String> {
    match semantic {
        gltf::Semantic::TexCoords(n) if *n > 0 => Some(format!("TEXCOORD_{n}")),
        gltf::Semantic::Colors(n) => Some(format!("COLOR_{n}")),
        gltf::Semantic::Tangents => Some("TANGENT".into()),
        _ => None,
    }
}

/// The values of one further attribute of `n` vertices (checked by `unreadable` first:
/// TEXCOORD_n of 2 components, COLOR_n of 3 or 4, TANGENT of 4), under `world`; `None` when
/// they cannot be read or are not `n`.
pub(super) fn read_attribute(
    name: &str,
    accessor: gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
    world: Mat4,
    n: usize,
) -> Option<VertexAttribute> {
    let mut a = read_values(name, accessor, buffers, n)?;
    // As normals: a translation alone leaves tangents bit-exact.
    if name == "TANGENT" && Mat3::from_mat4(world) != Mat3::IDENTITY {
        transform_tangents(&mut a.values, world);
    }
    Some(a)
}

/// Tangents (xyzw) under `world`: xyz by its linear part, renormalised, w flipped by a mirror.
pub(crate) fn transform_tangents(tangents: &mut [f32], world: Mat4) {
    let m = Mat3::from_mat4(world);
    let handedness = if m.determinant() < 0.0 { -1.0 } else { 1.0 };
    for t in tangents.chunks_exact_mut(4) {
        let [x, y, z] = (m * Vec3::new(t[0], t[1], t[2])).normalize_or_zero().to_array();
        t.copy_from_slice(&[x, y, z, t[3] * handedness]);
    }
}

/// Appends a block of `n` vertices from `base` to the mesh's further attributes: the block's
/// own values where it has the attribute, zeros where it does not. An attribute seen for the
/// first time gets zeros for the `base` vertices before it; RGB and RGBA colours of one set
/// become RGBA.
pub(super) fn append(all: &mut Vec<VertexAttribute>, block: Vec<VertexAttribute>, base: usize, n: usize) {
    for mut a in block {
        let at = match all.iter().position(|x| x.semantic == a.semantic) {
            Some(at) => at,
            None => {
                all.push(VertexAttribute::zeros(a.semantic.clone(), a.components, base));
                all.len() - 1
            }
        };
        let into = &mut all[at];
        if into.components == 3 && a.components == 4 {
            into.values = to_rgba(&into.values);
            into.components = 4;
        } else if into.components == 4 && a.components == 3 {
            a.values = to_rgba(&a.values);
        }
        into.values.extend(a.values);
    }
    for a in all.iter_mut() {
        a.values.resize(a.components * (base + n), 0.0);
    }
}

fn to_rgba(rgb: &[f32]) -> Vec<f32> {
    rgb.chunks_exact(3).flat_map(|c| [c[0], c[1], c[2], 1.0]).collect()
}

/// Marks, in each attribute, the primitives that lack it (`has[p]`: the semantics primitive
/// `p` was read with).
pub(super) fn mark_absent(all: &mut [VertexAttribute], has: &[Vec<String>]) {
    for a in all {
        a.absent = (0..has.len() as u32).filter(|&p| !has[p as usize].contains(&a.semantic)).collect();
    }
}
