//! Helpers every test binary shares: where the repository's files are, whichever
//! package hosts the binary (the library, the command line or the harness).
#![allow(dead_code)] // each test binary uses a different subset

use std::path::{Path, PathBuf};

/// The repository root: the nearest folder above the hosting package that holds
/// `missions/`.
pub fn repo_root() -> PathBuf {
    let package = Path::new(env!("CARGO_MANIFEST_DIR"));
    package
        .ancestors()
        .find(|dir| dir.join("missions").is_dir())
        .unwrap_or(package)
        .to_path_buf()
}

/// A file of the repository, from its path relative to the root.
pub fn repo_path(relative: &str) -> PathBuf {
    repo_root().join(relative)
}
