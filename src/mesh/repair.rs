//! The record of what was mended in an input: each [`Repair`] says what kind of defect, how
//! many, and where (a few example ids in the file's own numbering), so a user sees exactly
//! what changed. `--strict` turns the first one into an error instead.

use std::fmt;

/// Where a repair happened, in the numbering of the input file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// An input triangle (after polygon triangulation, in file order); for the kinds about
    /// polygons, a face of the file as written.
    Face(u32),
    /// An input vertex (file order).
    Vertex(u32),
    /// An edge, as two input vertex ids.
    Edge(u32, u32),
    /// A line of a text file (from 1), for what has no number in its file: an OBJ's points,
    /// lines and polygons, a PLY's header lines.
    Line(u32),
    /// A glTF mesh's primitive.
    Primitive {
        /// Mesh index.
        mesh: u32,
        /// Primitive index within it.
        primitive: u32,
    },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Face(i) => write!(f, "face {i}"),
            Location::Vertex(i) => write!(f, "vertex {i}"),
            Location::Edge(a, b) => write!(f, "edge {a}-{b}"),
            Location::Line(i) => write!(f, "line {i}"),
            Location::Primitive { mesh, primitive } => {
                write!(f, "mesh {mesh} primitive {primitive}")
            }
        }
    }
}

/// The kinds of defect that are mended without guessing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RepairKind {
    /// glTF primitives of point or line modes, or file faces with fewer than three vertices,
    /// were skipped (they are not surfaces), and glTF primitives without POSITION (which
    /// glTF 2.0 allows); so were the one or two indices a glTF triangle list's count leaves
    /// over (location: its primitive).
    SkippedNonTrianglePrimitives,
    /// PLY header lines that are no keyword (Blender 2.4x's bare credit line) or blank were
    /// read as comments (locations: their lines).
    CommentedHeaderLines,
    /// An ascii PLY's elements that spread over lines, or shared one, were read as a stream
    /// of words, as rply and MeshLab read them (locations: the lines where such elements
    /// start).
    RewrappedAsciiElements,
    /// Words past an ascii PLY element's last property on its line, or lines past the last
    /// element, were passed over, as Turk's `ply.c` and ply-rs read them (locations: their
    /// lines; where the words fit the header read as a stream, they are read that way
    /// instead, as [`RepairKind::RewrappedAsciiElements`]).
    IgnoredExtraWords,
    /// Polygon faces (OBJ, PLY, OFF) that cross themselves in their plane, so that no
    /// triangulation of their corners covers them without folding, were fanned from their
    /// first corner (locations: the file's faces, in file order; for OBJ, which numbers its
    /// faces nowhere, their lines).
    FannedSelfCrossingPolygons,
    /// Normals or texture coordinates holding NaN/inf were set to zero.
    ZeroedNonFiniteAttributes,
    /// A glTF primitive's normals or texture coordinates could not be read as what they
    /// claim to be (an accessor of the wrong type, a count other than the positions', a
    /// stride shorter than an element) and were left out of it, as if it had none.
    DroppedUnreadableAttributes,
    /// glTF primitives whose POSITION accessor lacks the `min` and `max` glTF 2.0 requires
    /// (or holds them as something other than three numbers) were read anyway: the bounds
    /// are taken from the positions, and a GLB output writes its own.
    RecomputedPositionBounds,
    /// Triangles naming the same (welded) vertex twice were dropped.
    DroppedDegenerateFaces,
    /// Triangles over the same three vertices as an earlier one (either winding) were dropped.
    DroppedDuplicateFaces,
    /// Faces were flipped so that each component is consistently oriented (the majority
    /// winding of the component is kept).
    ReorientedFaces,
    /// Edges shared by more than two faces were cut apart (faces paired in file order,
    /// opposite windings first; the rest became border).
    CutNonManifoldEdges,
    /// Edges where no consistent orientation exists (Möbius-like) were cut apart.
    CutNonOrientableEdges,
    /// Pinched vertices (several separate fans) were split, one vertex per fan.
    SplitNonManifoldVertices,
    /// Faces that could not be attached manifoldly were detached onto their own vertices.
    DetachedFaces,
    /// Vertices used by no remaining face were dropped.
    DroppedUnreferencedVertices,
    /// Triangles of zero area were dropped (only with `drop_zero_area`).
    DroppedZeroAreaFaces,
}

