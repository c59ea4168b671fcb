#![no_main]
//! The exact engine on small random solids: see `csgkit_fuzz::solids::check_case`.

libfuzzer_sys::fuzz_target!(
    |case: csgkit_fuzz::solids::Case| csgkit_fuzz::solids::check_case(&case)
);
