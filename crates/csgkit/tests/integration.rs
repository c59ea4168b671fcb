//! Integration tests, one module per area.

mod util;

// Every shared data mesh loads with the manifest's counts; formats round-trip.
mod io_formats;
// Truncated, corrupted and random bytes make no reader panic.
mod io_fuzz;
// Exact self-intersection counts agree with the manifest's reference.
mod self_intersection;
