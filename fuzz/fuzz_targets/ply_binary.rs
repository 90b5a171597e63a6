#![no_main]
//! Binary PLY: the input's first byte picks little- or big-endian, the rest follows a fixed
//! `ply` / `format binary_... 1.0` start.
use libfuzzer_sys::fuzz_target;
use tessella_io::{fuzzing, Format};

fuzz_target!(|data: &[u8]| {
    fuzzing::check_reader(Format::Ply, &fuzzing::ply_input(true, data));
});
