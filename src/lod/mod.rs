//! The view-dependent level-of-detail passes (papers/000, papers/001). Each pass is a pure
//! per-element function driven by rayon, the CPU reference for the GPU kernels to come.
//!
//! * [`passes`]: the vertex analysis of papers/000 §3 with its layered grid anchors, the
//!   boundary planes of §4.1–4.3 and the per-candidate selection of §4.4 / §5;
//! * [`coarsen`]: rounds of parallel collapses from a full mesh (offline, one view);
//! * [`hierarchy`]: papers/001's collapse records and per-face counters, the vertex split;
//! * [`runtime`]: the frame-to-frame [`Runtime`] that splits and collapses under a moving
//!   camera, with [`rebalance`] (papers/001 Figure 4) and the renderer's [`IndexBuffer`];
//! * [`scene_runtime`]: a glTF scene kept as it is, one runtime per mesh serving every node
//!   that draws it.

pub mod coarsen;
pub mod hierarchy;
pub mod index_buffer;
mod input_error;
mod lazy_list;
pub mod passes;
pub mod rebalance;
pub mod runtime;
mod scene_budget;
mod scene_groups;
pub mod scene_runtime;
mod scene_stretch;

pub use index_buffer::{IndexBuffer, IndexPart};
pub use input_error::InputError;
pub use runtime::{Cut, FrameStats, FrameStop, MemoryReport, Runtime, RuntimeOptions, CUT_FRAMES};
pub use scene_runtime::{SceneMeshRuntime, SceneRuntime, SceneRuntimeError};
