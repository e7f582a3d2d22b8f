//! [`Hierarchy::check`]: the per-face counters, tops, blocked counts and front recounted
//! from the records, with auditing every stack walked entry by entry.

use super::Hierarchy;
use crate::topology::{Topology, INVALID};

impl Hierarchy {
    /// Recounts the counters, tops, blocked counts and front membership from the records and
    /// compares them with the maintained values; names the first disagreement. `t`: the mesh
    /// this hierarchy belongs to.
    ///
    /// Every record must be on top of as many faces as it touched less its blocked count.
    /// Every record on top of all its faces is walked from the mesh: it must name exactly
    /// the faces it keeps entries for, and be on top of each. With auditing, every record's
    /// faces are known besides, and every face's stack is walked entry by entry. Without, the
    /// buried records are checked through sums: each face's stack holds its counter's worth
    /// of entries, so the counters add up to the entries kept, and every entry below a top
    /// blocks its record once.
    pub fn check(&self, t: &Topology) -> Result<(), String> {
        let mut tops = vec![0u32; self.records.len()];
        for &r in self.top.iter().filter(|&&r| r != INVALID) {
            if let Some(n) = tops.get_mut(r as usize) {
                *n += 1;
            }
        }
        let mut entries = 0u64;
        let mut on_front = 0usize;
        for u in 0..self.records.len() as u32 {
            let r = &self.records[u as usize];
            if r.target == INVALID {
                continue;
            }
            entries += u64::from(r.touched);
            // Blocked counts the faces where u is not on top.
            if u32::from(r.touched) != tops[u as usize] + u32::from(self.blocked[u as usize]) {
                return Err(format!(
                    "record {u}: on top of {} faces and blocked {} times, but it touched {}",
                    tops[u as usize], self.blocked[u as usize], r.touched
                ));
            }
            let on_top = self.blocked[u as usize] == 0;
            if on_top && !self.front.is_listed(u) {
                return Err(format!("record {u}: on top of all its faces but not on the front"));
            }
            if !on_top {
                continue;
            }
            on_front += 1;
            let mut walked = 0usize;
            let mut deepest = 0;
            let mut kept = r.slab as usize;
            for f in self.faces_on_top(t, u) {
                if f as usize >= self.top.len() || self.top[f as usize] != u {
                    return Err(format!("record {u}: on the front but not on top of face {f}"));
                }
                if let Some(audit) = &self.audit {
                    if audit[u as usize].get(walked).map(|e| e.0) != Some(f) {
                        return Err(format!("record {u}: face {f} walked from the mesh is not its entry {walked}"));
                    }
                }
                // The record below, kept where the face had one: a collapsed record it blocks.
                if self.counter[f as usize] > 1 {
                    let below = self.arena.get(kept).copied().unwrap_or(INVALID);
                    if below == u || !self.is_collapsed(below) || self.blocked[below as usize] == 0 {
                        return Err(format!("record {u}: face {f}'s record below, {below}, is not a blocked record"));
                    }
                    kept += 1;
                }
                walked += 1;
                deepest = deepest.max(self.counter[f as usize]);
                if walked > r.touched as usize {
                    break;
                }
            }
            if deepest != r.depth {
                return Err(format!("record {u}: depth {} kept, {deepest} on its faces", r.depth));
            }
            if walked != r.touched as usize {
                return Err(format!("record {u}: {walked} faces walked from the mesh, {} entries kept", r.touched));
            }
        }
        if on_front != self.front.len() {
            return Err(format!("{on_front} records on top of all their faces, the front counts {}", self.front.len()));
        }
        let mut stacked = 0u64;
        let mut below_tops = 0u64;
        for (f, (&c, &top)) in self.counter.iter().zip(&self.top).enumerate() {
            if (c == 0) != (top == INVALID) || (top != INVALID && !self.is_collapsed(top)) {
                return Err(format!("face {f}: counter {c} but top {top}"));
            }
            stacked += u64::from(c);
            below_tops += u64::from(c.saturating_sub(1));
        }
        if stacked != entries {
            return Err(format!("the face counters add up to {stacked}, the records keep {entries} entries"));
        }
        let blocked: u64 =
            (0..self.records.len()).filter(|&u| self.is_collapsed(u as u32)).map(|u| u64::from(self.blocked[u])).sum();
        if blocked != below_tops {
            return Err(format!(
                "records are blocked {blocked} times, the stacks hold {below_tops} entries below a top"
            ));
        }
        if let Some(audit) = &self.audit {
            self.check_audited(audit)?;
        }
        Ok(())
    }

    /// The full recount [`Hierarchy::check`] makes with auditing: every record's faces from
    /// the audit, every face's stack walked down from its top, and the arena compared with
    /// the audit's entries (all but the bottoms, in order).
    fn check_audited(&self, audit: &[Vec<(u32, u32)>]) -> Result<(), String> {
        let of = |u: u32| {
            let r = &self.records[u as usize];
            audit[u as usize].iter().copied().take(if r.target == INVALID { 0 } else { r.touched as usize })
        };
        let mut count = vec![0u32; self.counter.len()];
        for u in 0..self.records.len() as u32 {
            let r = &self.records[u as usize];
            if r.target != INVALID && audit[u as usize].len() != r.touched as usize {
                return Err(format!("record {u}: {} audited entries, {} touched", audit[u as usize].len(), r.touched));
            }
            for (k, (f, below)) in of(u).filter(|e| e.1 != INVALID).enumerate() {
                if self.arena.get(r.slab as usize + k) != Some(&below) {
                    return Err(format!("record {u}: face {f}'s record below is {below}, the arena keeps another"));
                }
            }
            for (f, _) in of(u) {
                count[f as usize] += 1;
            }
        }
        for (f, (&c, &n)) in self.counter.iter().zip(&count).enumerate() {
            if u32::from(c) != n {
                return Err(format!("face {f}: counter {c}, but {n} active records touch it"));
            }
            // Walking down the stack from the top must meet exactly `n` records, each touching f.
            let (mut r, mut seen) = (self.top[f], 0);
            while r != INVALID {
                let below = of(r).find(|e| e.0 == f as u32).ok_or(format!("face {f}: top {r} does not touch it"))?.1;
                seen += 1;
                r = below;
                if seen > n {
                    break;
                }
            }
            if seen != n {
                return Err(format!("face {f}: stack holds {seen} records, {n} touch it"));
            }
        }
        // Blocked counts need no second look: `check` has each record on top of `touched −
        // blocked` faces, and the walks above have every top among its record's faces.
        Ok(())
    }
}
