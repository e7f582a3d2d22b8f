//! Flying a camera (or several) around a mesh with the [`Runtime`]: the engine behind `dynlod fly`, the
//! demo and the runtime benchmarks.

use crate::camera_path::{frame_bounds, frame_box, orthographic, CameraPath};
use crate::lod::{FrameStats, FrameStop, Runtime, RuntimeOptions, SceneRuntime};
use crate::view::View;
use crate::Mesh;

/// What to fly.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct FlyOptions {
    /// Camera path. Default: orbit.
    pub path: CameraPath,
    /// Frames. Default: 360.
    pub frames: usize,
    /// Viewport in pixels. Default: 1920×1080.
    pub viewport: (u32, u32),
    /// Runtime options (pixel error, budget, …).
    pub runtime: RuntimeOptions,
    /// Validate the mesh and recount the hierarchy after every frame.
    pub verify: bool,
    /// Orthographic cameras: each frame's view framing at the mesh's centre what the path's
    /// perspective view frames there ([`orthographic`]). Default: off.
    pub orthographic: bool,
    /// Cameras flying the path together, evenly turned about the vertical axis through the
    /// mesh's centre ([`CameraPath::view_turned`]), all given to one runtime each frame
    /// ([`Runtime::update_views`]): a split screen, or one mesh drawn several times. Default: 1.
    pub cameras: usize,
}

impl Default for FlyOptions {
    fn default() -> Self {
        Self {
            path: CameraPath::Orbit,
            frames: 360,
            viewport: (1920, 1080),
            runtime: RuntimeOptions::default(),
            verify: false,
            orthographic: false,
            cameras: 1,
        }
    }
}

impl FlyOptions {
    /// Sets the path.
    pub fn path(mut self, p: CameraPath) -> Self {
        self.path = p;
        self
    }
    /// Sets the frame count.
    pub fn frames(mut self, n: usize) -> Self {
        self.frames = n;
        self
    }
    /// Sets the viewport.
    pub fn viewport(mut self, w: u32, h: u32) -> Self {
        self.viewport = (w.max(1), h.max(1));
        self
    }
    /// Sets the runtime options.
    pub fn runtime(mut self, r: RuntimeOptions) -> Self {
        self.runtime = r;
        self
    }
    /// Turns per-frame verification on (with [`RuntimeOptions::audit`], so buried records'
    /// stacks are recounted too; the memory figures then include the audit).
    pub fn verify(mut self, on: bool) -> Self {
        self.verify = on;
        self
    }
    /// Turns orthographic cameras on or off.
    pub fn orthographic(mut self, on: bool) -> Self {
        self.orthographic = on;
        self
    }
    /// Sets how many cameras fly the path together (at least 1).
    pub fn cameras(mut self, n: usize) -> Self {
        self.cameras = n.max(1);
        self
    }

    /// The views of frame `f` of a mesh with bounding box `centre` and `diag`, one per camera,
    /// into `out`.
    pub fn views(&self, f: usize, centre: [f32; 3], diag: f32, out: &mut Vec<View>) {
        out.clear();
        let n = self.cameras.max(1);
        out.extend((0..n).map(|k| {
            let turn = k as f32 * std::f32::consts::TAU / n as f32;
            let v = self.path.view_turned(f, self.frames, centre, diag, self.viewport, turn);
            if self.orthographic {
                orthographic(v, centre)
            } else {
                v
            }
        }));
    }
}

/// A whole flight.
#[derive(Debug, Clone, PartialEq)]
pub struct FlyReport {
    /// Per frame.
    pub frames: Vec<FrameStats>,
    /// Per frame: the largest screen-space error left after it, in pixels, over the cameras
    /// ([`Runtime::screen_error`]).
    pub screen_errors: Vec<f32>,
    /// Runtime bytes after the last frame.
    pub memory_bytes: usize,
    /// Input vertices n.
    pub vertices: usize,
    /// Input triangles.
    pub input_triangles: usize,
}

