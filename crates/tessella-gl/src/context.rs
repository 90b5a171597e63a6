//! A headless OpenGL 4 core context through EGL: Mesa's surfaceless platform first, then the
//! default display; no window, no surface (`EGL_KHR_surfaceless_context`).

use crate::error::GlError;
use glow::HasContext;
use khronos_egl as egl;

/// `EGL_PLATFORM_SURFACELESS_MESA`.
const PLATFORM_SURFACELESS_MESA: egl::Enum = 0x31DD;

/// What the driver says about itself.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DriverInfo {
    pub vendor: String,
    pub renderer: String,
    pub version: String,
    /// `GL_MAX_TESS_GEN_LEVEL` (at least 64 by the specification).
    pub max_tess_level: i32,
}

impl DriverInfo {
    /// True for Mesa's software rasterisers (llvmpipe, softpipe): time ratios only.
    pub fn is_software(&self) -> bool {
        let r = self.renderer.to_ascii_lowercase();
        r.contains("llvmpipe") || r.contains("softpipe") || r.contains("swrast")
    }
}

/// An OpenGL 4.3+ core context, current on the thread that made it (GL contexts belong to one
/// thread; make one per thread).
pub struct GlContext {
    // Field order: the GL function table goes first, then the context, then the library.
    gl: glow::Context,
    info: DriverInfo,
    /// The tessellation programs, one per hardware spacing, linked on first use and shared by
    /// every tessellator and evaluator on this context (freed with the context).
    programs: std::cell::RefCell<[Option<glow::Program>; 3]>,
    display: egl::Display,
    context: egl::Context,
    egl: egl::DynamicInstance<egl::EGL1_4>,
}

fn no_driver(what: impl Into<String>) -> GlError {
    GlError::NoDriver { what: what.into() }
}

/// `error`, the reason a start-up failed, with the failure of the clean-up that followed it (if
/// any) added to its message: the first error is the one to report, the second is not lost.
fn after_cleanup(error: GlError, cleanup: Result<(), egl::Error>, step: &str) -> GlError {
    match (error, cleanup) {
        (error, Ok(())) => error,
        (GlError::NoDriver { what }, Err(e)) => {
            no_driver(format!("{what}; {step} also failed ({e})"))
        }
        (error, Err(_)) => error,
    }
}

impl GlContext {
    /// Loads `libEGL.so.1`, opens a display without a window system and makes a 4.5 (else 4.3)
    /// core context current on this thread.
    pub fn new() -> Result<GlContext, GlError> {
        Self::with_library("libEGL.so.1")
    }

    /// [`GlContext::new`] with the EGL library at `library` (a file name or path).
    pub fn with_library(library: &str) -> Result<GlContext, GlError> {
        // SAFETY: loading an EGL library; its initialisers are trusted like any driver.
        let egl =
            unsafe { egl::DynamicInstance::<egl::EGL1_4>::load_required_from_filename(library) }
                .map_err(|e| no_driver(format!("{library} could not be loaded ({e})")))?;
        let display = Self::display(&egl)?;
        egl.initialize(display)
            .map_err(|e| no_driver(format!("eglInitialize failed ({e})")))?;
        // The display is not terminated on failure, nor when a context is dropped: EGL gives
        // every caller in the process the *same* display for the same platform, and
        // eglTerminate is not reference-counted, so one context terminating it broke every
        // other context of the process (tests on parallel threads failed to make theirs
        // current). The driver releases the display when the process ends.
        let (context, gl) = Self::make_context(&egl, display)?;
        // SAFETY: the context is current on this thread.
        let info = unsafe {
            DriverInfo {
                vendor: gl.get_parameter_string(glow::VENDOR),
                renderer: gl.get_parameter_string(glow::RENDERER),
                version: gl.get_parameter_string(glow::VERSION),
                max_tess_level: gl.get_parameter_i32(glow::MAX_TESS_GEN_LEVEL),
            }
        };
        let ctx = GlContext {
            gl,
            info,
            programs: Default::default(),
            display,
            context,
            egl,
        };
        let v = ctx.gl.version();
        if (v.major, v.minor) < (4, 3) {
            return Err(no_driver(format!(
                "the driver offers OpenGL {}.{} ({}), the backend needs 4.3 (tessellation shaders \
                 and storage buffers)",
                v.major, v.minor, ctx.info.renderer
            )));
        }
        Ok(ctx)
    }

    fn display(egl: &egl::DynamicInstance<egl::EGL1_4>) -> Result<egl::Display, GlError> {
        if let Some(egl15) = egl.upcast::<egl::EGL1_5>() {
            // SAFETY: the surfaceless platform takes no native display.
            let d = unsafe {
                egl15.get_platform_display(
                    PLATFORM_SURFACELESS_MESA,
                    egl::DEFAULT_DISPLAY,
                    &[egl::ATTRIB_NONE],
                )
            };
            if let Ok(d) = d {
                if egl.initialize(d).is_ok() {
                    return Ok(d);
                }
            }
        }
        // SAFETY: EGL_DEFAULT_DISPLAY is always a valid argument.
        unsafe { egl.get_display(egl::DEFAULT_DISPLAY) }
            .ok_or_else(|| no_driver("EGL has no display (neither surfaceless nor default)"))
    }

