//! Error types. Every variant names what is wrong and where (file, face, corner, vertex), so
//! a user can find the defect in their own file.
//!
//! Errors only happen where input comes in: loading ([`LoadError`]) and building connectivity
//! ([`BuildError`]). A mesh that has been built is valid; later passes never fail.

use std::path::PathBuf;

use crate::mesh::Repair;
use crate::topology::TopologyError;

/// A defect in an indexed triangle mesh that cannot be mended without guessing.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No triangles (or no vertices) at all.
    #[error("the mesh has no triangles")]
    Empty,
    /// Vertices but no faces: a point cloud (CGAL's `points_3`, scanners' raw output).
    #[error("{vertices} vertices and no faces (a point cloud?): there is no surface to simplify")]
    NoFaces {
        /// Vertices the input holds.
        vertices: usize,
    },
    /// Every triangle was degenerate (repeated or coincident vertices) and was dropped.
    #[error("no triangles left: all {dropped} were degenerate (repeated or coincident vertices)")]
    AllDegenerate {
        /// Triangles dropped.
        dropped: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("face {face} corner {corner} refers to vertex {index}, but there are only {vertex_count} vertices")]
    IndexOutOfRange {
        /// Triangle index in the input order.
        face: usize,
        /// 0, 1 or 2.
        corner: usize,
        /// The offending index as it was read (may be negative in some formats).
        index: i64,
        /// Number of vertices available.
        vertex_count: usize,
    },
    /// A vertex position holds NaN or an infinity.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFiniteCoordinate {
        /// Vertex index in the input order.
        vertex: usize,
        /// The coordinates as read.
        x: f32,
        /// The coordinates as read.
        y: f32,
        /// The coordinates as read.
        z: f32,
    },
    /// The mesh's origin ([`crate::IndexedMesh::origin`]) holds NaN or an infinity.
    #[error("the mesh's origin has a non-finite coordinate {origin:?}")]
    NonFiniteOrigin {
        /// The origin as given.
        origin: [f64; 3],
    },
    /// An attribute array does not have one entry per vertex.
    #[error("attribute {attribute} has {len} entries but there are {vertex_count} vertices")]
    AttributeLength {
        /// "normal" or "uv".
        attribute: &'static str,
        /// Entries present.
        len: usize,
        /// Entries expected.
        vertex_count: usize,
    },
    /// A further vertex attribute is not one a mesh can carry: an unknown semantic, a
    /// component count its semantic does not allow, not one value set per vertex, or a
    /// semantic an earlier attribute already has.
    #[error("attribute {semantic}: {reason}")]
    BadAttribute {
        /// Its semantic as given (`COLOR_0`, ...).
        semantic: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The per-triangle primitive list does not have one entry per triangle.
    #[error("triangle_primitive has {len} entries but there are {triangle_count} triangles")]
    PrimitiveListLength {
        /// Entries present.
        len: usize,
        /// Triangles in the mesh.
        triangle_count: usize,
    },
    /// A triangle names a primitive the mesh does not have.
    #[error("face {face} belongs to primitive {primitive}, but there are only {primitive_count} primitives")]
    PrimitiveOutOfRange {
        /// Triangle index in the input order.
        face: usize,
        /// The primitive id it names.
        primitive: u32,
        /// Primitives available (an empty list counts as one).
        primitive_count: usize,
    },
    /// More vertices or triangles than u32 ids can address.
    #[error("{what} count {count} exceeds the u32 id range")]
    TooLarge {
        /// "vertex" or "triangle".
        what: &'static str,
        /// The count found.
        count: usize,
    },
}

/// What went wrong while reading a file, without the file name (see [`LoadError`]).
#[derive(Debug, thiserror::Error)]
pub enum LoadErrorKind {
    /// The file could not be read.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// Neither the extension nor the first bytes name a format we read.
    #[error("unknown mesh format (expected .obj, .ply, .off, .stl, .gltf or .glb, optionally .gz)")]
    UnknownFormat,
    /// The file does not follow its format.
    #[error("malformed {format}{}: {message}", line.map(|l| format!(" at line {l}")).unwrap_or_default())]
    Malformed {
        /// Format name.
        format: &'static str,
        /// 1-based line, where the format is line-based and the parser knows it.
        line: Option<usize>,
        /// What the parser found.
        message: String,
    },
    /// The file ends before the data its header promises.
    #[error("truncated {format}: {message}")]
    Truncated {
        /// Format name.
        format: &'static str,
        /// What was missing.
        message: String,
    },
    /// A glTF primitive uses a mode we cannot turn into triangles, and the file has no other.
    #[error("glTF mesh {mesh} primitive {primitive} uses mode {mode}; only triangle modes can be simplified")]
    UnsupportedPrimitiveMode {
        /// Mesh index in the glTF document.
        mesh: usize,
        /// Primitive index in that mesh.
        primitive: usize,
        /// The mode's name.
        mode: String,
    },
    /// A feature of the format we do not read (named in the message).
    #[error("unsupported {format} feature: {message}")]
    Unsupported {
        /// Format name.
        format: &'static str,
        /// What is not supported.
        message: String,
    },
    /// The file parsed, but the mesh in it is unusable.
    #[error("{0}")]
    Mesh(#[from] MeshError),
}

/// A file that could not be loaded: which file, and why.
#[derive(Debug, thiserror::Error)]
#[error("{}: {kind}", path.display())]
pub struct LoadError {
    /// The file (or a label for in-memory input).
    pub path: PathBuf,
    /// What went wrong.
    #[source]
    pub kind: LoadErrorKind,
}

impl LoadError {
    pub(crate) fn new(path: impl Into<PathBuf>, kind: impl Into<LoadErrorKind>) -> Self {
        Self { path: path.into(), kind: kind.into() }
    }
}

/// Why connectivity could not be built from an indexed mesh.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The indexed mesh itself is unusable.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// `strict` was set and the input needed this repair.
    #[error("strict mode: the input needs a repair: {0}")]
    RepairNeeded(Repair),
    /// The repaired mesh failed validation. This is a bug in dynlod; please report it with
    /// the input file.
    #[error("internal error, please report: repaired mesh is invalid: {0}")]
    Internal(#[from] TopologyError),
}

/// Anything that can go wrong between a path and a built mesh.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading the file failed.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// Building connectivity failed.
    #[error("{}: {source}", path.display())]
    Build {
        /// The file the mesh came from.
        path: PathBuf,
        /// Why.
        source: BuildError,
    },
}

/// Why [`simplify_scene`](crate::simplify::simplify_scene) could not simplify a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A mesh (or the scene baked into one mesh, which shares a triangle target out) could
    /// not be built.
    #[error("{mesh}: {source}")]
    Build {
        /// "mesh 2 (wheels)", or "the scene baked into one mesh".
        mesh: String,
        /// Why.
        source: BuildError,
    },
    /// The scene could not be baked into one mesh to share a triangle target out.
    #[error("the scene baked into one mesh: {0}")]
    Flatten(LoadErrorKind),
    /// A ratio outside 0 to 1.
    #[error("the ratio must be between 0 and 1, got {0}")]
    Ratio(f64),
}
