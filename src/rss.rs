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
    #[test]
    fn resident_memory_grows_with_a_touched_allocation() {
        let Some(before) = super::resident() else { return };
        let big = vec![1u8; 64 << 20];
        let after = super::resident().unwrap();
        assert!(after.current >= before.current + (48 << 20), "{before:?} -> {after:?}");
        assert!(after.peak >= after.current);
        assert_eq!(big.iter().map(|&b| b as usize).sum::<usize>(), 64 << 20);
    }
}
