//! A whole glTF scene under a moving camera, kept as it is: one [`Runtime`] per mesh
//! definition, in the mesh's own space, updated each frame with the camera carried into that
//! space through every node that draws it ([`View::in_model_space`], then
//! [`Runtime::update_views`]). A mesh drawn by twenty nodes is held, coarsened and uploaded
//! once, and serves all twenty: each instance sees at most the pixel error and no face turns
//! against its eye (docs/ALGORITHM.md, "Several views in one runtime"). The renderer draws each
//! runtime's index buffer once per placement, with the placement's transform.
//!
//! ```text
//!   camera (world) ──M₁⁻¹──► view in mesh A's space ─┐
//!                  ──M₂⁻¹──► view in mesh A's space ─┴─► runtime A.update_views([v₁, v₂])
//!                  ──M₃⁻¹──► view in mesh B's space ───► runtime B.update_views([v₃])
//! ```
//!
//! Placements start as the scene's node transforms as loaded; a renderer that moves, adds or
//! removes instances sets a mesh's placements anew ([`SceneRuntime::set_placements`]), and
//! [`SceneRuntime::from_meshes`] takes meshes and placements from any scene graph, not only
//! glTF. A node that stretches or shears its mesh cannot carry a camera into the mesh's space
//! (the pixel size of an error there depends on its direction, which a runtime's error, a
//! length, does not know): [`SceneRuntime::new`] draws it with a copy of the mesh that has the
//! stretch baked in, placed by the rest of the node's transform (`scene_stretch.rs`; nodes
//! with the same stretch share the copy; [`SceneRuntime::stretched`] says which), while
//! [`SceneRuntime::from_meshes`] and [`SceneRuntime::set_placements`] refuse such a
//! placement, naming the mesh and the node or instance. A mesh with no placement gets no
//! updates and stays as it was.
//!
//! **Instance groups.** One runtime for all of a mesh's placements draws every one at the detail
//! its nearest needs: a forest of one tree drawn 400 times draws 400 near trees. With
//! [`SceneRuntime::set_instance_groups`] a mesh drawn more than once gets up to k runtimes, and
//! each frame its placements are shared among them by how many pixels a unit of the mesh
//! covers at each (bands of equal ratio between the nearest and the farthest,
//! `scene_groups.rs`): a group draws at its own nearest instance's detail. Each group is a
//! runtime of its own ([`SceneMeshRuntime`]: its placements, [`SceneMeshRuntime::instances`]
//! says which of the mesh's they are); it costs a runtime's memory, and its index buffer is an
//! upload of its own, over the mesh's one vertex buffer. A renderer keeps a group's buffer by
//! `(mesh, group)` and uploads it whole when [`SceneMeshRuntime::generation`] changes (the
//! group's runtime was replaced by a copy of another), else by its changed ranges. Every instance still sees at most the
//! pixel error: grouping moves triangles, never the bound.
//!
//! A triangle budget ([`RuntimeOptions::budget`], [`SceneRuntime::set_budget`]) is the whole
//! scene's: the triangles it draws, each mesh's once per placement, held under it by one
//! threshold for every mesh (`scene_budget.rs`), so the screen error is even across the scene
//! and the budget goes to what is near.

use rayon::prelude::*;

use crate::io::{GltfScene, Placement};
use crate::view::{check_model_matrix, views_through, ModelMatrixError, View};
use crate::{BuildError, BuildOptions, Mesh};

use super::scene_budget::SceneBudget;
use super::scene_groups::{self, GroupScratch};
use super::scene_stretch;
use super::{FrameStats, InputError, Runtime, RuntimeOptions};

