//! `fogbank report DIR`: one offline HTML page for a folder of runs.

use crate::common::CliResult;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct ReportArgs {
    /// Folder holding the outputs of `stats`, `converge`, `experiment`, ...
    pub dir: PathBuf,
}

pub fn run(a: ReportArgs) -> CliResult {
    let page = fogbank::report::write_report(&a.dir)?;
    println!("wrote {}", page.display());
    Ok(())
}
