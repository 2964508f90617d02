//! Helpers shared by the close-loop tests that read the shared CWRU data.

use bearing_data::DataLocation;
use std::path::{Path, PathBuf};

/// The shared data directory (`HYBRID_FDD_DATA` or `../shared/data`), `None` when it is absent —
/// which fails the test under `CI=true` and skips `what` otherwise.
pub fn data_dir(what: &str) -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let loc = DataLocation::resolve(None, &root).ok()?;
    match loc.required() {
        Ok(dir) => Some(dir.to_path_buf()),
        Err(e) => {
            assert!(
                std::env::var("CI").as_deref() != Ok("true"),
                "CWRU data required under CI=true: {e}"
            );
            eprintln!("skipping {what}: {e}");
            None
        }
    }
}
