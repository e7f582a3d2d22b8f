//! What an input holds that a [`Mesh`](super::Mesh) does not carry, so that no file written
//! from it has it either: a glTF scene's node hierarchy, animations, skins, extra vertex
//! attributes. These are not defects (unlike a [`Repair`](super::Repair), `--strict` does not
//! refuse them), but an artist converting a glTF has to be told what the output lost.

use std::fmt;

/// Kinds of input content a mesh does not carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum NotKeptKind {
    /// A glTF scene's node hierarchy: every mesh instance was baked into world space and
    /// merged into one mesh (count: mesh instances).
    FlattenedScene,
    /// glTF scenes besides the one read (count: scenes).
    OtherScenes,
    /// glTF animations (count: animations).
    Animations,
    /// glTF skins; vertices were read in their bind pose (count: skins).
    Skins,
    /// glTF morph targets; the base shape was read (count: primitives that have them).
    MorphTargets,
    /// Vertex attributes besides POSITION, NORMAL and TEXCOORD_0 (count: primitives that have
    /// them).
    OtherAttributes,
    /// glTF cameras (count: cameras).
    Cameras,
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
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Self::FlattenedScene => "node hierarchy flattened into one mesh in world space; mesh instances",
            Self::OtherScenes => "scenes besides the one read, not read",
            Self::Animations => "animations not kept",
            Self::Skins => "skins not kept (vertices read in bind pose)",
            Self::MorphTargets => "morph targets not kept (base shape read); primitives",
            Self::OtherAttributes => "vertex attributes besides POSITION, NORMAL, TEXCOORD_0 not kept; primitives",
            Self::Cameras => "cameras not kept",
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
