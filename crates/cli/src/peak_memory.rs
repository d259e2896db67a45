//! The closing line of every benchmark: the peak resident memory, so its memory claims can be
//! read beside its speed.

/// VmHWM in kB (`oficina_app::bench::peak_memory_kb`).
pub(crate) fn vm_hwm_kb() -> Option<u64> {
    oficina_app::bench::peak_memory_kb()
}

/// The closing line of a benchmark: `peak memory (VmHWM): 12345 kB`.
pub(crate) fn print() {
    match vm_hwm_kb() {
        Some(kb) => println!("peak memory (VmHWM): {kb} kB"),
        None => println!("peak memory (VmHWM): unavailable (no /proc/self/status)"),
    }
}
