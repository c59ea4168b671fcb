//! Integration tests, one module per area.

// Each test module uses a different part of the fixtures.
#[allow(dead_code)]
mod util;

/// The discrete engine against brute-force voxel oracles.
mod discrete_cases;
