#![no_main]
//! ASCII PLY: the input follows a fixed `ply` / `format ascii 1.0` start, so every run reaches
//! the element declarations and the ascii body.
use libfuzzer_sys::fuzz_target;
use tessella_io::{fuzzing, Format};

fuzz_target!(|data: &[u8]| {
    fuzzing::check_reader(Format::Ply, &fuzzing::ply_input(false, data));
});
