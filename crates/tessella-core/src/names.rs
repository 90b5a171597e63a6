//! The names of schemes, normal modes and backends, parsed and printed in this one place: the
//! CLI, the Python package and messages all use these, so a name means the same everywhere.
//!
//! | type | names |
//! |---|---|
//! | [`Scheme`] | `flat`, `phong`, `pn`, `png1`, `pn-aen`, `st`, `quadratic` |
//! | [`NormalMode`] | `linear`, `quadratic`, `real` |
//! | [`Backend`] | `auto`, `cpu`, `gpu`, `gl` |
//! | `Spacing` (in `refine`, where it is defined) | `grid`, `equal`, `fractional-odd`, `fractional-even` |
//!
//! Parsing ([`FromStr`], through [`parse_name`]) ignores ASCII case and takes `_` for `-`
//! (`PN_AEN` is `pn-aen`, a spelling that suits Python keywords); printing ([`fmt::Display`])
//! writes the name. A name that is none of these is an [`UnknownName`] listing the valid ones.
//! Phong's shape factor is not part of its name: `"phong"` parses to [`Scheme::PHONG`]
//! (alpha 3/4) and [`Scheme::with_alpha`] sets another.
//!
//! ```
//! use tessella_core::{Backend, NormalMode, Scheme};
//! let scheme: Scheme = "PN_AEN".parse()?;
//! assert_eq!(scheme, Scheme::PnAen);
//! assert_eq!(scheme.to_string(), "pn-aen");
//! assert_eq!("phong".parse::<Scheme>()?.with_alpha(0.5), Scheme::Phong { alpha: 0.5 });
//! assert_eq!("real".parse::<NormalMode>()?, NormalMode::Real);
//! assert_eq!("cpu".parse::<Backend>()?, Backend::Cpu);
//! let err = "loop".parse::<Scheme>().unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     r#"unknown scheme "loop"; use one of ["flat", "phong", "pn", "png1", "pn-aen", "st", "quadratic"]"#
//! );
//! # Ok::<(), tessella_core::UnknownName>(())
//! ```

use crate::scheme::{NormalMode, Scheme};
use std::fmt;
use std::str::FromStr;
use thiserror::Error;

/// A name that names none of the values of its kind.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown {what} {name:?}; use one of {valid:?}")]
pub struct UnknownName {
    /// The kind of value: `"scheme"`, `"normal mode"`, `"backend"`.
    pub what: &'static str,
    /// The name as given.
    pub name: String,
    /// The valid names.
    pub valid: &'static [&'static str],
}

/// A kind of value known by name on the command line, in Python and in messages.
pub trait Named: Sized + Copy + 'static {
    /// What the values are, for messages: `"scheme"`.
    const WHAT: &'static str;
    /// Every value (with default parameters), in the order help texts list them.
    const ALL: &'static [Self];
    /// The names of [`Named::ALL`], in the same order.
    const NAMES: &'static [&'static str];
    /// This value's name.
    fn name(&self) -> &'static str;
    /// One line about this value, for help texts.
    fn description(&self) -> &'static str;
}

/// The value of `T` called `text` (ASCII case ignored, `_` taken for `-`).
pub fn parse_name<T: Named>(text: &str) -> Result<T, UnknownName> {
    let wanted = text.to_ascii_lowercase().replace('_', "-");
    T::ALL
        .iter()
        .zip(T::NAMES)
        .find(|(_, name)| **name == wanted)
        .map(|(value, _)| *value)
        .ok_or_else(|| UnknownName {
            what: T::WHAT,
            name: text.to_string(),
            valid: T::NAMES,
        })
}

impl Scheme {
    /// This scheme with Phong's shape factor `alpha` (other schemes have none and are returned
    /// as they are).
    pub fn with_alpha(self, alpha: f32) -> Scheme {
        match self {
            Scheme::Phong { .. } => Scheme::Phong { alpha },
            other => other,
        }
    }
}

