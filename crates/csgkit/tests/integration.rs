//! Integration tests, one module per area.

mod util;

// Every shared data mesh loads with the manifest's counts; formats round-trip.
mod io_formats;
// Truncated, corrupted and random bytes make no reader panic.
mod io_fuzz;
// Every shared data mesh analysed: topology and measures agree with the manifest.
mod real_data;
