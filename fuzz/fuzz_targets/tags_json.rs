#![no_main]
use libfuzzer_sys::fuzz_target;
use tessella_io::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::check_tags_json(data);
});