impl Named for Scheme {
    const WHAT: &'static str = "scheme";
    const ALL: &'static [Scheme] = &[
        Scheme::Flat,
        Scheme::PHONG,
        Scheme::Pn,
        Scheme::Png1,
        Scheme::PnAen,
        Scheme::ScalarTagged,
        Scheme::Quadratic,
    ];
    const NAMES: &'static [&'static str] =
        &["flat", "phong", "pn", "png1", "pn-aen", "st", "quadratic"];
    fn name(&self) -> &'static str {
        Scheme::name(self)
    }
    fn description(&self) -> &'static str {
        match self {
            Scheme::Flat => "The coarse triangles themselves (normals interpolated)",
            Scheme::Phong { .. } => "Phong tessellation (quadratic; shape factor alpha)",
            Scheme::Pn => "Curved PN triangles (cubic)",
            Scheme::Png1 => {
                "PNG1: tangent-plane continuous (G1) patches from each triangle and its edge \
                 neighbours"
            }
            Scheme::PnAen => {
                "PN with adjacent edge normals: crack-free PN across hard edges (split normals)"
            }
            Scheme::ScalarTagged => {
                "Scalar-tagged PN: creases and per-vertex tension, sharpness, bias (see tags)"
            }
            Scheme::Quadratic => {
                "Second-order finite elements (6-node triangles): the element's own P2 map"
            }
        }
    }
}

impl Named for NormalMode {
    const WHAT: &'static str = "normal mode";
    const ALL: &'static [NormalMode] =
        &[NormalMode::Linear, NormalMode::Quadratic, NormalMode::Real];
    const NAMES: &'static [&'static str] = &["linear", "quadratic", "real"];
    fn name(&self) -> &'static str {
        match self {
            NormalMode::Linear => "linear",
            NormalMode::Quadratic => "quadratic",
            NormalMode::Real => "real",
        }
    }
    fn description(&self) -> &'static str {
        match self {
            NormalMode::Linear => {
                "Vertex normals interpolated linearly (default for flat and phong)"
            }
            NormalMode::Quadratic => {
                "Vlachos' quadratic normals (default for pn, png1, pn-aen, st)"
            }
            NormalMode::Real => "The surface's own normal, from its derivatives",
        }
    }
}

/// Where refinement runs. The core only names it; the GPU crate, the CLI and the Python package
/// decide how (the core itself is the CPU backend).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum Backend {
    /// A hardware GPU when there is one (a software adapter is slower than the CPU), otherwise
    /// the CPU; the CPU also when the GPU fails.
    #[default]
    Auto,
    /// The CPU, all cores.
    Cpu,
    /// A GPU, a software adapter (lavapipe) included; an error when there is none.
    Gpu,
    /// The OpenGL 4 tessellation stages (tessella-gl): the hardware tessellator, so a
    /// tessellator spacing (equal, fractional-odd, fractional-even); unwelded output.
    Gl,
}

impl Named for Backend {
    const WHAT: &'static str = "backend";
    const ALL: &'static [Backend] = &[Backend::Auto, Backend::Cpu, Backend::Gpu, Backend::Gl];
    const NAMES: &'static [&'static str] = &["auto", "cpu", "gpu", "gl"];
    fn name(&self) -> &'static str {
        match self {
            Backend::Auto => "auto",
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
            Backend::Gl => "gl",
        }
    }
    fn description(&self) -> &'static str {
        match self {
            Backend::Auto => "A hardware GPU for large outputs when there is one, else the CPU",
            Backend::Cpu => "The CPU, all cores",
            Backend::Gpu => "The GPU (a software adapter is used when there is no hardware one)",
            Backend::Gl => {
                "OpenGL 4 tessellation shaders (the hardware tessellator; needs a tessellator \
                 --spacing)"
            }
        }
    }
}

impl Backend {
    /// `auto` refines outputs with fewer refined vertices than this on the CPU without looking
    /// for a GPU at all: opening a device costs more (tens to hundreds of milliseconds, plus the
    /// upload and read-back) than the CPU takes for such outputs on all cores.
    pub const AUTO_GPU_MIN_VERTICES: u64 = 1 << 20;

