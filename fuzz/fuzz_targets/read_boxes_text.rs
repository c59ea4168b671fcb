#![no_main]
//! See `csgkit_fuzz::check_boxes_text`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| csgkit_fuzz::check_boxes_text(data));
