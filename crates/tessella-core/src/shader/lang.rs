//! The languages the generated code is printed in.

/// A shading language the generated code is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Lang {
    /// WebGPU's WGSL.
    Wgsl,
    /// GLSL 4.30 (the OpenGL tessellation backend).
    Glsl,
}
