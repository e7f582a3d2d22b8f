//! The view-dependent level-of-detail passes (papers/000, papers/001). Each pass is a pure
//! per-element function driven by rayon, the CPU reference for the GPU kernels to come.
//!
//! Present so far: the vertex analysis of papers/000 §3 ([`passes::classify`]) with its layered
//! grid anchors ([`passes::anchors`]), the boundary planes of §4.1–4.3 ([`passes::boundaries`])
//! and the per-candidate selection of §4.4 with §5's test-1-only result ([`passes::select`]).
//! The round driver (candidates, parallel selection, application keeping the round manifold,
//! deadlock flags, §6 reclassification) and the vertex splits (papers/001) build on these.

pub mod coarsen;
pub mod passes;