/// Why a [`SceneRuntime`] cannot be built, or cannot take new placements.
#[derive(Debug, thiserror::Error)]
pub enum SceneRuntimeError {
    /// A mesh definition did not build.
    #[error("{mesh}: {source}")]
    Build {
        /// The mesh, as [`SceneMesh::label`](crate::io::SceneMesh::label) names it.
        mesh: String,
        /// Why.
        source: BuildError,
    },
    /// A node draws its mesh through a transform a camera cannot be carried through.
    #[error("{mesh} drawn by {node}: {source}")]
    Placement {
        /// The mesh, as [`SceneMesh::label`](crate::io::SceneMesh::label) names it, or
        /// "mesh k" by its position.
        mesh: String,
        /// The node ("node 4"), or the placement by its position in the mesh's list
        /// ("instance 2") where no node is known.
        node: String,
        /// Why.
        source: ModelMatrixError,
    },
    /// [`SceneRuntime::set_placements`] named a mesh the scene runtime does not have.
    #[error("no mesh {mesh}: the scene runtime has {meshes}")]
    NoSuchMesh {
        /// The position asked for.
        mesh: usize,
        /// How many meshes there are.
        meshes: usize,
    },
}

/// A runtime of the scene: a mesh definition's, serving all its placements, or with instance
/// groups ([`SceneRuntime::set_instance_groups`]) some of them. Draw its index buffer once per
/// entry of `placements`.
#[derive(Clone)]
pub struct SceneMeshRuntime {
    /// The mesh's index among the source's meshes (its position, from
    /// [`SceneRuntime::from_meshes`]).
    pub index: usize,
    /// The mesh's position among the scene runtime's meshes, as
    /// [`SceneRuntime::set_placements`] takes it.
    pub mesh: usize,
    /// Its group among the mesh's runtimes: 0 draws the nearest instances.
    pub group: usize,
    /// The runtime, in the mesh's own space.
    pub runtime: Runtime,
    /// The stretch baked into this runtime's mesh (column-major: the mesh's positions are
    /// the source's through it), for nodes that stretched or sheared the mesh; `None`: the
    /// source's mesh as it is. A renderer draws a stretched copy from the runtime's own
    /// vertices ([`crate::Mesh::wedge_positions`]), at its `placements`.
    pub stretch: Option<[[f32; 3]; 3]>,
    /// Where it is drawn: one entry per instance it serves.
    pub placements: Vec<Placement>,
    /// Which of the mesh's placements those are (positions in the list it was given), in
    /// the same order.
    pub instances: Vec<usize>,
    /// Changes whenever this group's runtime is replaced by a copy of another (a group added,
    /// an idle group started warm): its index buffer is then not the one a renderer kept for
    /// `(mesh, group)`, and [`IndexPart::changed_ranges`](super::index_buffer::IndexPart::changed_ranges)
    /// are the copy's. A renderer holding an earlier generation uploads the whole buffer.
    pub generation: u64,
    /// The last update's views, one per camera and placement (kept for reuse).
    pub(super) views: Vec<View>,
}

/// A mesh definition: every placement, and what grouping reads.
pub(super) struct SceneMeshDef {
    /// How errors name it.
    label: String,
    /// Where it is drawn: one entry per instance.
    pub(super) placements: Vec<Placement>,
    /// Its bounding sphere in its own space (centre, radius).
    pub(super) sphere: ([f32; 3], f32),
}

impl SceneMeshDef {
    fn new(label: String, placements: Vec<Placement>, mesh: &Mesh) -> Self {
        let (centre, diag) = crate::camera_path::frame_bounds(&mesh.positions);
        Self { label, placements, sphere: (centre, 0.5 * diag) }
    }

    /// How many runtimes it gets with up to `k` groups: one per placement at most, one at least.
    fn groups(&self, k: usize) -> usize {
        k.min(self.placements.len()).max(1)
    }
}

/// The one runtime of mesh `mesh` (group 0, every placement).
fn sole(index: usize, mesh: usize, runtime: Runtime, placements: &[Placement]) -> SceneMeshRuntime {
    let instances = (0..placements.len()).collect();
    let (placements, views) = (placements.to_vec(), Vec::new());
    SceneMeshRuntime { index, mesh, group: 0, runtime, stretch: None, placements, instances, generation: 0, views }
}

