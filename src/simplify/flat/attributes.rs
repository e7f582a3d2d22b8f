//! The attribute part of the flat passes' costs, with attributes weighted: the wedges'
//! attribute quadrics (simplify/attribute_quadric.rs) and, per wedge, its own term
//! A_w(p_v, s_w), which every collapse onto w adds. That term changes only when w's quadric
//! grows, after a walk, so it is kept rather than evaluated for every target.

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::simplify::attribute_quadric::AttributeQuadrics;

pub(super) struct Attributes {
    quadrics: AttributeQuadrics,
    own: Vec<f64>,
}

impl Attributes {
    pub fn new(quadrics: AttributeQuadrics, mesh: &Mesh) -> Self {
        let own = (0..mesh.wedges.len() as u32).into_par_iter().map(|w| quadrics.own_cost(mesh, w)).collect();
        Self { quadrics, own }
    }

    /// The attribute part of a collapse into a vertex at `pv` through the wedge `map` of the
    /// faces on its edge ([`AttributeQuadrics::cost_of`], bit for bit).
    pub fn cost(&self, map: [(u32, u32); 2], pv: DVec3) -> f64 {
        let (pairs, n) = AttributeQuadrics::distinct(map);
        self.quadrics.cost_of_kept(&pairs[..n], pv, &self.own)
    }

    /// The same for a single pair (an edge that is no seam).
    pub fn cost_of_pair(&self, pair: (u32, u32), pv: DVec3) -> f64 {
        self.quadrics.cost_of_kept(&[pair], pv, &self.own)
    }

    /// Adds each wedge of a collapse's `map` to the one it maps onto, and refreshes that
    /// one's own term. A pass's collapses have disjoint ends, so the order of its merges does
    /// not matter.
    pub fn merge(&mut self, map: [(u32, u32); 2], mesh: &Mesh) {
        let (pairs, n) = AttributeQuadrics::distinct(map);
        self.quadrics.merge(&pairs[..n]);
        for &(_, into) in &pairs[..n] {
            self.own[into as usize] = self.quadrics.own_cost(mesh, into);
        }
    }

    /// The quadrics, back to the engine.
    pub fn into_quadrics(self) -> AttributeQuadrics {
        self.quadrics
    }
}
