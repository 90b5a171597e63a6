//! The tests' check of generated WGSL: naga parses and validates it (the naga wgpu brings in),
//! and a failure panics with naga's report on the source and `what` it was.
#![cfg(test)]

pub(crate) fn validate_wgsl(source: &str, what: &str) {
    let parsed = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&parsed)
    .unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(source)));
}
