//! The refinement options of `refine` and `render`, from their flags through the core's text
//! form ([`tessella_core::refine::OPTION_KEYS`]): `--level 5.5` is `level=5.5`, parsed by
//! [`RefineOptions::from_pairs`] as Python's `level=5.5`, npm's `{ level: 5.5 }` and the
//! viewer's `?level=5.5` are. A bad value's message names the flag.

use crate::args::ShapeArgs;
use tessella_core::refine::{Ask, Spacing};
use tessella_core::{Named, RefineOptions};

/// The option flags as given.
pub struct Flags<'a> {
    /// `--scheme`, `--alpha` and `--normals`.
    pub shape: ShapeArgs,
    pub level: f64,
    pub spacing: Spacing,
    pub lod: Option<&'a str>,
    /// `--camera` as given, or the picture's own camera for `render`.
    pub camera: Option<String>,
    pub size: Option<(u32, u32)>,
    pub soup: bool,
    pub max_memory: Option<u64>,
}

impl Flags<'_> {
    /// The flags as `key=value` pairs: a LOD replaces `--level`, which always has a value.
    pub fn pairs(&self) -> Vec<(&'static str, String)> {
        let mut pairs = vec![
            ("scheme", self.shape.scheme.0.name().to_string()),
            ("alpha", self.shape.alpha.to_string()),
            ("spacing", self.spacing.to_string()),
            ("soup", self.soup.to_string()),
        ];
        match self.lod {
            Some(lod) => pairs.push(("lod", lod.to_string())),
            None => pairs.push(("level", self.level.to_string())),
        }
        if let Some(camera) = &self.camera {
            pairs.push(("camera", camera.clone()));
        }
        if let Some((w, h)) = self.size {
            pairs.push(("size", format!("{w}x{h}")));
        }
        if let Some(normals) = self.shape.normals {
            pairs.push(("normals", normals.0.name().to_string()));
        }
        if let Some(bytes) = self.max_memory {
            pairs.push(("max-memory", bytes.to_string()));
        }
        pairs
    }

    /// The options these flags ask for.
    pub fn parse(&self) -> anyhow::Result<RefineOptions> {
        RefineOptions::from_pairs(self.pairs())
            .map_err(|e| anyhow::anyhow!("--{}: {}", e.key, e.message))
    }
}

/// An ask as the CLI's flags spell it, for a conflict's message.
fn flag(ask: Ask) -> String {
    match ask {
        Ask::FractionalLevel => "a fractional --level".into(),
        Ask::PerEdgeLevels => "per-edge levels".into(),
        Ask::Origin => "--write-origin".into(),
        Ask::Uvs => "texture coordinates".into(),
        Ask::GlBackend => "--backend gl".into(),
        other => format!("--{}", other.key()),
    }
}

/// Refuses `asks` with these options where the core's rules say they cannot go together
/// ([`RefineOptions::conflict`]), in the CLI's spelling.
pub fn refuse_conflicts(
    options: &RefineOptions,
    asks: impl IntoIterator<Item = Ask>,
) -> anyhow::Result<()> {
    options
        .conflict(asks)
        .map_err(|c| anyhow::anyhow!(c.message(flag)))
}
