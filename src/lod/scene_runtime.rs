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
//! glTF. A placement that stretches or shears its mesh is refused, naming the mesh and the
//! node or instance: the pixel size of an error there depends on its direction, which a
//! runtime's error (a length) does not know. A mesh with no placement gets no updates and
//! stays as it was.
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
use super::{FrameStats, Runtime, RuntimeOptions};

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

/// One mesh definition of the scene under its runtime.
pub struct SceneMeshRuntime {
    /// The mesh's index among the source's meshes (its position, from
    /// [`SceneRuntime::from_meshes`]).
    pub index: usize,
    /// How errors name it.
    label: String,
    /// The mesh's runtime, in its own space.
    pub runtime: Runtime,
    /// Where it is drawn: one entry per instance.
    pub placements: Vec<Placement>,
    /// The last update's views, one per camera and placement (kept for reuse).
    pub(super) views: Vec<View>,
}

/// Placements without nodes.
fn placed(worlds: impl Iterator<Item = [[f32; 4]; 4]>) -> Vec<Placement> {
    worlds.map(|world| Placement { node: None, world }).collect()
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
    pub(super) meshes: Vec<SceneMeshRuntime>,
    /// The last update's figures, one per mesh.
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
        let mut meshes = Vec::with_capacity(scene.meshes.len());
        for sm in &scene.meshes {
            let label = sm.label();
            check(&label, &sm.placements)?;
            let mesh = Mesh::build(&sm.mesh, build)
                .map_err(|source| SceneRuntimeError::Build { mesh: label.clone(), source })?;
            meshes.push(SceneMeshRuntime {
                index: sm.index,
                label,
                runtime: Runtime::new(mesh, options.clone().budget(None)),
                placements: sm.placements.clone(),
                views: Vec::new(),
            });
        }
        Ok(Self::of(meshes, &options))
    }

    /// A scene runtime over meshes you built, each with the world transforms it is drawn
    /// with (object → world, column-major, as glTF stores them; none: not drawn). For a scene
    /// graph of your own; the meshes are named by their position. Options as for
    /// [`SceneRuntime::new`].
    pub fn from_meshes(
        meshes: Vec<(Mesh, Vec<[[f32; 4]; 4]>)>,
        options: RuntimeOptions,
    ) -> Result<Self, SceneRuntimeError> {
        let mut out = Vec::with_capacity(meshes.len());
        for (index, (mesh, worlds)) in meshes.into_iter().enumerate() {
            let label = format!("mesh {index}");
            let placements = placed(worlds.iter().copied());
            check(&label, &placements)?;
            out.push(SceneMeshRuntime {
                index,
                label,
                runtime: Runtime::new(mesh, options.clone().budget(None)),
                placements,
                views: Vec::new(),
            });
        }
        Ok(Self::of(out, &options))
    }

    fn of(meshes: Vec<SceneMeshRuntime>, options: &RuntimeOptions) -> Self {
        let stats = vec![FrameStats::default(); meshes.len()];
        let (pixel_error, budget) = (options.pixel_error, SceneBudget::new(options.budget));
        Self { meshes, stats, pixel_error, tau: pixel_error, budget }
    }

    /// Sets where the mesh at position `mesh` of [`SceneRuntime::meshes`] is drawn from the
    /// next update on: an object moved, an instance added or removed (none: not drawn, not
    /// updated). Refused, with the placements left as they were, if one stretches or shears.
    /// The next update adapts the mesh to its new views as to any camera move.
    pub fn set_placements(&mut self, mesh: usize, worlds: &[[[f32; 4]; 4]]) -> Result<(), SceneRuntimeError> {
        let meshes = self.meshes.len();
        let m = self.meshes.get_mut(mesh).ok_or(SceneRuntimeError::NoSuchMesh { mesh, meshes })?;
        let placements = placed(worlds.iter().copied());
        check(&m.label, &placements)?;
        m.placements = placements;
        Ok(())
    }

    /// The meshes under their runtimes, in the scene's order.
    pub fn meshes(&self) -> &[SceneMeshRuntime] {
        &self.meshes
    }

    /// Adapts every drawn mesh to `cameras` (world space; one for a single screen, several for
    /// a split screen), each mesh for each camera through each of its placements. Returns
    /// each mesh's figures (a mesh no node draws: not updated, its figures zero but for
    /// [`FrameStats::skipped`]). Allocates only when a mesh gets more views than ever before;
    /// a frame every mesh skips ([`Runtime::update`]: nothing changed; in budget mode, under a
    /// threshold that did not move) runs on the calling thread and allocates nothing.
    pub fn update(&mut self, cameras: &[View]) -> &[FrameStats] {
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
