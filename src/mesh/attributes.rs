//! Vertex attributes besides the position, the normal and the first texture coordinates:
//! further texture coordinate sets (lightmaps, detail maps), vertex colours (painted game
//! assets, coloured scans) and tangents (normal-mapped assets). They are named by their glTF
//! semantic (`TEXCOORD_1`, `COLOR_0`, `TANGENT`) whatever format they came from, and held as
//! `f32`, colours in 0–1.
//!
//! Nothing in the simplifier or the runtime reads their values: a half-edge collapse keeps
//! one of its two vertices, so every corner that survives keeps a wedge of the input, and an
//! attribute only has to take part in telling wedges apart (a colour or lightmap seam is a
//! seam like any other: [`super::Wedges`]).

/// One per-vertex attribute of an [`IndexedMesh`](super::IndexedMesh) (values per input
/// vertex) or of [`Wedges`](super::Wedges) (values per wedge).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VertexAttribute {
    /// The glTF semantic: `TEXCOORD_n` for n ≥ 1, `COLOR_n`, `TANGENT`.
    pub semantic: String,
    /// Components per vertex, 1 to 4 (colours 3 or 4, tangents 4 with the handedness last).
    pub components: usize,
    /// `components` values per vertex.
    pub values: Vec<f32>,
    /// Primitives whose source lacked the attribute: their vertices hold zeros, and writers
    /// leave it out of them as the source did (sorted).
    pub absent: Vec<u32>,
}

impl VertexAttribute {
    /// An attribute present in every primitive.
    pub fn new(semantic: impl Into<String>, components: usize, values: Vec<f32>) -> Self {
        Self { semantic: semantic.into(), components, values, absent: Vec::new() }
    }

    /// An attribute over `count` vertices, all zero.
    pub fn zeros(semantic: impl Into<String>, components: usize, count: usize) -> Self {
        Self::new(semantic, components, vec![0.0; components * count])
    }

    /// The values of vertex (or wedge) `i`.
    pub fn get(&self, i: usize) -> &[f32] {
        &self.values[i * self.components..(i + 1) * self.components]
    }

    /// Number of vertices (or wedges) it has values for.
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.components).unwrap_or(0)
    }

    /// Whether it has values for none.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Whether primitive `p` has it.
    pub fn present_in(&self, p: u32) -> bool {
        self.absent.binary_search(&p).is_err()
    }

    /// Whether it is a vertex colour (`COLOR_n`).
    pub fn is_colour(&self) -> bool {
        self.semantic.starts_with("COLOR_")
    }

    /// How many leading components carry a value that varies over a face (what an
    /// attribute-weighted cost or an attribute error compares): all, but a tangent's xyz
    /// without its handedness, which is ±1 and a seam where it flips.
    pub fn varying_components(&self) -> usize {
        if self.semantic == "TANGENT" {
            self.components.min(3)
        } else {
            self.components
        }
    }

    /// The semantic under which a mesh carries morph target k's attribute S: `TARGETk:S`
    /// (a scene-keeping glTF load; [`crate::io::GltfScene`]).
    pub fn morph_target_semantic(k: usize, semantic: &str) -> String {
        format!("TARGET{k}:{semantic}")
    }

    /// (k, S) where this is morph target k's attribute S
    /// ([`VertexAttribute::morph_target_semantic`]).
    pub fn morph_target(&self) -> Option<(usize, &str)> {
        parse_morph_target(&self.semantic)
    }

    /// Whether its values mean something only beside the glTF scene they came from: joints
    /// and weights (a skin's), morph target deltas. A scene-keeping load carries them
    /// ([`crate::io::GltfScene`]); files written from the mesh alone leave them out.
    pub fn scene_only(&self) -> bool {
        self.semantic.starts_with("JOINTS_") || self.semantic.starts_with("WEIGHTS_") || self.morph_target().is_some()
    }

    /// Whether its semantic and component count are ones glTF 2.0 allows (§3.7.2.1):
    /// `TEXCOORD_n` (n ≥ 1; `TEXCOORD_0` is [`IndexedMesh::uvs`](super::IndexedMesh::uvs))
    /// of 2, `COLOR_n` of 3 or 4, `TANGENT` of 4, or an application-specific `_NAME` of 1
    /// to 4; otherwise why not.
    pub fn check_semantic(&self) -> Result<(), String> {
        let set = |prefix: &str| {
            self.semantic.strip_prefix(prefix).is_some_and(|n| {
                !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) && (n == "0" || !n.starts_with('0'))
            })
        };
        let allowed: &[usize] = if set("TEXCOORD_") && self.semantic != "TEXCOORD_0" {
            &[2]
        } else if set("COLOR_") {
            &[3, 4]
        } else if self.semantic == "TANGENT" {
            &[4]
        } else if self.semantic.len() > 1 && self.semantic.starts_with('_') {
            &[1, 2, 3, 4]
        } else if set("JOINTS_") || set("WEIGHTS_") {
            &[4]
        } else if self.morph_target().is_some() {
            &[1, 2, 3, 4]
        } else {
            return Err("not a semantic a mesh carries (TEXCOORD_1, TEXCOORD_2, ..., COLOR_n, TANGENT, _NAME, \
                        JOINTS_n, WEIGHTS_n or TARGETk:SEMANTIC)"
                .into());
        };
        match allowed.contains(&self.components) {
            true => Ok(()),
            false => Err(format!("{} components, where glTF allows {allowed:?}", self.components)),
        }
    }

    /// The same attribute with no values yet (room for `count` vertices).
    pub(crate) fn empty_like(&self, count: usize) -> Self {
        let values = Vec::with_capacity(self.components * count);
        Self { semantic: self.semantic.clone(), components: self.components, values, absent: self.absent.clone() }
    }

    /// The same attribute with the values of `order`'s vertices, in that order (sized
    /// exactly: the runtime's memory report counts capacity).
    pub(crate) fn gather(&self, order: &[u32]) -> Self {
        let mut values = Vec::with_capacity(order.len() * self.components);
        for &i in order {
            values.extend_from_slice(self.get(i as usize));
        }
        Self { semantic: self.semantic.clone(), components: self.components, values, absent: self.absent.clone() }
    }
}

/// (k, S) of a semantic `TARGETk:S` ([`VertexAttribute::morph_target_semantic`]).
pub(crate) fn parse_morph_target(semantic: &str) -> Option<(usize, &str)> {
    let (k, semantic) = semantic.strip_prefix("TARGET")?.split_once(':')?;
    let k = k.parse().ok().filter(|_| k.bytes().all(|b| b.is_ascii_digit()))?;
    (!semantic.is_empty()).then_some((k, semantic))
}

/// A class per input vertex such that two vertices share a class exactly when every one of
/// `attributes` holds the same bits at both (−0.0 and +0.0 apart, as for normals and UVs);
/// empty when there are no attributes. Classes follow first appearance.
pub(crate) fn classes(attributes: &[VertexAttribute], count: usize) -> Vec<u32> {
    if attributes.is_empty() {
        return Vec::new();
    }
    let width: usize = attributes.iter().map(|a| a.components).sum();
    let mut map: rustc_hash::FxHashMap<Box<[u32]>, u32> = Default::default();
    let mut key = Vec::with_capacity(width);
    (0..count)
        .map(|i| {
            key.clear();
            for a in attributes {
                key.extend(a.get(i).iter().map(|c| c.to_bits()));
            }
            if let Some(&class) = map.get(key.as_slice()) {
                return class;
            }
            let next = map.len() as u32;
            map.insert(key.as_slice().into(), next);
            next
        })
        .collect()
}
