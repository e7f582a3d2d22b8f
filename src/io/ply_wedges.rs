//! Texture coordinates per face corner, as MeshLab writes textured PLY (a `texcoord` list of
//! 2k floats beside each face's k indices, and a `texnumber` naming which of the header's
//! `comment TextureFile NAME` textures the face uses). The mesh holds one texture coordinate
//! per vertex, so a vertex whose corners disagree is split: its first texture coordinate
//! keeps the file's vertex (so vertex numbers in repairs stay the file's), every other one
//! gets a copy appended after the file's vertices. Welding joins the copies again by
//! position and keeps the seam on the wedges, as it does for OBJ. Faces are grouped into one
//! primitive per texture, named by its file, so an output keeps them apart; read from a file,
//! the textures beside it become the primitives' materials (`obj_materials.rs`).

use std::collections::HashMap;

use crate::mesh::{IndexedMesh, Primitive};

/// The vertices of a mesh read so far, split where their corners' texture coordinates
/// disagree.
pub(super) struct Wedges {
    /// Whether each file vertex has its texture coordinate (its first corner's) yet.
    seen: Vec<bool>,
    /// The copies made: (file vertex, texture coordinate bits) to vertex.
    copies: HashMap<(u32, [u32; 2]), u32>,
}

impl Wedges {
    /// For a mesh of `n` file vertices, with its `uvs` about to be set here.
    pub(super) fn new(out: &mut IndexedMesh) -> Self {
        let n = out.positions.len();
        out.uvs = vec![[0.0; 2]; n];
        Wedges { seen: vec![false; n], copies: HashMap::new() }
    }

    /// The vertex for file vertex `v` at texture coordinate `uv`: `v` itself, or a copy.
    pub(super) fn vertex(&mut self, out: &mut IndexedMesh, v: u32, uv: [f32; 2]) -> u32 {
        let (i, bits) = (v as usize, uv.map(f32::to_bits));
        if !self.seen[i] {
            self.seen[i] = true;
            out.uvs[i] = uv;
            return v;
        }
        match out.uvs[i].map(f32::to_bits) == bits {
            true => v,
            false => *self.copies.entry((v, bits)).or_insert_with(|| copy(out, v, uv)),
        }
    }
}

/// Appends a copy of vertex `v` (position, normal, every attribute) at texture coordinate
/// `uv`; its id.
fn copy(out: &mut IndexedMesh, v: u32, uv: [f32; 2]) -> u32 {
    let id = out.push_copy(v);
    out.uvs[id as usize] = uv;
    id
}

/// One primitive per texture number in `numbers` (each triangle's), named by the header's
/// `TextureFile` comments, with `out.triangle_primitive` set to match. Texture numbers are
/// kept in order, so primitive k is the k-th texture the faces use.
pub(super) fn primitives(out: &mut IndexedMesh, numbers: &[i64], textures: &[String]) {
    let mut used: Vec<i64> = numbers.to_vec();
    used.sort_unstable();
    used.dedup();
    let name = |t: i64| usize::try_from(t).ok().and_then(|t| textures.get(t)).cloned();
    out.primitives = used
        .iter()
        .map(|&t| Primitive { name: name(t).unwrap_or_else(|| format!("texture {t}")), ..Primitive::default() })
        .collect();
    out.triangle_primitive = numbers.iter().map(|t| used.binary_search(t).expect("a used number") as u32).collect();
    if out.primitives.len() <= 1 {
        out.triangle_primitive.clear();
    }
}
