//! A level of detail of a whole glTF scene in one call ([`simplify_scene`]), as
//! `dynlod simplify IN.glb OUT.glb` makes it: each mesh definition simplified once, in its
//! own space, to a share of the scene's triangle target, then written back around the
//! scene's nodes, skins, animations, morph targets and materials by
//! [`GltfScene::save`](crate::io::GltfScene::save).
//!
//! The shares come from simplifying the scene baked into one mesh in world space first
//! ([`GltfScene::flattened`](crate::io::GltfScene::flattened), what `--flatten` writes) and
//! giving each mesh what that run left it, per node that draws it
//! ([`GltfScene::allot`](crate::io::GltfScene::allot)): one ratio for every mesh would take
//! as much from a bolt as from a flat panel, where this allots by error across the scene
//! (2CylinderEngine at 25 %: 0.031 % RMS against 0.104 % for one ratio per mesh,
//! docs/BENCHMARKS.md "Scene-keeping glTF").
//!
//! The engine is pluggable ([`SceneEngine`]): [`SimplifyOptions`] runs the offline methods;
//! the command line plugs papers/000's parallel rounds in the same way. Meshes run as
//! parallel tasks; each engine gives the same result on any thread count, so the scene does
//! too.

use rayon::prelude::*;

use super::{lock_vertices, simplify, SimplifyOptions, SimplifyStats};
use crate::error::SceneError;
use crate::io::{GltfScene, Placement};
use crate::mesh::{BuildOptions, IndexedMesh, Mesh};
use crate::topology::HalfEdges;

/// What cuts each mesh of a scene (and the scene baked into one mesh, to share a triangle
/// target out).
pub trait SceneEngine: Sync {
    /// What one run reports.
    type Stats: Send;

    /// Simplifies `mesh` to `target` triangles, or with `None` as far as the engine's own
    /// bound allows. `drawn` says where the scene draws it: a bound in distance (an error,
    /// in the scene's units) must be divided by its `scale`, and a camera in world space
    /// carried into the mesh's space through each of its `placements`.
    fn cut(&self, mesh: &mut Mesh, target: Option<usize>, drawn: &Drawn<'_>) -> Self::Stats;
}

/// Where the scene draws a mesh, for [`SceneEngine::cut`].
#[derive(Debug, Clone, Copy)]
pub struct Drawn<'a> {
    /// The mesh is drawn up to `scale` times larger than its own units
    /// ([`SceneMesh::scale`](crate::io::SceneMesh::scale); 1 for the baked scene).
    pub scale: f64,
    /// Each instance's node and world transform
    /// ([`SceneMesh::placements`](crate::io::SceneMesh::placements); the baked scene: once,
    /// where it is). Empty for a mesh no node draws.
    pub placements: &'a [Placement],
}

/// The baked scene's placement: in world space already.
const IN_WORLD: [Placement; 1] = [Placement {
    node: None,
    instance: None,
    world: [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]],
}];

/// The offline methods: [`SimplifyOptions::max_error`] is in the scene's units, and its
/// `target_triangles` is replaced by each mesh's share.
impl SceneEngine for SimplifyOptions {
    type Stats = SimplifyStats;

    fn cut(&self, mesh: &mut Mesh, target: Option<usize>, drawn: &Drawn<'_>) -> SimplifyStats {
        simplify(mesh, self.target_triangles(target.unwrap_or(0)).max_error(self.max_error / drawn.scale))
    }
}

/// How many triangles the scene should draw after [`simplify_scene`]. Counts are of drawn
/// triangles: a mesh two nodes draw counts twice, as in the scene baked into one mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SceneTarget {
    /// No count: each mesh goes as far as the engine's own bound allows (an error bound).
    Bound,
    /// This fraction (0 to 1) of the triangles drawn.
    Ratio(f64),
    /// This many triangles drawn.
    Triangles(usize),
}

/// Options of [`simplify_scene`] besides the engine's own.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct SceneOptions {
    /// The triangle target. Default: [`SceneTarget::Bound`].
    pub target: SceneTarget,
    /// How each mesh (and the baked scene) is built. Default: [`BuildOptions::default`].
    pub build: BuildOptions,
    /// Keep every border vertex where it is ([`lock_border`]). Default: false.
    pub lock_border: bool,
}

impl Default for SceneOptions {
    fn default() -> Self {
        Self { target: SceneTarget::Bound, build: BuildOptions::default(), lock_border: false }
    }
}

impl SceneOptions {
    /// Sets [`SceneOptions::target`].
    pub fn target(mut self, t: SceneTarget) -> Self {
        self.target = t;
        self
    }
    /// Sets [`SceneOptions::build`].
    pub fn build(mut self, b: BuildOptions) -> Self {
        self.build = b;
        self
    }
    /// Sets [`SceneOptions::lock_border`].
    pub fn lock_border(mut self, on: bool) -> Self {
        self.lock_border = on;
        self
    }
}

/// A scene's meshes simplified: [`SceneLod::meshes`] go to
/// [`GltfScene::save`](crate::io::GltfScene::save) as they are.
#[derive(Debug, Clone)]
pub struct SceneLod<S> {
    /// The simplified meshes, in the order of [`GltfScene::meshes`].
    pub meshes: Vec<IndexedMesh>,
    /// What happened to each, in the same order.
    pub reports: Vec<SceneMeshReport<S>>,
    /// What was repaired or could not be kept on load, per mesh ("mesh 2 (wheels): ...").
    pub notes: Vec<String>,
}