impl RepairKind {
    /// A stable snake_case name (used in JSON).
    pub fn name(self) -> &'static str {
        match self {
            Self::SkippedNonTrianglePrimitives => "skipped_non_triangle_primitives",
            Self::CommentedHeaderLines => "commented_header_lines",
            Self::RewrappedAsciiElements => "rewrapped_ascii_elements",
            Self::IgnoredExtraWords => "ignored_extra_words",
            Self::FannedSelfCrossingPolygons => "fanned_self_crossing_polygons",
            Self::ZeroedNonFiniteAttributes => "zeroed_non_finite_attributes",
            Self::DroppedUnreadableAttributes => "dropped_unreadable_attributes",
            Self::RecomputedPositionBounds => "recomputed_position_bounds",
            Self::DroppedDegenerateFaces => "dropped_degenerate_faces",
            Self::DroppedDuplicateFaces => "dropped_duplicate_faces",
            Self::ReorientedFaces => "reoriented_faces",
            Self::CutNonManifoldEdges => "cut_non_manifold_edges",
            Self::CutNonOrientableEdges => "cut_non_orientable_edges",
            Self::SplitNonManifoldVertices => "split_non_manifold_vertices",
            Self::DetachedFaces => "detached_faces",
            Self::DroppedUnreferencedVertices => "dropped_unreferenced_vertices",
            Self::DroppedZeroAreaFaces => "dropped_zero_area_faces",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Self::SkippedNonTrianglePrimitives => "skipped point/line primitives or faces of fewer than 3 vertices",
            Self::CommentedHeaderLines => "read header lines that are no keyword, or blank, as comments",
            Self::RewrappedAsciiElements => "read ascii PLY elements over several lines, or sharing one, as words",
            Self::IgnoredExtraWords => "passed over words past an ascii PLY element's properties",
            Self::FannedSelfCrossingPolygons => {
                "fanned polygons that cross themselves (no triangulation covers them without folding)"
            }
            Self::ZeroedNonFiniteAttributes => "set non-finite normals/UVs to zero on vertices",
            Self::DroppedUnreadableAttributes => {
                "left out normals/UVs of the wrong type, count or stride from glTF primitives"
            }
            Self::RecomputedPositionBounds => {
                "read glTF primitives whose POSITION accessor lacks min/max (bounds taken from the positions)"
            }
            Self::DroppedDegenerateFaces => "dropped degenerate faces (a vertex repeated)",
            Self::DroppedDuplicateFaces => "dropped duplicate faces",
            Self::ReorientedFaces => "flipped faces to make winding consistent",
            Self::CutNonManifoldEdges => "cut apart non-manifold edges (more than two faces)",
            Self::CutNonOrientableEdges => "cut apart edges with no consistent orientation",
            Self::SplitNonManifoldVertices => "split non-manifold (pinched) vertices",
            Self::DetachedFaces => "detached faces that could not be attached manifoldly",
            Self::DroppedUnreferencedVertices => "dropped unreferenced vertices",
            Self::DroppedZeroAreaFaces => "dropped zero-area faces",
        }
    }
}

/// Examples kept per repair (the count is always exact).
pub const MAX_EXAMPLES: usize = 5;

/// One kind of repair applied to an input: how many, and the first few places.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Repair {
    /// What was mended.
    pub kind: RepairKind,
    /// How many elements (faces, vertices, edges) it touched.
    pub count: usize,
    /// Up to [`MAX_EXAMPLES`] of them, in input numbering.
    pub examples: Vec<Location>,
}

impl Repair {
    /// A repair of `kind` with no elements yet.
    pub fn new(kind: RepairKind) -> Self {
        Self { kind, count: 0, examples: Vec::new() }
    }

    /// Counts one more element, keeping it as an example while there is room.
    pub fn add(&mut self, at: Location) {
        self.count += 1;
        if self.examples.len() < MAX_EXAMPLES {
            self.examples.push(at);
        }
    }

    /// Pushes this repair onto `list` if it touched anything.
    pub fn push_into(self, list: &mut Vec<Repair>) {
        if self.count > 0 {
            list.push(self);
        }
    }
}

impl fmt::Display for Repair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.kind.describe(), self.count)?;
        if !self.examples.is_empty() {
            let ex: Vec<String> = self.examples.iter().map(|l| l.to_string()).collect();
            write!(f, " (e.g. {}{})", ex.join(", "), if self.count > self.examples.len() { ", …" } else { "" })?;
        }
        Ok(())
    }
}