impl FlyReport {
    /// Median and 99th percentile of the update time over the warm frames (all but the first).
    pub fn warm_percentiles(&self) -> (f64, f64) {
        let mut t: Vec<f64> = self.frames.iter().skip(1).map(|f| f.total_ms).collect();
        if t.is_empty() {
            t = self.frames.iter().map(|f| f.total_ms).collect();
        }
        if t.is_empty() {
            return (0.0, 0.0);
        }
        t.sort_by(f64::total_cmp);
        let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
        (at(0.5), at(0.99))
    }

    /// Mean and largest screen-space error over the warm frames (all but the first), pixels.
    pub fn warm_screen_error(&self) -> (f64, f64) {
        let warm = if self.screen_errors.len() > 1 { &self.screen_errors[1..] } else { &self.screen_errors[..] };
        if warm.is_empty() {
            return (0.0, 0.0);
        }
        let sum: f64 = warm.iter().map(|&e| f64::from(e)).sum();
        (sum / warm.len() as f64, warm.iter().copied().fold(0.0f32, f32::max).into())
    }

    /// Fewest and most triangles over the frames.
    pub fn triangle_range(&self) -> (usize, usize) {
        let it = self.frames.iter().map(|f| f.triangles);
        (it.clone().min().unwrap_or(0), it.max().unwrap_or(0))
    }
}

/// A failed `verify`: which frame, and what was wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("frame {frame}: {what}")]
pub struct VerifyError {
    /// Frame number (from 1).
    pub frame: u64,
    /// The violation.
    pub what: String,
}

/// Flies `mesh` along the path, calling `each` after every frame.
pub fn fly(mesh: Mesh, o: &FlyOptions, mut each: impl FnMut(&FrameStats)) -> Result<FlyReport, VerifyError> {
    let (centre, diag) = frame_bounds(&mesh.positions);
    let vertices = mesh.positions.len();
    let input_triangles = mesh.topology.live_face_count();
    let (euler, loops) = {
        let s = mesh.topology.stats();
        (s.euler, s.boundary_loops)
    };
    // Verifying recounts every stack, buried records' too: that needs their faces kept.
    let mut rt = Runtime::new(mesh, o.runtime.clone().audit(o.runtime.audit || o.verify));
    let mut frames = Vec::with_capacity(o.frames);
    let mut screen_errors = Vec::with_capacity(o.frames);
    let mut views = Vec::with_capacity(o.cameras);
    for f in 0..o.frames {
        o.views(f, centre, diag, &mut views);
        let s = rt.update_views(&views);
        if o.verify {
            verify(&rt, (euler, loops)).map_err(|what| VerifyError { frame: s.frame, what })?;
        }
        each(&s);
        frames.push(s);
        screen_errors.push(rt.screen_error());
    }
    Ok(FlyReport { frames, screen_errors, memory_bytes: rt.memory_report().total(), vertices, input_triangles })
}

/// [`fly`] for a glTF scene kept as it is ([`SceneRuntime`]): the path frames the scene's
/// world bounds, each frame updates every mesh for the cameras through each of its
/// placements, and a frame's figures are the meshes' together: `triangles` those the scene
/// draws (each mesh times its placements), `vertices` those the runtimes hold, edits and
/// phase times summed, `total_ms` the whole update's wall time, the deepest chain, the
/// first stop other than converged. `FlyReport::vertices` is the meshes' input vertices and
/// `input_triangles` the triangles the full scene draws.
pub fn fly_scene(
    mut scene: SceneRuntime,
    bounds: ([f32; 3], [f32; 3]),
    o: &FlyOptions,
    mut each: impl FnMut(&FrameStats),
) -> Result<FlyReport, VerifyError> {
    let (centre, diag) = frame_box(bounds.0, bounds.1);
    let topology: Vec<(i64, u32)> = scene
        .meshes()
        .iter()
        .map(|m| {
            let s = m.runtime.mesh().topology.stats();
            (s.euler, s.boundary_loops)
        })
        .collect();
    // Each mesh once (its first group), however many runtimes it has.
    let vertices = scene.meshes().iter().filter(|m| m.group == 0).map(|m| m.runtime.mesh().positions.len()).sum();
    let input_triangles = scene.drawn_triangles();
    let mut frames = Vec::with_capacity(o.frames);
    let mut screen_errors = Vec::with_capacity(o.frames);
    let mut views = Vec::with_capacity(o.cameras);
    for f in 0..o.frames {
        o.views(f, centre, diag, &mut views);
        let start = std::time::Instant::now();
        let per_mesh = scene.update(&views);
        let mut s = together(per_mesh, start.elapsed().as_secs_f64() * 1e3);
        (s.frame, s.triangles) = (f as u64 + 1, scene.drawn_triangles());
        if o.verify {
            for (m, &shape) in scene.meshes().iter().zip(&topology) {
                let group = if m.group > 0 { format!(" (group {})", m.group) } else { String::new() };
                let fail =
                    |what: String| VerifyError { frame: s.frame, what: format!("mesh {}{group}: {what}", m.index) };
                verify(&m.runtime, shape).map_err(fail)?;
            }
        }
        each(&s);
        frames.push(s);
        screen_errors.push(scene.screen_error());
    }
    Ok(FlyReport { frames, screen_errors, memory_bytes: scene.memory_bytes(), vertices, input_triangles })
}

