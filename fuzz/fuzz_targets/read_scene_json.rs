#![no_main]
//! See `csgkit_fuzz::check_scene_json`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| csgkit_fuzz::check_scene_json(data));
