//! Shared context of every task: workspace root and where the data lives.
//!
//! Tasks that need the CWRU data call [`Context::data_dir`] (an error when there is none) or
//! [`Context::data_dir_or_skip`] (`None` = print a skip message, except under `CI=true`). The
//! resolution itself lives in `bearing_data::DataLocation`.

use std::path::{Path, PathBuf};

use bearing_data::DataLocation;

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
    /// Where the data lives: `Found(dir)` (dir holds `cwru/`) or `Absent`.
    pub data: DataLocation,
}

impl Context {
    /// Build the context from the global flags. An explicit `--data-dir` / `HYBRID_FDD_DATA`
    /// that is not a directory is an error here; a missing default is not (see [`Self::data_dir`]).
    pub fn new(g: &GlobalArgs) -> anyhow::Result<Self> {
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .map(PathBuf::from)
            .ok_or_else(|| anyhow::anyhow!("xtask has no parent directory"))?;
        let ci = bearing_data::ci_from_env();
        let data = DataLocation::resolve(g.data_dir.as_deref(), &root)?;
        Ok(Self {
            root,
            data_dir_flag: g.data_dir.clone(),
            ci,
            data,
        })
    }

    /// The data directory (holds `cwru/`); pass it to `bearing_data::load_record`.
    /// Errors with a clear message when no data directory was found.
    #[allow(dead_code)] // used by the pipeline tasks
    pub fn data_dir(&self) -> anyhow::Result<&Path> {
        Ok(self.data.required()?)
    }

    /// The data directory, or `Ok(None)` when it is absent (the caller prints a skip message);
    /// under `CI=true` an absent directory is an error instead.
    #[allow(dead_code)] // used by the pipeline tasks
    pub fn data_dir_or_skip(&self) -> anyhow::Result<Option<&Path>> {
        Ok(self.data.require(self.ci)?)
    }
}