/// Placements without nodes.
fn placed(worlds: impl Iterator<Item = [[f32; 4]; 4]>) -> Vec<Placement> {
    worlds.map(|world| Placement { node: None, instance: None, world }).collect()
}

/// Refuses the first placement a camera cannot be carried through ([`check_model_matrix`]:
/// once checked, a placement carries every camera).
fn check(label: &str, placements: &[Placement]) -> Result<(), SceneRuntimeError> {
    for (k, p) in placements.iter().enumerate() {
        check_model_matrix(p.world).map_err(|source| SceneRuntimeError::Placement {
            mesh: label.to_string(),
            node: p.label(k),
            source,
        })?;
    }
    Ok(())
}

/// A glTF scene's meshes, each under a [`Runtime`] serving every node that draws it. See the
/// module docs.
pub struct SceneRuntime {
    /// The runtimes, by mesh and within a mesh by group.
    pub(super) meshes: Vec<SceneMeshRuntime>,
    /// The mesh definitions, by position.
    defs: Vec<SceneMeshDef>,
    /// Most runtimes per mesh ([`SceneRuntime::set_instance_groups`]).
    groups: usize,
    /// The last update's cameras (grouping placements set between updates).
    cameras: Vec<View>,
    /// Grouping's lists, kept for reuse.
    group_scratch: GroupScratch,
    /// The last generation given to a runtime ([`SceneMeshRuntime::generation`]).
    generations: u64,
    /// What was baked for stretching nodes ([`SceneRuntime::stretched`]).
    stretched: Vec<String>,
    /// The last update's figures, one per runtime.
    pub(super) stats: Vec<FrameStats>,
    /// The pixel error (in budget mode, where the threshold starts from).
    pixel_error: f32,
    /// The threshold every mesh runs at: the pixel error, or in budget mode what the budget
    /// allows.
    pub(super) tau: f32,
    /// The budget mode (`scene_budget.rs`).
    pub(super) budget: SceneBudget,
}

impl SceneRuntime {
    /// Builds every mesh of `scene` with `build` and puts it under a runtime with `options`:
    /// the same pixel error everywhere. A budget in `options` is the whole scene's (drawn
    /// triangles; see the module docs), not each mesh's; an edit cap
    /// ([`RuntimeOptions::max_edits`]) is each mesh's (under a budget, a mesh that reaches it
    /// ends the scene's frame: the threshold is not moved on a scene still catching up).
    pub fn new(scene: &GltfScene, build: BuildOptions, options: RuntimeOptions) -> Result<Self, SceneRuntimeError> {
        let (mut meshes, mut defs) = (Vec::with_capacity(scene.meshes.len()), Vec::with_capacity(scene.meshes.len()));
        // Stretched copies come after the source's meshes, which keep their positions.
        let (mut copies, mut stretched) = (Vec::new(), Vec::new());
        for (at, sm) in scene.meshes.iter().enumerate() {
            let label = sm.label();
            let (kept, by_stretch) = scene_stretch::sort(&sm.placements);
            check(&label, &kept)?;
            let mesh = Mesh::build(&sm.mesh, build)
                .map_err(|source| SceneRuntimeError::Build { mesh: label.clone(), source })?;
            defs.push(SceneMeshDef::new(label.clone(), kept.clone(), &mesh));
            meshes.push(sole(sm.index, at, Runtime::new(mesh, options.clone().budget(None)), &kept));
            for s in by_stretch {
                let nodes: Vec<String> = s.placements.iter().enumerate().map(|(k, p)| p.label(k)).collect();
                let copy = format!("{label} stretched for {}", nodes.join(", "));
                let mesh = Mesh::build(&scene_stretch::bake(&sm.mesh, s.stretch), build)
                    .map_err(|source| SceneRuntimeError::Build { mesh: copy.clone(), source })?;
                let axes = s.stretch.map(|c| glam::Vec3::from(c).length());
                stretched.push(format!(
                    "{label}: {} stretch or shear it (axes scaled by {axes:?}), so they draw a copy with the stretch baked in",
                    nodes.join(", ")
                ));
                copies.push((SceneMeshDef::new(copy, s.placements.clone(), &mesh), sm.index, s, mesh));
            }
        }
        for (def, index, s, mesh) in copies {
            let mut m = sole(index, defs.len(), Runtime::new(mesh, options.clone().budget(None)), &s.placements);
            m.stretch = Some(s.stretch);
            defs.push(def);
            meshes.push(m);
        }
        let mut rt = Self::of(meshes, defs, &options);
        rt.stretched = stretched;
        Ok(rt)
    }