/// The meshes' figures of one frame as one (see [`fly_scene`]); `wall_ms` is the update's.
fn together(per_mesh: &[FrameStats], wall_ms: f64) -> FrameStats {
    let sum = |f: fn(&FrameStats) -> usize| per_mesh.iter().map(f).sum::<usize>();
    let held = sum(|s| s.vertices);
    FrameStats {
        collapses: sum(|s| s.collapses),
        splits: sum(|s| s.splits),
        split_rounds: sum(|s| s.split_rounds),
        collapse_rounds: sum(|s| s.collapse_rounds),
        graded_phases: per_mesh.iter().map(|s| s.graded_phases).max().unwrap_or(0),
        attempts: per_mesh.iter().map(|s| s.attempts).max().unwrap_or(0),
        rebalanced: sum(|s| s.rebalanced),
        rebalance_attempts: sum(|s| s.rebalance_attempts),
        vertices: held,
        max_chain_depth: per_mesh.iter().map(|s| s.max_chain_depth).max().unwrap_or(0),
        mean_chain_depth: per_mesh.iter().map(|s| s.mean_chain_depth * s.vertices as f64).sum::<f64>()
            / held.max(1) as f64,
        pixel_error: per_mesh.iter().map(|s| s.pixel_error).fold(0.0, f32::max),
        classify_ms: per_mesh.iter().map(|s| s.classify_ms).sum(),
        split_ms: per_mesh.iter().map(|s| s.split_ms).sum(),
        collapse_ms: per_mesh.iter().map(|s| s.collapse_ms).sum(),
        rebalance_ms: per_mesh.iter().map(|s| s.rebalance_ms).sum(),
        output_ms: per_mesh.iter().map(|s| s.output_ms).sum(),
        total_ms: wall_ms,
        changed_triangles: sum(|s| s.changed_triangles),
        changed_ranges: sum(|s| s.changed_ranges),
        stop: per_mesh.iter().map(|s| s.stop).find(|&st| st != FrameStop::Converged).unwrap_or_default(),
        skipped: per_mesh.iter().all(|s| s.skipped),
        ..FrameStats::default()
    }
}

/// `fly --verify`'s checks after a frame: the mesh validates, the hierarchy's stacks and the
/// charges recount, and the Euler characteristic and border loops are `shape`.
fn verify(rt: &Runtime, shape: (i64, u32)) -> Result<(), String> {
    let (euler, loops) = shape;
    rt.mesh().topology.validate().map_err(|e| e.to_string())?;
    rt.hierarchy().check(&rt.mesh().topology)?;
    rt.check_charges()?;
    let st = rt.mesh().topology.stats();
    if st.euler != euler || st.boundary_loops != loops {
        return Err(format!(
            "Euler characteristic {} (was {euler}), border loops {} (was {loops})",
            st.euler, st.boundary_loops
        ));
    }
    Ok(())
}
