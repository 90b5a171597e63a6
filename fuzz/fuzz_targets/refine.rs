#![no_main]
//! `refine` on small meshes and options built from the input: an error, or finite output with
//! valid indices.
use libfuzzer_sys::fuzz_target;
use tessella_io::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::check_refine(data);
});
