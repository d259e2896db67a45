//! The peak resident memory of this process (Linux's VmHWM), printed by every benchmark so
//! its memory claims can be read beside its speed.

/// VmHWM in kB, from /proc/self/status; `None` where there is no such file.
pub fn vm_hwm_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let l = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    l.split_whitespace().nth(1)?.parse().ok()
}

/// The closing line of a benchmark: `peak memory (VmHWM): 12345 kB`.
pub fn print() {
    match vm_hwm_kb() {
        Some(kb) => println!("peak memory (VmHWM): {kb} kB"),
        None => println!("peak memory (VmHWM): unavailable (no /proc/self/status)"),
    }
}