/// One mesh's run in a [`SceneLod`].
#[derive(Debug, Clone)]
pub struct SceneMeshReport<S> {
    /// Nodes that draw it ([`SceneMesh::instances`](crate::io::SceneMesh::instances)).
    pub instances: usize,
    /// Its triangles before, once.
    pub input_triangles: usize,
    /// Its triangles after, once.
    pub output_triangles: usize,
    /// Its share of the target, once; `None` under [`SceneTarget::Bound`].
    pub target: Option<usize>,
    /// What its engine reported.
    pub stats: S,
}

impl<S> SceneLod<S> {
    /// Triangles the source scene draws (each mesh times the nodes that draw it).
    pub fn drawn_input_triangles(&self) -> usize {
        self.reports.iter().map(|r| r.input_triangles * r.instances).sum()
    }
    /// Triangles the simplified scene draws.
    pub fn drawn_output_triangles(&self) -> usize {
        self.reports.iter().map(|r| r.output_triangles * r.instances).sum()
    }
}

/// Keeps every border vertex of `mesh` where it is (see [`lock_vertices`]).
pub fn lock_border(mesh: &mut Mesh) {
    let border: Vec<u32> = (0..mesh.positions.len() as u32).filter(|&v| mesh.topology.is_boundary_vertex(v)).collect();
    lock_vertices(mesh, border);
}

/// Simplifies every mesh definition of `scene` through `engine` (see the module docs).
///
/// ```no_run
/// use dynlod::io::GltfScene;
/// use dynlod::simplify::{simplify_scene, Method, SceneOptions, SceneTarget, SimplifyOptions};
///
/// let scene = GltfScene::load("truck.glb")?;
/// let engine = SimplifyOptions::default().method(Method::Qem);
/// let lod = simplify_scene(&scene, &engine, SceneOptions::default().target(SceneTarget::Ratio(0.25)))?;
/// for note in scene.save("truck_lod1.glb", &lod.meshes)? {
///     eprintln!("{note}");
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn simplify_scene<E: SceneEngine>(
    scene: &GltfScene,
    engine: &E,
    options: SceneOptions,
) -> Result<SceneLod<E::Stats>, SceneError> {
    if let SceneTarget::Ratio(r) = options.target {
        if !(0.0..=1.0).contains(&r) {
            return Err(SceneError::Ratio(r));
        }
    }
    let mut notes = Vec::new();
    let mut meshes = Vec::with_capacity(scene.meshes.len());
    for sm in &scene.meshes {
        let label = sm.label();
        let mut mesh =
            Mesh::build(&sm.mesh, options.build).map_err(|source| SceneError::Build { mesh: label.clone(), source })?;
        notes.extend(mesh.repairs.iter().map(|r| format!("{label}: repaired on load: {r}")));
        notes.extend(mesh.not_kept.iter().map(|n| format!("{label}: {n}")));
        if options.lock_border {
            lock_border(&mut mesh);
        }
        meshes.push(mesh);
    }
    let inputs: Vec<usize> = meshes.iter().map(|m| m.topology.live_face_count()).collect();
    let targets = targets(scene, engine, &options, &inputs)?;
    let (meshes, reports) = meshes
        .into_par_iter()
        .zip(targets.into_par_iter().zip(inputs).zip(&scene.meshes))
        .map(|(mut mesh, ((target, input), sm))| {
            let drawn = Drawn { scale: f64::from(sm.scale), placements: &sm.placements };
            let stats = engine.cut(&mut mesh, target, &drawn);
            let output = mesh.topology.live_face_count();
            let report = SceneMeshReport {
                instances: sm.instances,
                input_triangles: input,
                output_triangles: output,
                target,
                stats,
            };
            (mesh.to_indexed(), report)
        })
        .unzip();
    Ok(SceneLod { meshes, reports, notes })
}

/// Each mesh's target (see the module docs). A mesh the scene does not draw keeps the plain
/// ratio; so does every mesh where only one is drawn, or nothing is to go.
fn targets<E: SceneEngine>(
    scene: &GltfScene,
    engine: &E,
    options: &SceneOptions,
    inputs: &[usize],
) -> Result<Vec<Option<usize>>, SceneError> {
    let drawn: usize = inputs.iter().zip(&scene.meshes).map(|(&n, sm)| n * sm.instances).sum();
    let ratio = match options.target {
        SceneTarget::Bound => return Ok(vec![None; inputs.len()]),
        SceneTarget::Ratio(r) => r,
        SceneTarget::Triangles(n) => n as f64 / drawn.max(1) as f64,
    };
    let plain = |n: usize| Some(((n as f64 * ratio).round() as usize).min(n));
    if scene.meshes.iter().filter(|sm| sm.instances > 0).count() <= 1 || ratio >= 1.0 {
        return Ok(inputs.iter().map(|&n| plain(n)).collect());
    }
    const BAKED: &str = "the scene baked into one mesh";
    let flat = scene.flattened().map_err(SceneError::Flatten)?;
    let mut flat =
        Mesh::build(&flat, options.build).map_err(|source| SceneError::Build { mesh: BAKED.into(), source })?;
    if options.lock_border {
        lock_border(&mut flat);
    }
    let target = (flat.topology.live_face_count() as f64 * ratio).round() as usize;
    engine.cut(&mut flat, Some(target), &Drawn { scale: 1.0, placements: &IN_WORLD });
    Ok(scene.allot(&flat).into_iter().zip(inputs).map(|(t, &n)| t.map(|t| t.min(n)).or(plain(n))).collect())
}
