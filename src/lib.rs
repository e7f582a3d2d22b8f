//! # dynlod
//!
//! An incremental, view-dependent progressive-mesh runtime. A renderer hands it a camera
//! every frame; it coarsens the mesh through parallel half-edge collapses that need no
//! coordination (papers/000, Odaker et al. 2015) and refines it again through vertex splits
//! whose legality is checked by counters (papers/001, Merrin & Shah), so the level of detail
//! carries over from frame to frame instead of being rebuilt. Beside it: an offline
//! simplifier (papers/002's dihedral-angle cost with multiple-choice selection, and greedy
//! quadrics), glTF scenes simplified whole, and quality metrics. docs/ALGORITHM.md maps each
//! paper section to its file.
//!
//! ## The pipeline
//!
//! * [`io`] reads OBJ, PLY, OFF, STL and glTF/GLB into an [`IndexedMesh`] and writes OBJ,
//!   binary PLY and GLB atomically (a temporary file, then a rename); a file far from its own
//!   origin (a survey's UTM coordinates) is read relative to its centre,
//!   [`IndexedMesh::origin`], so f32 keeps its precision, and written back where it was;
//! * [`Mesh::build`] welds vertices by position while keeping per-corner attribute *wedges*
//!   (normals, UVs, colours, tangents: their seams survive), repairs what can be repaired
//!   without guessing (and records it in [`Mesh::repairs`]), and builds the compact
//!   [`topology::Topology`] every pass edits; bad input is a typed [`Error`] naming file and
//!   place;
//! * [`lod::Runtime`] keeps a mesh at a view-dependent level of detail: each
//!   [`lod::Runtime::update`] classifies the live vertices in screen pixels, splits where the
//!   view needs detail, collapses where it does not, rebalances long dependency chains, and
//!   updates the renderer's [`lod::IndexBuffer`] (stable slots, one part per primitive, and the
//!   ranges that changed);
//! * [`simplify`] makes static levels of detail offline, one mesh or a whole glTF scene;
//! * [`metrics`] measures what a simplification cost: symmetric Hausdorff distance (Metro
//!   style) and attribute errors.
//!
//! ## A renderer's frame loop
//!
//! The vertex buffer is uploaded once (a half-edge collapse moves no vertex); each frame only
//! the index ranges the update changed are uploaded, one index buffer per primitive:
//!
//! ```
//! use dynlod::lod::{Runtime, RuntimeOptions};
//! use dynlod::view::View;
//!
//! let mesh = dynlod::Mesh::build(&dynlod::procedural::uv_sphere(64, 128), Default::default())?;
//! let vertex_buffer = mesh.wedge_positions(); // with mesh.wedges.normals, .uvs, .attributes
//! let mut index_buffers: Vec<Vec<[u32; 3]>> = Vec::new(); // stand-ins for GPU buffers
//!
//! let mut rt = Runtime::new(mesh, RuntimeOptions::default().pixel_error(1.0));
//! for frame in 0..30 {
//!     let distance = 3.0 + frame as f32; // flying away
//!     let view = View::perspective([0.0, 0.0, distance], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
//!     let stats = rt.update(Some(&view));
//!     let parts = rt.index_buffer().parts();
//!     index_buffers.resize(parts.len(), Vec::new());
//!     for (part, gpu) in parts.iter().zip(&mut index_buffers) {
//!         gpu.resize(part.triangles().len(), [0; 3]); // draw all of it
//!         for r in part.changed_ranges() {
//!             let r = r.start as usize..r.end as usize; // queue.write_buffer(..) in wgpu
//!             gpu[r.clone()].copy_from_slice(&part.triangles()[r]);
//!         }
//!     }
//!     assert_eq!(stats.triangles, rt.triangles());
//! }
//! // Far away, under a thousand of the 16k triangles are left, drawn from the same vertices.
//! assert!(rt.triangles() < 1_000);
//! assert!(index_buffers[0].iter().flatten().all(|&w| (w as usize) < vertex_buffer.len()));
//! # Ok::<(), dynlod::BuildError>(())
//! ```
//!
//! A mesh drawn with a model matrix (an object placed in the world) keeps one runtime in its
//! own space: [`view::View::in_model_space`] carries the world camera there, exactly for any
//! rotation, translation, uniform scale or mirror. Cameras are perspective or orthographic
//! ([`view::View::orthographic`]: a directional light's shadow pass, CAD and map views).
//! [`lod::RuntimeOptions::budget`] holds a triangle budget instead of a pixel error;
//! [`lod::FrameStats`] says what each frame did and why it stopped, and
//! [`lod::Runtime::memory_report`] what every structure holds.
//!
//! A scene of several meshes, each drawn at one or more placements, runs under a
//! [`lod::SceneRuntime`]: one runtime per mesh serving all its placements, and a budget (if
//! any) for everything the scene draws, spent where the camera is:
//!
//! ```
//! use dynlod::lod::{RuntimeOptions, SceneRuntime};
//! use dynlod::view::View;
//!
//! let at = |x: f32, z: f32| [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [x, 0.0, z, 1.0]];
//! let rock = dynlod::Mesh::build(&dynlod::procedural::uv_sphere(32, 64), Default::default())?;
//! let ring = dynlod::Mesh::build(&dynlod::procedural::torus(48, 96), Default::default())?;
//! // Four rocks along the road and one ring beside it.
//! let placed = vec![(rock, (0..4).map(|k| at(2.0, -6.0 * k as f32)).collect()), (ring, vec![at(-2.0, -1.0)])];
//! let mut scene = SceneRuntime::from_meshes(placed, RuntimeOptions::default().budget(Some(6_000)))?;
//! assert_eq!(scene.drawn_triangles(), 4 * 3_968 + 9_216); // at full detail
//! let camera = View::perspective([0.0, 1.0, 4.0], [0.0, 0.0, -10.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
//! for _ in 0..10 {
//!     scene.update(&[camera]); // then upload each mesh's changed ranges, draw it at each placement
//! }
//! assert!(scene.drawn_triangles() <= 6_000);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Offline: a static level of detail, and what it cost
//!
//! ```
//! use dynlod::metrics::{hausdorff, HausdorffOptions};
//! use dynlod::simplify::{simplify, Method, SimplifyOptions};
//!
//! let input = dynlod::procedural::torus(48, 96);
//! let mut mesh = dynlod::Mesh::build(&input, Default::default())?;
//! let stats = simplify(&mut mesh, SimplifyOptions::default().method(Method::QemFlat).target_triangles(900));
//! assert!(stats.output_triangles <= 900);
//! let lod = mesh.to_indexed(); // dynlod::io::save("torus_lod.glb", &lod) writes it
//! let d = hausdorff(&input, &lod, HausdorffOptions::default());
//! assert!(d.pct(d.rms) < 0.5, "RMS distance {:.3} % of the diagonal", d.pct(d.rms));
//! # Ok::<(), dynlod::BuildError>(())
//! ```
//!
//! Loading a file and checking what was repaired:
//!
//! ```no_run
//! let indexed = dynlod::io::load("bunny.ply")?;
//! let mesh = dynlod::Mesh::build(&indexed, dynlod::BuildOptions::default())?;
//! mesh.topology.validate()?;
//! println!("{} vertices, {} repairs", mesh.positions.len(), mesh.repairs.len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A glTF scene keeps its nodes, skins and animations: [`simplify::simplify_scene`] and
//! [`io::GltfScene`]. A static cut for known cameras ([`lod::coarsen::coarsen_views`]) keeps
//! what every view needs: one mesh seen by several cameras, or drawn by several nodes of a
//! scene under one (each node's view from [`io::SceneMesh::placements`] and
//! [`view::View::in_model_space`]).