    /// A scene runtime over meshes you built, each with the world transforms it is drawn
    /// with (object → world, column-major, as glTF stores them; none: not drawn). For a scene
    /// graph of your own; the meshes are named by their position. Options as for
    /// [`SceneRuntime::new`].
    pub fn from_meshes(
        meshes: Vec<(Mesh, Vec<[[f32; 4]; 4]>)>,
        options: RuntimeOptions,
    ) -> Result<Self, SceneRuntimeError> {
        let (mut out, mut defs) = (Vec::with_capacity(meshes.len()), Vec::with_capacity(meshes.len()));
        for (index, (mesh, worlds)) in meshes.into_iter().enumerate() {
            let label = format!("mesh {index}");
            let placements = placed(worlds.iter().copied());
            check(&label, &placements)?;
            defs.push(SceneMeshDef::new(label, placements.clone(), &mesh));
            out.push(sole(index, index, Runtime::new(mesh, options.clone().budget(None)), &placements));
        }
        Ok(Self::of(out, defs, &options))
    }

    fn of(meshes: Vec<SceneMeshRuntime>, defs: Vec<SceneMeshDef>, options: &RuntimeOptions) -> Self {
        let stats = vec![FrameStats::default(); meshes.len()];
        let (pixel_error, budget) = (options.pixel_error, SceneBudget::new(options.budget));
        let (cameras, group_scratch) = (Vec::new(), GroupScratch::default());
        let (generations, stretched) = (0, Vec::new());
        Self {
            meshes,
            defs,
            groups: 1,
            cameras,
            group_scratch,
            generations,
            stretched,
            stats,
            pixel_error,
            tau: pixel_error,
            budget,
        }
    }

    /// Sets where the mesh at position `mesh` (of those given; [`SceneMeshRuntime::mesh`]) is
    /// drawn from the next update on: an object moved, an instance added or removed (none: not
    /// drawn, not updated). Refused, with the placements left as they were, if one stretches
    /// or shears. The next update adapts the mesh to its new views as to any camera move. With
    /// instance groups the placements are shared among the mesh's runtimes at once, by the
    /// last update's cameras (before any update, all to the first); a group added for them
    /// starts as a copy of the mesh's farthest.
    pub fn set_placements(&mut self, mesh: usize, worlds: &[[[f32; 4]; 4]]) -> Result<(), SceneRuntimeError> {
        let meshes = self.defs.len();
        let def = self.defs.get_mut(mesh).ok_or(SceneRuntimeError::NoSuchMesh { mesh, meshes })?;
        let placements = placed(worlds.iter().copied());
        check(&def.label, &placements)?;
        def.placements = placements;
        self.regroup();
        Ok(())
    }

    /// Lets each mesh drawn more than once have up to `k` runtimes (at least 1: one serves all,
    /// the default), each serving the placements in one band of distance (module docs), from
    /// now on. A group added starts as a copy of the mesh's farthest runtime; the placements
    /// are shared as [`SceneRuntime::set_placements`] shares them.
    pub fn set_instance_groups(&mut self, k: usize) {
        self.groups = k.max(1);
        self.regroup();
    }

    /// Most runtimes per mesh ([`SceneRuntime::set_instance_groups`]).
    pub fn instance_groups(&self) -> usize {
        self.groups
    }

