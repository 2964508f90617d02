//! SHA-256 checksums of recordings against the digests pinned in the catalog.

use std::path::Path;

use sha2::{Digest, Sha256};

use crate::catalog::CatalogEntry;
use crate::error::{DataError, Result};

/// Whether (and how strictly) to check a file's SHA-256 before parsing it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Verify {
    /// Check when the catalog pins a digest; load unpinned files unchecked (the default).
    #[default]
    IfPinned,
    /// Check, and fail with [`DataError::NoPinnedChecksum`] when no digest is pinned.
    Required,
    /// Do not hash the file (saves ~10 ms per 12 kHz record).
    Skip,
}

/// Lower-case hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    let mut s = String::with_capacity(64);
    for b in digest {
        s.push(char::from_digit(u32::from(b >> 4), 16).unwrap_or('0'));
        s.push(char::from_digit(u32::from(b & 0xF), 16).unwrap_or('0'));
    }
    s
}

/// Check `bytes` against `entry`'s pinned digest according to `mode`.
pub fn verify_bytes(entry: &CatalogEntry, bytes: &[u8], mode: Verify) -> Result<()> {
    let expected = match (mode, entry.sha256) {
        (Verify::Skip, _) | (Verify::IfPinned, None) => return Ok(()),
        (Verify::Required, None) => {
            return Err(DataError::NoPinnedChecksum {
                number: entry.number,
            });
        }
        (_, Some(e)) => e,
    };
    let found = sha256_hex(bytes);
    if found.eq_ignore_ascii_case(expected) {
        Ok(())
    } else {
        Err(DataError::ChecksumMismatch {
            number: entry.number,
            expected: expected.to_owned(),
            found,
        })
    }
}

/// State of one catalogued file on disk (what `cargo xtask data` prints).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FileStatus {
    /// Present and its SHA-256 equals the pinned digest.
    Verified,
    /// Present, but its SHA-256 differs from the pinned digest.
    Mismatch {
        /// The digest found.
        found: String,
    },
    /// Present; not hashed (verification off) or no digest pinned.
    Present,
    /// Not on disk.
    Missing,
}

/// Check the file of `entry` under the `cwru/` folder `cwru_dir`: present? verified?
///
/// With `verify == false` a present file is reported as [`FileStatus::Present`] without reading it.
pub fn check_file(cwru_dir: &Path, entry: &CatalogEntry, verify: bool) -> Result<FileStatus> {
    let path = cwru_dir.join(entry.rel_path);
    if !path.is_file() {
        return Ok(FileStatus::Missing);
    }
    let Some(expected) = entry.sha256.filter(|_| verify) else {
        return Ok(FileStatus::Present);
    };
    let bytes = std::fs::read(&path).map_err(|source| DataError::Io { path, source })?;
    let found = sha256_hex(&bytes);
    Ok(if found.eq_ignore_ascii_case(expected) {
        FileStatus::Verified
    } else {
        FileStatus::Mismatch { found }
    })
}