#![warn(missing_docs)]

pub mod camera_path;
pub mod error;
pub mod fly;
pub mod info;
pub mod io;
pub mod lod;
pub mod mesh;
pub mod metrics;
pub mod procedural;
pub mod rss;
pub mod simplify;
pub mod topology;
pub mod view;

mod lists;
mod par;

/// The bundled Stanford bunny, for the crate's unit tests (the integration tests have their
/// own copy in tests/).
#[cfg(test)]
pub(crate) fn test_bunny() -> Mesh {
    load_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz"), BuildOptions::default())
        .expect("the bundled bunny loads")
}

/// A runtime on the bundled bunny after one update, at `frame` of a 100-frame dolly seen in a
/// `viewport`: a coarsened mesh with deep chains, for unit tests of the hierarchy.
#[cfg(test)]
pub(crate) fn test_bunny_runtime(options: lod::RuntimeOptions, frame: usize, viewport: (u32, u32)) -> lod::Runtime {
    let m = test_bunny();
    let (centre, diag) = camera_path::frame_bounds(&m.positions);
    let mut rt = lod::Runtime::new(m, options);
    rt.update(Some(&camera_path::CameraPath::Dolly.view(frame, 100, centre, diag, viewport)));
    rt
}

pub use error::{BuildError, Error, LoadError, LoadErrorKind, MeshError, SceneError};
pub use mesh::{BuildOptions, IndexedMesh, Mesh, Repair};

/// Loads a file and builds its mesh in one step.
pub fn load_mesh(path: impl AsRef<std::path::Path>, options: BuildOptions) -> Result<Mesh, Error> {
    let path = path.as_ref();
    let indexed = io::load(path)?;
    Mesh::build(&indexed, options).map_err(|source| Error::Build { path: path.to_path_buf(), source })
}
