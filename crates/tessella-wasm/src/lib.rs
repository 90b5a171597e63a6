//! # tessella-wasm
//!
//! The Rust half of the npm package `tessella` (`js/`): wasm-bindgen exports over flat typed
//! arrays. `js/src/index.js` wraps them into the documented API (`refine`, `Refiner`,
//! `readMesh`, `writeMesh`, `readAnimated`, `refineGltf` (a whole glTF scene, `scene.rs`),
//! `TessellaError`, `sceneCamera` (the framing of tessella's pictures, `framing.rs`), and
//! `InstancedSurface` and
//! `AdaptiveSurface`, what `tessella/three`'s `TessellatedMesh` draws from, with one level or
//! with `lod`); nothing here is meant to be
//! called directly.
//!
//! Every input is validated before any work (`arrays.rs`, `options.rs`, the core's `Mesh::new`
//! and `Plan::new`), so bad input comes back as a thrown JS `Error` with the core's message,
//! never as a trap. A panic would be a bug: [`start`] installs a hook that throws it as a JS error
//! instead of `RuntimeError: unreachable` (the JS side then refuses further calls, since a
//! panicked instance's state is not trustworthy).
//!
//! The crate also builds natively (a workspace member), so its option and array handling is
//! tested by `cargo test` like the rest.

mod adaptive;
mod animated;
mod arrays;
mod deformer;
mod errors;
mod files;
mod framing;
mod gpu_nets;
mod instanced;
mod naga_check;
mod nets_wgsl;
mod options;
mod refine;
mod refiner;
mod scene;
#[cfg(test)]
mod test_meshes;

use wasm_bindgen::prelude::*;

/// Runs when the module is instantiated: panics throw a JS `Error` (prefixed
/// `errors::PANIC_PREFIX`) instead of trapping.
#[wasm_bindgen(start)]
pub fn start() {
    std::panic::set_hook(Box::new(|info| {
        wasm_bindgen::throw_str(&format!("{}{info}", errors::PANIC_PREFIX))
    }));
}

/// The scheme names `refine` accepts, in the core's order.
#[wasm_bindgen]
pub fn schemes() -> Vec<String> {
    use tessella_core::{Named, Scheme};
    Scheme::NAMES.iter().map(|s| s.to_string()).collect()
}

/// The widest texture the package lays out (texels a row: nets, LOD records and instances,
/// corner attributes): WebGL2's guaranteed 2048, so three.js's layouts read it here.
#[wasm_bindgen(js_name = "maxTextureWidth")]
pub fn max_texture_width() -> usize {
    instanced::MAX_TEXTURE_WIDTH
}

/// Panics on purpose, so the JS tests can check that a panic is thrown as an error (and that
/// the package refuses further calls). Not part of the documented API.
#[wasm_bindgen(js_name = "__panicForTests")]
pub fn panic_for_tests() {
    panic!("a deliberate panic for the tests");
}
