//! # dynlod
//!
//! An incremental, view-dependent progressive-mesh runtime. This first layer is the
//! foundation every later pass stands on:
//!
//! * [`io`] reads OBJ, PLY (faces and triangle strips), OFF, STL and glTF/GLB into an
//!   [`IndexedMesh`], and writes OBJ, binary PLY and GLB atomically;
//! * [`Mesh::build`] welds vertices by position while keeping per-corner attribute wedges,
//!   repairs what can be repaired without guessing (and records it), and builds the compact
//!   [`topology::Topology`] that the parallel passes and GPU kernels will edit;
//! * [`topology::Topology::validate`] checks every connectivity invariant.
//!
//! ```no_run
//! let indexed = dynlod::io::load("bunny.ply")?;
//! let mesh = dynlod::Mesh::build(&indexed, dynlod::BuildOptions::default())?;
//! mesh.topology.validate()?;
//! println!("{} vertices, {} repairs", mesh.positions.len(), mesh.repairs.len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Papers implemented by this crate (see docs/ALGORITHM.md): Odaker et al. 2015 (parallel
//! half-edge collapse), Merrin & Shah (dynamic vertex hierarchies), Jia et al. (dihedral-angle
//! cost with multiple-choice selection).

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
