//! How much memory a job may use when `--max-memory` is not given.

/// The memory the system reports as available (Linux `/proc/meminfo` `MemAvailable`), or
/// `None` where that is not known (the job then runs without a cap).
pub fn available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}
