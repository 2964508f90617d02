//! Where the data lives: one setting (`--data-dir` / `HYBRID_FDD_DATA`), defaulting to
//! `../shared/data` beside the workspace when that exists.

use std::path::{Path, PathBuf};

use crate::error::{DataError, Result};

/// Environment variable naming the data directory (the one holding `cwru/`).
pub const DATA_DIR_ENV: &str = "HYBRID_FDD_DATA";

/// The resolved data directory, or the fact that there is none.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DataLocation {
    /// The data directory (it holds `cwru/`).
    Found(PathBuf),
    /// No directory was given and the default does not exist.
    Absent {
        /// The default location that was looked at.
        searched: PathBuf,
    },
}

impl DataLocation {
    /// Resolve the data directory: an explicit `flag` (CLI `--data-dir` or `HYBRID_FDD_DATA`)
    /// must exist, else [`DataError::DataDirNotFound`]; without one, `workspace_root/../shared/data`
    /// is used when it is a directory, else the result is [`DataLocation::Absent`].
    pub fn resolve(flag: Option<&Path>, workspace_root: &Path) -> Result<Self> {
        match flag {
            Some(p) if p.is_dir() => Ok(Self::Found(p.to_path_buf())),
            Some(p) => Err(DataError::DataDirNotFound {
                path: p.to_path_buf(),
            }),
            None => {
                let default = workspace_root.join("..").join("shared").join("data");
                if default.is_dir() {
                    Ok(Self::Found(default))
                } else {
                    Ok(Self::Absent { searched: default })
                }
            }
        }
    }

    /// [`resolve`](Self::resolve) with the flag taken from `HYBRID_FDD_DATA` (for tests and
    /// tools without a CLI). An empty variable counts as unset.
    pub fn from_env(workspace_root: &Path) -> Result<Self> {
        let flag = std::env::var_os(DATA_DIR_ENV)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from);
        Self::resolve(flag.as_deref(), workspace_root)
    }

    /// The data directory, if found.
    pub fn path(&self) -> Option<&Path> {
        match self {
            Self::Found(p) => Some(p),
            Self::Absent { .. } => None,
        }
    }

    /// The `cwru/` folder inside the data directory, if found.
    pub fn cwru_dir(&self) -> Option<PathBuf> {
        self.path().map(|p| p.join("cwru"))
    }

    /// The data directory, or `Ok(None)` ("skip") when absent, or [`DataError::DataAbsent`] when
    /// absent and `ci` is set (`CI=true`: missing data fails instead of skipping).
    pub fn require(&self, ci: bool) -> Result<Option<&Path>> {
        match self {
            Self::Found(p) => Ok(Some(p)),
            Self::Absent { searched } if ci => Err(DataError::DataAbsent {
                searched: searched.clone(),
            }),
            Self::Absent { .. } => Ok(None),
        }
    }

    /// The data directory, or [`DataError::DataAbsent`].
    pub fn required(&self) -> Result<&Path> {
        match self {
            Self::Found(p) => Ok(p),
            Self::Absent { searched } => Err(DataError::DataAbsent {
                searched: searched.clone(),
            }),
        }
    }
}

/// Whether the `CI` environment variable asks for strict behaviour (`true` or `1`).
pub fn ci_from_env() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}
