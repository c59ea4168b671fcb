#![no_main]
//! See `csgkit_fuzz::check_openscad_csg`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| csgkit_fuzz::check_openscad_csg(data));
