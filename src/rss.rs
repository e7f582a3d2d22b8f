//! The process's resident memory, to cross-check [`crate::lod::Runtime::memory_report`]
//! against what the operating system sees. Linux only (`/proc/self/status`); `None`
//! elsewhere.

/// Resident set size now and its peak (`VmRSS`, `VmHWM`), in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Resident {
    /// Bytes resident now.
    pub current: usize,
    /// The most bytes ever resident in this process.
    pub peak: usize,
}

/// Reads the process's resident memory, or `None` where `/proc/self/status` is missing.
pub fn resident() -> Option<Resident> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |name: &str| -> Option<usize> {
        let line = status.lines().find(|l| l.starts_with(name))?;
        let kb: usize = line[name.len()..].trim().trim_end_matches("kB").trim().parse().ok()?;
        Some(kb * 1024)
    };
    Some(Resident { current: field("VmRSS:")?, peak: field("VmHWM:")? })
}

#[cfg(test)]
mod tests {
    /// Other tests of this process allocate and free at the same time (a runtime frees
    /// ~15 MB when it drops), which can hide part of the growth in one reading; a few tries
    /// tell that apart from a reading that does not see allocations at all.
    #[test]
    fn resident_memory_grows_with_a_touched_allocation() {
        let mut seen = Vec::new();
        for _ in 0..5 {
            let Some(before) = super::resident() else { return };
            let big = vec![1u8; 64 << 20];
            let after = super::resident().unwrap();
            assert!(after.peak >= after.current);
            assert_eq!(big.iter().map(|&b| b as usize).sum::<usize>(), 64 << 20);
            if after.current >= before.current + (48 << 20) {
                return;
            }
            seen.push((before, after));
        }
        panic!("a touched 64 MiB allocation never showed: {seen:?}");
    }
}
