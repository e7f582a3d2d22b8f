//! The process's resident memory, to cross-check [`crate::lod::Runtime::memory_report`]
//! against what the operating system sees. Linux only (`/proc/self/status`); `None`
//! elsewhere.
//!
//! For a tight cross-check, read it while the structures counted are alive, after
//! [`trim_heap`]: the allocator otherwise keeps what loading and the cold start freed,
//! which the OS still counts as resident.

/// The process's resident memory, in bytes (`/proc/self/status`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Resident {
    /// All resident pages now (`VmRSS`): the heap, and the binary's code and the files
    /// mapped as far as they have been read.
    pub current: usize,
    /// Resident anonymous pages now (`RssAnon`): the heap, thread stacks, no file-backed
    /// pages. What the process's own data structures can account for.
    pub anon: usize,
    /// The most pages ever resident in this process (`VmHWM`).
    pub peak: usize,
}

/// Reads the process's resident memory, or `None` where `/proc/self/status` (or, before
/// Linux 4.5, its `RssAnon` line) is missing.
pub fn resident() -> Option<Resident> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |name: &str| -> Option<usize> {
        let line = status.lines().find(|l| l.starts_with(name))?;
        let kb: usize = line[name.len()..].trim().trim_end_matches("kB").trim().parse().ok()?;
        Some(kb * 1024)
    };
    Some(Resident { current: field("VmRSS:")?, anon: field("RssAnon:")?, peak: field("VmHWM:")? })
}

/// Hands the allocator's free memory back to the OS, so the resident set shows what is
/// held rather than what was once used. glibc only (`malloc_trim`), where it returns
/// `true`; elsewhere it does nothing and returns `false`.
pub fn trim_heap() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: `malloc_trim` takes no pointers and only returns free pages of glibc's
        // own heaps to the OS; it is safe to call at any time from any thread.
        unsafe { libc::malloc_trim(0) };
        true
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        false
    }
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
            assert!(after.peak >= after.current && after.current >= after.anon);
            assert_eq!(big.iter().map(|&b| b as usize).sum::<usize>(), 64 << 20);
            if after.anon >= before.anon + (48 << 20) {
                return;
            }
            seen.push((before, after));
        }
        panic!("a touched 64 MiB allocation never showed: {seen:?}");
    }
}
