//! What an input holds that a [`Mesh`](super::Mesh) does not carry, so that no file written
//! from it has it either: a glTF scene's node hierarchy, animations and skins; per-vertex
//! properties besides positions, normals, texture coordinates, colours and tangents (a
//! scan's confidence, a glTF's joints); face colours; PLY elements besides faces; an OBJ's
//! material libraries. These are not defects (unlike a [`Repair`](super::Repair),
//! `--strict` does not refuse them), but whoever simplifies a scan or an animated glTF has to
//! be told what the output lost. (What an output *format* cannot hold is
//! [`crate::io::not_written`].) [`crate::io::GltfScene`] keeps a glTF's scene, skins,
//! animations, morph targets, joints and weights where a GLB is written from it.

use std::fmt;

/// Kinds of input content a mesh does not carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum NotKeptKind {
    /// A glTF scene's node hierarchy: every mesh instance (a node drawing a mesh, or one of
    /// a node's `EXT_mesh_gpu_instancing` instances) was baked into world space and merged
    /// into one mesh (count: mesh instances).
    FlattenedScene,
    /// glTF scenes besides the one read (count: scenes).
    OtherScenes,
    /// glTF animations (count: animations).
    Animations,
    /// glTF skins; vertices were read in their bind pose (count: skins).
    Skins,
    /// glTF morph targets; the base shape was read (count: primitives that have them).
    MorphTargets,
    /// Vertex attributes a mesh does not carry (glTF: joints and weights, whose skins are
    /// not kept, and any it cannot read; PLY: properties besides positions, normals, texture
    /// coordinates and colours; OFF: face colours) and face attributes (PLY and OFF face
    /// colours) (count: primitives that have them, 1 for a single-primitive file; detail:
    /// names).
    OtherAttributes,
    /// glTF cameras (count: cameras).
    Cameras,
    /// Material libraries an OBJ names (`mtllib`) that could not be read: not found beside
    /// it, or the file was read from memory (count: libraries; detail: names).
    Materials,
    /// What an OBJ's materials hold that glTF materials do not carry: maps other than
    /// `map_Kd`, and textures not found or not PNG or JPEG (count: maps; detail: which).
    MaterialMaps,
    /// PLY elements besides vertex, face and tristrips (count: elements; detail: names).
    OtherElements,
    /// OBJ free-form geometry, which is not tessellated: curves and surfaces (`curv`,
    /// `curv2`, `surf`; count: statements; detail: which keywords).
    FreeFormGeometry,
    /// glTF extensions the source uses that the mesh neither decodes nor carries in its
    /// materials: lights, material variants (count: extensions; detail: names). Compression
    /// (Draco, meshopt) is decoded, or its fallback read, and `EXT_mesh_gpu_instancing` is
    /// read (each instance drawn, and counted in [`NotKeptKind::FlattenedScene`]).
    Extensions,
}

impl NotKeptKind {
    /// A stable snake_case name (used in JSON).
    pub fn name(self) -> &'static str {
        match self {
            Self::FlattenedScene => "flattened_scene",
            Self::OtherScenes => "other_scenes",
            Self::Animations => "animations",
            Self::Skins => "skins",
            Self::MorphTargets => "morph_targets",
            Self::OtherAttributes => "other_attributes",
            Self::Cameras => "cameras",
            Self::Materials => "materials",
            Self::MaterialMaps => "material_maps",
            Self::OtherElements => "other_elements",
            Self::FreeFormGeometry => "free_form_geometry",
            Self::Extensions => "extensions",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Self::FlattenedScene => "node hierarchy flattened into one mesh in world space; mesh instances",
            Self::OtherScenes => "scenes besides the one read, not read",
            Self::Animations => "animations not kept",
            Self::Skins => "skins not kept (vertices read in bind pose)",
            Self::MorphTargets => "morph targets not kept (base shape read); primitives",
            Self::OtherAttributes => "vertex or face attributes not kept; primitives",
            Self::Cameras => "cameras not kept",
            Self::Materials => "material libraries (mtllib) not read",
            Self::MaterialMaps => "material maps not carried",
            Self::OtherElements => "PLY elements besides vertex, face and tristrips not kept",
            Self::FreeFormGeometry => "free-form curves and surfaces not tessellated; statements",
            Self::Extensions => "glTF extensions not kept",
        }
    }
}

/// One kind of input content not carried: how much, and which (names, for attributes).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotKept {
    /// What was not carried.
    pub kind: NotKeptKind,
    /// How many (see each [`NotKeptKind`] for what is counted).
    pub count: usize,
    /// Which, where that helps: attribute names, meshes drawn more than once. May be empty.
    pub detail: String,
}

impl NotKept {
    /// `count` of `kind`, with `detail`.
    pub fn new(kind: NotKeptKind, count: usize, detail: impl Into<String>) -> Self {
        Self { kind, count, detail: detail.into() }
    }
}

impl fmt::Display for NotKept {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.kind.describe(), self.count)?;
        if !self.detail.is_empty() {
            write!(f, " ({})", self.detail)?;
        }
        Ok(())
    }
}
