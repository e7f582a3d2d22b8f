//! The `dynlod info` report: what a mesh file holds and what was repaired, as text or JSON.

use serde_json::{json, Value};

use crate::mesh::Mesh;

/// Everything `dynlod info` prints.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshInfo {
    /// Vertex records in the file.
    pub input_vertices: usize,
    /// Triangles in the file (polygons fan-split).
    pub input_triangles: usize,
    /// Topological vertices after welding and repair.
    pub vertices: usize,
    /// Triangles after repair.
    pub triangles: usize,
    /// Undirected edges.
    pub edges: usize,
    /// Attribute wedges (distinct vertex + normal + UV + further attributes).
    pub wedges: usize,
    /// The vertex attributes carried besides POSITION, by glTF semantic (`NORMAL`,
    /// `TEXCOORD_0`, `COLOR_0`, ...), with their component counts.
    pub attributes: Vec<(String, usize)>,
    /// Edges across which a normal or UV changes.
    pub seam_edges: usize,
    /// Connected components.
    pub components: usize,
    /// Edges with one face.
    pub boundary_edges: usize,
    /// Closed border loops.
    pub boundary_loops: usize,
    /// Edges with more than two faces in the input.
    pub non_manifold_edges: usize,
    /// Pinched vertices split in the input.
    pub non_manifold_vertices: usize,
    /// Zero-area triangles with distinct vertices.
    pub zero_area_triangles: usize,
    /// V − E + F.
    pub euler: i64,
    /// Sum of component genera.
    pub genus: Option<u32>,
    /// Bounding box corners, relative to `origin`.
    pub bbox_min: [f32; 3],
    /// Bounding box corners.
    pub bbox_max: [f32; 3],
    /// Where the positions' zero lies in the file's coordinates: zero unless the file lies
    /// far from its own origin ([`crate::IndexedMesh::origin`]).
    pub origin: [f64; 3],
    /// Primitives (glTF primitives, OBJ objects).
    pub primitives: usize,
    /// Repairs, one line each.
    pub repairs: Vec<crate::Repair>,
    /// What the input holds that the mesh does not carry (a glTF's node hierarchy, animations).
    pub not_kept: Vec<crate::mesh::NotKept>,
    /// `Ok` or the first violated invariant.
    pub validation: Result<(), crate::topology::TopologyError>,
}

/// The attributes a mesh carries besides its positions, with their component counts.
fn attributes(mesh: &Mesh) -> Vec<(String, usize)> {
    let w = &mesh.wedges;
    let mut out = Vec::new();
    if !w.normals.is_empty() {
        out.push(("NORMAL".to_string(), 3));
    }
    if !w.uvs.is_empty() {
        out.push(("TEXCOORD_0".to_string(), 2));
    }
    out.extend(w.attributes.iter().map(|a| (a.semantic.clone(), a.components)));
    out
}

impl MeshInfo {
    /// Collects the report for a built mesh (runs [`crate::topology::Topology::validate`]).
    pub fn new(mesh: &Mesh) -> Self {
        let s = mesh.topology.stats();
        let (bbox_min, bbox_max) = mesh.bounds();
        Self {
            input_vertices: mesh.input_vertices,
            input_triangles: mesh.input_triangles,
            vertices: s.vertices as usize,
            triangles: s.faces as usize,
            edges: s.edges as usize,
            wedges: mesh.wedges.len(),
            attributes: attributes(mesh),
            seam_edges: mesh.seam_edges(),
            components: s.components.len(),
            boundary_edges: s.boundary_edges as usize,
            boundary_loops: s.boundary_loops as usize,
            non_manifold_edges: mesh.defects.non_manifold_edges,
            non_manifold_vertices: mesh.defects.non_manifold_vertices,
            zero_area_triangles: mesh.defects.zero_area_triangles,
            euler: s.euler,
            genus: s.genus,
            bbox_min,
            bbox_max,
            origin: mesh.origin,
            primitives: mesh.primitives.len(),
            repairs: mesh.repairs.clone(),
            not_kept: mesh.not_kept.clone(),
            validation: mesh.topology.validate(),
        }
    }

