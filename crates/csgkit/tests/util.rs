//! Fixtures shared by the integration tests.

use std::path::PathBuf;

/// The shared data folder (`../shared/data` beside the repository, or `$CSGKIT_SHARED_DATA`
/// for a work tree kept elsewhere), or `None` with a message when it is absent, so tests that
/// need real data skip instead of failing.
pub fn shared_data() -> Option<PathBuf> {
    let dir = std::env::var_os("CSGKIT_SHARED_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
        PathBuf::from,
    );
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: shared data folder {} is absent", dir.display());
        None
    }
}

/// A file in the repository's own test data (`crates/csgkit/tests/data`).
pub fn repo_data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}
