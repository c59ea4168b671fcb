#![no_main]
//! See `csgkit_fuzz::check_vox`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| csgkit_fuzz::check_vox(data));