    /// Gives each mesh as many runtimes as its groups (copies of its farthest, or the farthest
    /// dropped) and shares its placements among them by the last cameras.
    fn regroup(&mut self) {
        let mut old = std::mem::take(&mut self.meshes).into_iter().peekable();
        for (at, def) in self.defs.iter().enumerate() {
            let mut mine: Vec<SceneMeshRuntime> = std::iter::from_fn(|| old.next_if(|m| m.mesh == at)).collect();
            let want = def.groups(self.groups);
            mine.truncate(want);
            while mine.len() < want {
                let mut copy = mine.last().expect("a mesh keeps its first runtime").clone();
                self.generations += 1;
                (copy.group, copy.generation) = (mine.len(), self.generations);
                mine.push(copy);
            }
            self.meshes.extend(mine);
        }
        self.stats.resize(self.meshes.len(), FrameStats::default());
        self.share();
    }

    /// Shares every mesh's placements among its runtimes by the last update's cameras
    /// (`scene_groups.rs`).
    fn share(&mut self) {
        scene_groups::share(
            &self.defs,
            &mut self.meshes,
            &self.cameras,
            &mut self.group_scratch,
            &mut self.generations,
        );
    }

    /// The runtimes, by mesh in the scene's order and within a mesh by group (nearest first;
    /// one per mesh without instance groups).
    pub fn meshes(&self) -> &[SceneMeshRuntime] {
        &self.meshes
    }

    /// How many meshes the scene has (runtimes may be more: [`SceneRuntime::meshes`]):
    /// the source's, then one stretched copy per distinct stretch of its nodes.
    pub fn mesh_count(&self) -> usize {
        self.defs.len()
    }

    /// What [`SceneRuntime::new`] baked for nodes that stretch or shear their mesh, one line
    /// per copy (the mesh, the nodes, the axes' scales); empty where no node does.
    pub fn stretched(&self) -> &[String] {
        &self.stretched
    }

    /// Adapts every drawn mesh to `cameras` (world space; one for a single screen, several for
    /// a split screen), each mesh for each camera through each of its placements. Returns
    /// each runtime's figures, as [`SceneRuntime::meshes`] lists them (a runtime drawn nowhere:
    /// not updated, its figures zero but for
    /// [`FrameStats::skipped`]). Allocates only when a mesh gets more views than ever before;
    /// a frame every mesh skips ([`Runtime::update`]: nothing changed; in budget mode, under a
    /// threshold that did not move) runs on the calling thread and allocates nothing.
    ///
    /// A camera that fails [`View::check`], or a pixel error or hysteresis the runtimes
    /// refuse, makes every runtime's figures say so ([`FrameStop::Refused`](super::FrameStop::Refused))
    /// and changes nothing.
    pub fn update(&mut self, cameras: &[View]) -> &[FrameStats] {
        if let Err(e) = self.check_input(cameras) {
            for (m, s) in self.meshes.iter_mut().zip(&mut self.stats) {
                *s = m.runtime.refuse(e, std::time::Instant::now());
            }
            return &self.stats;
        }
        let moved =
            self.cameras.len() != cameras.len() || self.cameras.iter().zip(cameras).any(|(a, b)| !a.is_identical(b));
        if moved {
            self.cameras.clear();
            self.cameras.extend_from_slice(cameras);
            if self.groups > 1 {
                self.share();
            }
        }
        for m in &mut self.meshes {
            // Checked when set (`check`): every placement carries every camera.
            views_through(cameras, &m.placements, &mut m.views).expect("placements are checked when they are set");
        }
        let one = |(m, s): (&mut SceneMeshRuntime, &mut FrameStats)| {
            *s = if m.placements.is_empty() {
                FrameStats { skipped: true, ..FrameStats::default() }
            } else {
                m.runtime.update_views(&m.views)
            };
        };
        let settled = self.budget.tris.is_none() || self.budget.settled;
        if settled && self.meshes.iter().all(|m| m.placements.is_empty() || m.runtime.repeats(&m.views)) {
            // Each returns at once: no hand-off to the pool (whose queue allocates now and then).
            self.meshes.iter_mut().zip(&mut self.stats).for_each(one);
        } else if let Some(budget) = self.budget.tris {
            self.update_in_budget(budget);
        } else {
            // The meshes side by side on the pool, each update on the thread that takes it (its
            // passes join the pool's work from there): every runtime is deterministic alone.
            crate::par::on_pool(|| self.meshes.par_iter_mut().zip(&mut self.stats).for_each(one));
        }
        &self.stats
    }

