//! What every command shares: its result type, the worker pool and the
//! peak-memory probe.

pub type CliResult = Result<(), Box<dyn std::error::Error>>;

/// Peak resident set size of this process (Linux `VmHWM`), 0 elsewhere.
pub fn peak_memory_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| {
                l.split_whitespace()
                    .nth(1)
                    .and_then(|kb| kb.parse::<u64>().ok())
                    .map(|kb| kb * 1024)
            })
        })
        .unwrap_or(0)
}

pub fn thread_pool(
    threads: Option<usize>,
) -> Result<rayon::ThreadPool, Box<dyn std::error::Error>> {
    let n = threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    if n == 0 {
        return Err("--threads must be at least 1".into());
    }
    Ok(rayon::ThreadPoolBuilder::new().num_threads(n).build()?)
}

/// Writes `v` as pretty JSON with a final newline, naming the file on error.
pub fn write_json(path: &std::path::Path, v: &serde_json::Value) -> CliResult {
    std::fs::write(path, serde_json::to_string_pretty(v)? + "\n")
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}
