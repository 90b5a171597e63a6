//! The tessellation program: the generated and written GLSL of one spacing (`shaders.rs`),
//! compiled and linked once per context ([`crate::GlContext`] keeps it).

use crate::error::GlError;
use crate::shaders::glsl_sources;
use glow::HasContext;
use tessella_core::tessellator::Partitioning;

/// Compiles the four stages of `spacing`'s program and links them, with the transform feedback
/// varyings the read-back takes; a compile or link failure is an error with the driver's log.
pub(crate) fn link(gl: &glow::Context, spacing: Partitioning) -> Result<glow::Program, GlError> {
    let src = glsl_sources(spacing);
    // SAFETY: GL calls on the current context.
    unsafe {
        let program = gl.create_program().map_err(GlError::Unsupported)?;
        let mut shaders = Vec::new();
        let stages = [
            (glow::VERTEX_SHADER, "vertex", &src.vertex),
            (
                glow::TESS_CONTROL_SHADER,
                "tessellation control",
                &src.control,
            ),
            (
                glow::TESS_EVALUATION_SHADER,
                "tessellation evaluation",
                &src.evaluation,
            ),
            (glow::FRAGMENT_SHADER, "fragment", &src.fragment),
        ];
        for (kind, stage, text) in stages {
            let s = gl.create_shader(kind).map_err(GlError::Unsupported)?;
            gl.shader_source(s, text);
            gl.compile_shader(s);
            if !gl.get_shader_compile_status(s) {
                let log = gl.get_shader_info_log(s);
                gl.delete_shader(s);
                for s in shaders {
                    gl.delete_shader(s);
                }
                gl.delete_program(program);
                return Err(GlError::Compile { stage, log });
            }
            gl.attach_shader(program, s);
            shaders.push(s);
        }
        gl.transform_feedback_varyings(
            program,
            &["tf_position", "tf_normal", "tf_coord", "tf_face"],
            glow::INTERLEAVED_ATTRIBS,
        );
        gl.link_program(program);
        for s in shaders {
            gl.detach_shader(program, s);
            gl.delete_shader(s);
        }
        if !gl.get_program_link_status(program) {
            let log = gl.get_program_info_log(program);
            gl.delete_program(program);
            return Err(GlError::Link { log });
        }
        Ok(program)
    }
}
