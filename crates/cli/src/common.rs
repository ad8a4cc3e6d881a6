//! What every command shares: its result type, the worker pool and JSON
//! output.

pub type CliResult = Result<(), Box<dyn std::error::Error>>;

pub fn thread_pool(
    threads: Option<usize>,
) -> Result<rayon::ThreadPool, Box<dyn std::error::Error>> {
    let n = fogbank::renderer::threads_or_all(threads)
        .map_err(|_| "--threads must be at least 1".to_string())?;
    Ok(rayon::ThreadPoolBuilder::new().num_threads(n).build()?)
}

/// Writes `v` as pretty JSON with a final newline, naming the file on error.
pub fn write_json(path: &std::path::Path, v: &serde_json::Value) -> CliResult {
    std::fs::write(path, serde_json::to_string_pretty(v)? + "\n")
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}
