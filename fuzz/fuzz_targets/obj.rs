#![no_main]
use libfuzzer_sys::fuzz_target;
use tessella_io::{fuzzing, Format};

fuzz_target!(|data: &[u8]| {
    fuzzing::check_reader(Format::Obj, data);
});