    /// One JSON object (keys documented in the README).
    pub fn to_json(&self, file: &str) -> Value {
        json!({
            "file": file,
            "input_vertices": self.input_vertices,
            "input_triangles": self.input_triangles,
            "vertices": self.vertices,
            "triangles": self.triangles,
            "edges": self.edges,
            "wedges": self.wedges,
            "attributes": self.attributes.iter().map(|(s, c)| json!({"semantic": s, "components": c})).collect::<Vec<_>>(),
            "seam_edges": self.seam_edges,
            "components": self.components,
            "boundary_edges": self.boundary_edges,
            "boundary_loops": self.boundary_loops,
            "non_manifold_edges": self.non_manifold_edges,
            "non_manifold_vertices": self.non_manifold_vertices,
            "zero_area_triangles": self.zero_area_triangles,
            "euler_characteristic": self.euler,
            "genus": self.genus,
            "bbox_min": self.in_file(self.bbox_min),
            "bbox_max": self.in_file(self.bbox_max),
            "origin": self.origin,
            "primitives": self.primitives,
            "valid": self.validation.is_ok(),
            "validation_error": self.validation.as_ref().err().map(|e| e.to_string()),
            "repairs": repairs_json(&self.repairs),
            "not_kept": not_kept_json(&self.not_kept),
        })
    }

    /// A corner relative to the origin, in the file's coordinates.
    fn in_file(&self, c: [f32; 3]) -> [f64; 3] {
        std::array::from_fn(|k| self.origin[k] + f64::from(c[k]))
    }

    /// Human-readable multi-line report.
    pub fn to_text(&self, file: &str) -> String {
        let mut s = String::new();
        let mut line = |k: &str, v: String| s.push_str(&format!("{k:<22} {v}\n"));
        line("file", file.to_string());
        line("vertices", format!("{} (input {})", self.vertices, self.input_vertices));
        line("triangles", format!("{} (input {})", self.triangles, self.input_triangles));
        line("edges", self.edges.to_string());
        let names: Vec<String> = self.attributes.iter().map(|(s, c)| format!("{s} ({c})")).collect();
        line("attributes", if names.is_empty() { "position only".into() } else { names.join(", ") });
        line("attribute wedges", format!("{} ({} seam edges)", self.wedges, self.seam_edges));
        line("components", self.components.to_string());
        line("boundary", format!("{} edges in {} loops", self.boundary_edges, self.boundary_loops));
        line(
            "non-manifold in input",
            format!("{} edges, {} vertices", self.non_manifold_edges, self.non_manifold_vertices),
        );
        line("zero-area triangles", self.zero_area_triangles.to_string());
        line("euler characteristic", self.euler.to_string());
        line("genus", self.genus.map_or("undefined".into(), |g| g.to_string()));
        if self.origin == [0.0; 3] {
            line("bounding box", format!("{:?} .. {:?}", self.bbox_min, self.bbox_max));
        } else {
            let corner = |c: [f32; 3]| {
                let [x, y, z] = [0, 1, 2].map(|k| crate::mesh::origin::InFile(self.origin[k], c[k]));
                format!("[{x}, {y}, {z}]")
            };
            line("bounding box", format!("{} .. {}", corner(self.bbox_min), corner(self.bbox_max)));
            line(
                "origin",
                format!(
                    "{:?} (far from the file's own: positions are kept relative to it, and added back on writing)",
                    self.origin
                ),
            );
        }
        line("primitives", self.primitives.to_string());
        line("valid", self.validation.as_ref().map_or_else(|e| format!("NO: {e}"), |_| "yes".into()));
        if self.repairs.is_empty() {
            line("repairs", "none".into());
        } else {
            line("repairs", String::new());
            for r in &self.repairs {
                s.push_str(&format!("  - {r}\n"));
            }
        }
        if !self.not_kept.is_empty() {
            s.push_str(&format!("{:<22}\n", "not kept"));
            for n in &self.not_kept {
                s.push_str(&format!("  - {n}\n"));
            }
        }
        s
    }
}

/// [`NotKept`](crate::mesh::NotKept) entries as JSON objects (`kind`, `count`, `detail`,
/// `message`), for every command's `--json`.
pub fn not_kept_json(list: &[crate::mesh::NotKept]) -> Value {
    Value::Array(
        list.iter()
            .map(|n| json!({ "kind": n.kind.name(), "count": n.count, "detail": n.detail, "message": n.to_string() }))
            .collect(),
    )
}

/// [`Repair`](crate::Repair) entries as JSON objects (`kind`, `count`, `examples`, `message`).
pub fn repairs_json(list: &[crate::Repair]) -> Value {
    Value::Array(
        list.iter()
            .map(|r| {
                json!({
                    "kind": r.kind.name(),
                    "count": r.count,
                    "examples": r.examples.iter().map(|l| l.to_string()).collect::<Vec<_>>(),
                    "message": r.to_string(),
                })
            })
            .collect(),
    )
}