    /// Whether `cameras`, the pixel error and the runtimes' options can be used for an update
    /// ([`SceneRuntime::update`]).
    pub fn check_input(&self, cameras: &[View]) -> Result<(), InputError> {
        super::input_error::check(cameras, self.pixel_error)?;
        // Every runtime has the scene's options (`SceneRuntime::new`), set together after.
        self.meshes.first().map_or(Ok(()), |m| m.runtime.check_input(&[]))
    }

    /// Changes the pixel error from the next update on (a quality setting; in budget mode,
    /// where the threshold starts again from). Setting the value in force changes nothing
    /// ([`Runtime::set_pixel_error`]).
    pub fn set_pixel_error(&mut self, px: f32) {
        if px.to_bits() == self.pixel_error.to_bits()
            && (self.budget.tris.is_some() || px.to_bits() == self.tau.to_bits())
        {
            return;
        }
        (self.pixel_error, self.tau, self.budget.settled) = (px, px, false);
        for m in &mut self.meshes {
            m.runtime.set_pixel_error(px);
        }
    }

    /// Changes the scene's triangle budget from the next update on (`None`: back to the pixel
    /// error). It counts the triangles the scene draws ([`SceneRuntime::drawn_triangles`]: a
    /// mesh's once per placement). The budget in force again changes nothing.
    pub fn set_budget(&mut self, tris: Option<usize>) {
        if tris == self.budget.tris {
            return;
        }
        self.budget.restart(tris);
        if tris.is_none() {
            self.tau = self.pixel_error;
            for m in &mut self.meshes {
                // The runtimes ran at the scene's threshold: back to the pixel error.
                m.runtime.set_pixel_error(self.pixel_error);
            }
        }
    }

    /// Changes every mesh's edit cap per frame from the next update on
    /// ([`Runtime::set_max_edits`]): for example none for the first update, on a loading
    /// thread, and a cap after it.
    pub fn set_max_edits(&mut self, n: Option<usize>) {
        for m in &mut self.meshes {
            m.runtime.set_max_edits(n);
        }
    }

    /// The scene's triangle budget, if any.
    pub fn budget(&self) -> Option<usize> {
        self.budget.tris
    }

    /// The threshold every mesh ran at in the last update, in pixels: the pixel error, or in
    /// budget mode what the budget allowed.
    pub fn threshold(&self) -> f32 {
        self.tau
    }

    /// Triangles the scene draws now: each mesh's live triangles times its placements.
    pub fn drawn_triangles(&self) -> usize {
        self.meshes.iter().map(|m| m.runtime.triangles() * m.placements.len()).sum()
    }

    /// Triangles the runtimes hold now (each mesh once).
    pub fn held_triangles(&self) -> usize {
        self.meshes.iter().map(|m| m.runtime.triangles()).sum()
    }

    /// The largest screen-space error any instance shows, in pixels, over the last update's
    /// cameras ([`Runtime::screen_error`]: pixels are the screen's in every mesh's space).
    pub fn screen_error(&self) -> f32 {
        self.meshes.iter().filter(|m| !m.placements.is_empty()).map(|m| m.runtime.screen_error()).fold(0.0, f32::max)
    }

    /// Bytes of every runtime together ([`Runtime::memory_report`]).
    pub fn memory_bytes(&self) -> usize {
        self.meshes.iter().map(|m| m.runtime.memory_report().total()).sum()
    }
}
