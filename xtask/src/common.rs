//! Shared context of every task: workspace root and where the data lives.

use std::path::PathBuf;

/// Flags every task accepts.
#[derive(clap::Args, Debug)]
pub struct GlobalArgs {
    /// Directory holding `cwru/` (defaults to `../shared/data` beside the workspace when it exists).
    #[arg(long, env = "HYBRID_FDD_DATA", global = true)]
    pub data_dir: Option<PathBuf>,
}

/// Resolved context handed to every task.
#[derive(Debug)]
pub struct Context {
    /// Workspace root (parent of `xtask/`).
    pub root: PathBuf,
    /// The data directory the user asked for, if any (resolution happens in `bearing-data`).
    pub data_dir_flag: Option<PathBuf>,
    /// `CI=true`: missing data is an error, not a skip.
    pub ci: bool,
}

impl Context {
    /// Build the context from the global flags.
    pub fn new(g: &GlobalArgs) -> anyhow::Result<Self> {
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .map(PathBuf::from)
            .ok_or_else(|| anyhow::anyhow!("xtask has no parent directory"))?;
        let ci = std::env::var("CI").map(|v| v == "true" || v == "1").unwrap_or(false);
        Ok(Self { root, data_dir_flag: g.data_dir.clone(), ci })
    }
}
