//! What every command shares: its result type and JSON output.

pub type CliResult = Result<(), Box<dyn std::error::Error>>;

/// Writes `v` as pretty JSON with a final newline, naming the file on error.
pub fn write_json(path: &std::path::Path, v: &serde_json::Value) -> CliResult {
    std::fs::write(path, serde_json::to_string_pretty(v)? + "\n")
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}
