//! The view-dependent level-of-detail passes (papers/000, papers/001). Each pass is a pure
//! per-element function driven by rayon, the CPU reference for the GPU kernels to come.
//!
//! Present so far: the vertex analysis of papers/000 §3 ([`passes::classify`]) with its layered
//! grid anchors ([`passes::anchors`]). The parallel collapse rounds (§4–§6) and the vertex
//! splits (papers/001) build on these.

pub mod passes;