    fn make_context(
        egl: &egl::DynamicInstance<egl::EGL1_4>,
        display: egl::Display,
    ) -> Result<(egl::Context, glow::Context), GlError> {
        egl.bind_api(egl::OPENGL_API)
            .map_err(|e| no_driver(format!("EGL cannot bind the desktop OpenGL API ({e})")))?;
        let attrs = [
            egl::SURFACE_TYPE,
            egl::DONT_CARE,
            egl::RENDERABLE_TYPE,
            egl::OPENGL_BIT,
            egl::NONE,
        ];
        let config = egl
            .choose_first_config(display, &attrs)
            .map_err(|e| no_driver(format!("eglChooseConfig failed ({e})")))?
            .ok_or_else(|| no_driver("EGL offers no configuration for desktop OpenGL"))?;
        let mut last = String::new();
        for (major, minor) in [(4, 5), (4, 3)] {
            let ctx_attrs = [
                egl::CONTEXT_MAJOR_VERSION,
                major,
                egl::CONTEXT_MINOR_VERSION,
                minor,
                egl::CONTEXT_OPENGL_PROFILE_MASK,
                egl::CONTEXT_OPENGL_CORE_PROFILE_BIT,
                egl::NONE,
            ];
            match egl.create_context(display, config, None, &ctx_attrs) {
                Ok(ctx) => {
                    if let Err(e) = egl.make_current(display, None, None, Some(ctx)) {
                        let error = no_driver(format!(
                            "the context cannot be made current without a surface \
                             (EGL_KHR_surfaceless_context: {e})"
                        ));
                        let cleanup = egl.destroy_context(display, ctx);
                        return Err(after_cleanup(error, cleanup, "eglDestroyContext"));
                    }
                    // SAFETY: the context is current; symbols come from the same driver.
                    let gl = unsafe {
                        glow::Context::from_loader_function(|s| {
                            egl.get_proc_address(s)
                                .map_or(std::ptr::null(), |p| p as *const _)
                        })
                    };
                    return Ok((ctx, gl));
                }
                Err(e) => last = format!("{e}"),
            }
        }
        Err(no_driver(format!(
            "EGL could not create an OpenGL 4.3 core context ({last})"
        )))
    }

    /// The GL function table.
    pub fn gl(&self) -> &glow::Context {
        &self.gl
    }
    /// Vendor, renderer, version, tessellation limit.
    pub fn info(&self) -> &DriverInfo {
        &self.info
    }

    /// The tessellation program for `spacing`, linked on first use and kept: tessellators and
    /// evaluators on this context share it.
    pub(crate) fn program(
        &self,
        spacing: tessella_core::tessellator::Partitioning,
    ) -> Result<glow::Program, GlError> {
        let i = match spacing {
            tessella_core::tessellator::Partitioning::Equal => 0,
            tessella_core::tessellator::Partitioning::FractionalOdd => 1,
            tessella_core::tessellator::Partitioning::FractionalEven => 2,
        };
        if let Some(p) = self.programs.borrow()[i] {
            return Ok(p);
        }
        let p = crate::program::link(&self.gl, spacing)?;
        if let Err(e) = self.check("linking the tessellation program") {
            // SAFETY: the program was made on this context and is not kept.
            unsafe { self.gl.delete_program(p) };
            return Err(e);
        }
        self.programs.borrow_mut()[i] = Some(p);
        Ok(p)
    }

    /// How many tessellation programs this context has linked (at most one per spacing).
    pub fn linked_programs(&self) -> usize {
        self.programs.borrow().iter().flatten().count()
    }

    /// `Err` naming `call` when GL has recorded an error (all pending errors are cleared).
    pub fn check(&self, call: &'static str) -> Result<(), GlError> {
        // SAFETY: plain state query on the current context.
        let code = unsafe { self.gl.get_error() };
        if code == glow::NO_ERROR {
            return Ok(());
        }
        // Clear the rest so the next check starts clean.
        for _ in 0..16 {
            // SAFETY: as above.
            if unsafe { self.gl.get_error() } == glow::NO_ERROR {
                break;
            }
        }
        Err(GlError::Gl {
            call,
            code,
            name: error_name(code),
        })
    }
}

fn error_name(code: u32) -> &'static str {
    match code {
        glow::INVALID_ENUM => "GL_INVALID_ENUM",
        glow::INVALID_VALUE => "GL_INVALID_VALUE",
        glow::INVALID_OPERATION => "GL_INVALID_OPERATION",
        glow::INVALID_FRAMEBUFFER_OPERATION => "GL_INVALID_FRAMEBUFFER_OPERATION",
        glow::OUT_OF_MEMORY => "GL_OUT_OF_MEMORY",
        _ => "unknown",
    }
}

impl Drop for GlContext {
    fn drop(&mut self) {
        // A drop has no caller to return a failed release to (and the driver frees what is
        // left when the process ends), so a failure is reported on stderr, once per step. The
        // display stays initialised: other contexts of the process share it (see `with_library`).
        let steps = [
            (
                "eglMakeCurrent",
                self.egl.make_current(self.display, None, None, None),
            ),
            (
                "eglDestroyContext",
                self.egl.destroy_context(self.display, self.context),
            ),
        ];
        for (step, result) in steps {
            if let Err(e) = result {
                eprintln!("tessella-gl: releasing the GL context: {step} failed ({e})");
            }
        }
    }
}
