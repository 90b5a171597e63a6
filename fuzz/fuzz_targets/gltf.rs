#![no_main]
//! glTF JSON and GLB: the reader tells them apart by the GLB magic, as for a file.
use libfuzzer_sys::fuzz_target;
use tessella_io::{fuzzing, Format};

fuzz_target!(|data: &[u8]| {
    let format = if data.starts_with(b"glTF") {
        Format::Glb
    } else {
        Format::Gltf
    };
    fuzzing::check_reader(format, data);
});