    /// The device this backend refines an output of `vertices` refined vertices on: the one
    /// backend choice every front end makes, with one size estimate, the plan's exact vertex
    /// count ([`Plan::vertex_count`](crate::refine::Plan::vertex_count)). `auto` looks for a
    /// hardware GPU only from [`Backend::AUTO_GPU_MIN_VERTICES`] on, and refines on the CPU
    /// when it finds none or the GPU fails ([`Backend::falls_back`]).
    ///
    /// ```
    /// use tessella_core::names::Device;
    /// use tessella_core::Backend;
    /// assert_eq!(Backend::Auto.device(10_000), Device::Cpu);
    /// assert_eq!(Backend::Auto.device(4 << 20), Device::HardwareGpu);
    /// assert_eq!(Backend::Gpu.device(1), Device::AnyGpu);
    /// ```
    pub fn device(self, vertices: u64) -> Device {
        match self {
            Backend::Auto if vertices >= Self::AUTO_GPU_MIN_VERTICES => Device::HardwareGpu,
            Backend::Auto | Backend::Cpu => Device::Cpu,
            Backend::Gpu => Device::AnyGpu,
            Backend::Gl => Device::Gl,
        }
    }

    /// Whether a GPU that fails (or is missing) leaves the work to the CPU: `auto` only; `gpu`
    /// and `gl` report the failure.
    pub fn falls_back(self) -> bool {
        self == Backend::Auto
    }
}

/// Where a [`Backend`] refines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Device {
    Cpu,
    /// A hardware GPU if there is one (a software adapter is slower than the CPU), else the CPU.
    HardwareGpu,
    /// Any GPU adapter, software included; an error when there is none.
    AnyGpu,
    /// The OpenGL 4 tessellation stages.
    Gl,
}

macro_rules! parse_and_print {
    ($($t:ty),*) => {$(
        impl FromStr for $t {
            type Err = UnknownName;
            fn from_str(text: &str) -> Result<$t, UnknownName> {
                parse_name(text)
            }
        }
        impl fmt::Display for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(Named::name(self))
            }
        }
    )*};
}
parse_and_print!(Scheme, NormalMode, Backend);

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn round_trip<
        T: Named + FromStr<Err = UnknownName> + fmt::Display + PartialEq + fmt::Debug,
    >() {
        assert_eq!(T::ALL.len(), T::NAMES.len());
        for (value, name) in T::ALL.iter().zip(T::NAMES) {
            assert_eq!(value.name(), *name);
            assert_eq!(value.to_string(), *name);
            assert_eq!(name.parse::<T>().as_ref(), Ok(value));
            assert_eq!(name.to_ascii_uppercase().parse::<T>().as_ref(), Ok(value));
            assert!(!value.description().is_empty());
        }
        let err = "nonsense".parse::<T>().unwrap_err();
        assert_eq!(err.valid, T::NAMES);
        for name in T::NAMES {
            assert!(err.to_string().contains(name), "{err}");
        }
    }

    #[test]
    fn every_name_round_trips_and_unknown_names_list_the_valid_ones() {
        round_trip::<Scheme>();
        round_trip::<NormalMode>();
        round_trip::<Backend>();
    }

    #[test]
    fn spellings_and_phong_alpha() {
        assert_eq!("pn_aen".parse::<Scheme>(), Ok(Scheme::PnAen));
        assert_eq!("St".parse::<Scheme>(), Ok(Scheme::ScalarTagged));
        assert!(" st".parse::<Scheme>().is_err());
        assert_eq!("phong".parse::<Scheme>(), Ok(Scheme::PHONG));
        assert_eq!(Scheme::Pn.with_alpha(0.5), Scheme::Pn);
        assert_eq!(
            Scheme::PHONG.with_alpha(0.25),
            Scheme::Phong { alpha: 0.25 }
        );
        assert_eq!(Scheme::Phong { alpha: 0.25 }.to_string(), "phong");
        let err = "scalar-tagged".parse::<Scheme>().unwrap_err();
        assert_eq!((err.what, err.name.as_str()), ("scheme", "scalar-tagged"));
        assert!("".parse::<Backend>().is_err());
        assert!("pn aen".parse::<Scheme>().is_err());
    }
}
