//! # tessella-regression
//!
//! A test-only crate: the regression suite every refining backend runs, after OpenSubdiv's
//! regression suite. Its tests (`tests/regression/`) define one check and run it for each
//! implementation of `tessella_core::refine::Evaluator`: the CPU's `CpuEvaluator`, the GPU
//! compute `GpuEvaluator` (wgpu; lavapipe in CI) and the GL `GlEvaluator` (the hardware
//! tessellator through EGL; llvmpipe in CI). Every output vertex is compared, at its coarse
//! face and barycentric point, with the independent f64 evaluation in
//! `tessella-core/tests/reference` over the shared corpus of meshes
//! (`tessella-core/tests/reference/corpus.rs`), for flat, Phong and PN with linear,
//! quadratic and real normals, on the grid pattern and the hardware spacings; displaced
//! output is compared with an f64 displacement of the reference. Run it with
//! `cargo test -p tessella-regression` (it is part of `cargo test --workspace`).
//!
//! The crate has no code of its own.
