//! Integration tests, one module per area.

mod util;

// The discrete engine against brute-force voxel oracles.
mod discrete_cases;
// Every shared data mesh loads with the manifest's counts; formats round-trip.
mod io_formats;
// Truncated, corrupted and random bytes make no reader panic.
mod io_fuzz;
