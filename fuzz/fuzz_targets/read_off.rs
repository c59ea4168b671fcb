#![no_main]
//! The Off reader on any bytes: see `csgkit_fuzz::check_reader`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| csgkit_fuzz::check_reader(data, csgkit::Format::Off));
