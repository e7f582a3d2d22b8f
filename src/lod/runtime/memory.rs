//! [`Runtime::memory_report`]: the bytes of every structure the runtime holds, beside n and m
//! (papers/001 §"Data Structures": 46n + 72m). docs/BENCHMARKS.md, "Memory", has the figures.

use super::Runtime;
use crate::view::{Frustum, View, Viewpoint};

/// Bytes held per structure, from [`Runtime::memory_report`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MemoryReport {
    /// (structure, bytes).
    pub entries: Vec<(&'static str, usize)>,
    /// Original vertices n.
    pub vertices: usize,
    /// Live vertices m.
    pub active_vertices: usize,
}

impl MemoryReport {
    /// Sum of all entries.
    pub fn total(&self) -> usize {
        self.entries.iter().map(|e| e.1).sum()
    }
}

impl Runtime {
    /// Every structure's bytes, with n and m.
    pub fn memory_report(&self) -> MemoryReport {
        let t = &self.mesh.topology;
        let w = &self.mesh.wedges;
        let mut entries = vec![
            ("mesh.positions", self.mesh.positions.capacity() * 12),
            ("topology.faces", t.faces.capacity() * 12),
            ("topology.twin", t.twin.capacity() * 4),
            ("topology.vertex_he", t.vertex_he.capacity() * 4),
            ("topology.vflags", t.vflags.capacity()),
            ("wedges.corner", w.corner_bytes()),
            ("wedges.attributes", w.attribute_bytes()),
            ("wedges.source", w.source_bytes()),
            ("mesh.face_primitive", self.mesh.primitive_bytes()),
            ("mesh.sources", self.mesh.vertex_source.bytes() + self.mesh.face_source.bytes()),
            ("runtime.normals", self.normals.capacity() * 12),
            ("runtime.anchor_floor", self.floor.bytes()),
            (
                "runtime.flags",
                self.in_r.capacity()
                    + self.stays.capacity()
                    + self.cand.capacity()
                    + [&self.seen, &self.ignored, &self.blocked_before].map(|b| b.capacity() / 8).iter().sum::<usize>()
                    + self.flagged.capacity() * 4,
            ),
            ("runtime.live", self.live.bytes()),
            ("runtime.rebalance_tried", self.rebalance_tried.bytes()),
            ("runtime.scratch", self.scratch.bytes()),
            (
                "runtime.views",
                self.views.capacity() * size_of::<View>()
                    + self.frustums.capacity() * size_of::<Frustum>()
                    + self.eyes.capacity() * size_of::<Viewpoint>()
                    + self.view_order.bytes(),
            ),
        ];
        entries.extend(self.hierarchy.memory());
        entries.extend(self.index.memory());
        MemoryReport { entries, vertices: t.vertex_count(), active_vertices: self.live.len() }
    }
}
