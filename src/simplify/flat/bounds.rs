//! Each vertex's bound: its cheapest allowed target and that collapse's cost, as the last pass
//! that found it stale worked it out (flat/mod.rs).

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering::Relaxed};

use crate::topology::INVALID;

/// Per vertex, the target (`INVALID`: no allowed target) and the cost's bits. Relaxed atomics,
/// so that the pass that works the bounds out stores each vertex's own as it goes (a serial
/// loop storing them afterwards read what the other threads had just written); nothing reads
/// a bound in the pass that writes it.
pub(super) struct Bounds {
    target: Vec<AtomicU32>,
    cost: Vec<AtomicU64>,
}

impl Bounds {
    /// `n` vertices without a bound.
    pub fn new(n: usize) -> Self {
        Self {
            target: (0..n).map(|_| AtomicU32::new(INVALID)).collect(),
            cost: (0..n).map(|_| AtomicU64::new(0)).collect(),
        }
    }

    /// v's bound: (cost, target), `None` when v has no allowed target. (Test builds check
    /// the kept bounds with it.)
    #[cfg(test)]
    pub fn get(&self, v: u32) -> Option<(f64, u32)> {
        let t = self.target[v as usize].load(Relaxed);
        (t != INVALID).then(|| (f64::from_bits(self.cost[v as usize].load(Relaxed)), t))
    }

    /// v's bound as (cost, target), with `INVALID` for none (the cost is then meaningless):
    /// `Bounds::get` without a branch.
    pub fn get_or_none(&self, v: u32) -> (f64, u32) {
        (f64::from_bits(self.cost[v as usize].load(Relaxed)), self.target[v as usize].load(Relaxed))
    }

    /// v's cheapest target (`INVALID`: none).
    pub fn target(&self, v: u32) -> u32 {
        self.target[v as usize].load(Relaxed)
    }

    /// Sets v's bound.
    pub fn set(&self, v: u32, b: Option<(f64, u32)>) {
        let (cost, t) = b.unwrap_or((0.0, INVALID));
        self.cost[v as usize].store(cost.to_bits(), Relaxed);
        self.target[v as usize].store(t, Relaxed);
    }
}
