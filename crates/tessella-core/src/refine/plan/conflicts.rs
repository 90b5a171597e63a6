//! Which asks cannot go together, written once for every front end. The levels' kind comes
//! from the [`RefineOptions`] themselves; a front end adds what else a call asked for
//! ([`Ask::Displace`], [`Ask::Origin`], [`Ask::Uvs`], [`Ask::GlBackend`]) and gets the first
//! [`Conflict`], which it words with its own spelling of the two asks (`--displace`,
//! `displace=`) in the one sentence [`Conflict::message`] makes.
//!
//! ```
//! use tessella_core::refine::{Ask, Spacing};
//! use tessella_core::{RefineOptions, Scheme};
//! let odd = RefineOptions::new(Scheme::Pn, 3).with_spacing(Spacing::FractionalOdd);
//! let conflict = odd.conflict([Ask::Displace]).unwrap_err();
//! let cli = |ask: Ask| format!("--{}", ask.key());
//! assert_eq!(
//!     conflict.message(cli),
//!     "--displace cannot be combined with --spacing (displacement follows the uniform grid's \
//!      output layout, a whole level on the grid pattern)"
//! );
//! assert!(RefineOptions::new(Scheme::Pn, 3).conflict([Ask::Displace]).is_ok());
//! ```

use super::levels::{Levels, Spacing};
use super::options::RefineOptions;

/// One thing a refinement is asked for that another may exclude.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Ask {
    /// A hardware tessellator spacing instead of the grid (from the options).
    Spacing,
    /// One level for every edge that is not a whole number (from the options).
    FractionalLevel,
    /// Per-edge levels from a LOD function (from the options).
    Lod,
    /// Per-edge levels given edge by edge (from the options).
    PerEdgeLevels,
    /// Displacement along the normals.
    Displace,
    /// Each refined vertex's coarse face and barycentric coordinates.
    Origin,
    /// Texture coordinates carried onto the refined vertices.
    Uvs,
    /// The OpenGL 4 tessellator backend.
    GlBackend,
}

impl Ask {
    /// The ask's key in the options' text form and the CLI's flags (`spacing`, `level`,
    /// `lod`, `displace`, `origin`, `uvs`, `backend`): a front end's spelling starts there.
    pub fn key(self) -> &'static str {
        match self {
            Ask::Spacing => "spacing",
            Ask::FractionalLevel | Ask::PerEdgeLevels => "level",
            Ask::Lod => "lod",
            Ask::Displace => "displace",
            Ask::Origin => "origin",
            Ask::Uvs => "uvs",
            Ask::GlBackend => "backend",
        }
    }
}

/// Two asks that cannot go together, and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Conflict {
    /// The ask the rule is about (displacement, say).
    pub ask: Ask,
    /// The ask it cannot be combined with.
    pub with: Ask,
    /// Why, in words that name no front end's spelling.
    pub why: &'static str,
}

impl Conflict {
    /// `"{ask} cannot be combined with {with} ({why})"`, the asks spelt by `spell`.
    pub fn message(&self, spell: impl Fn(Ask) -> String) -> String {
        format!(
            "{} cannot be combined with {} ({})",
            spell(self.ask),
            spell(self.with),
            self.why
        )
    }
}

impl std::fmt::Display for Conflict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message(|a| a.key().to_string()))
    }
}

impl std::error::Error for Conflict {}

/// A rule: `ask` excludes each of `with`.
struct Rule {
    ask: Ask,
    with: &'static [Ask],
    why: &'static str,
}

/// The rules, in the order they are checked. Each is a limit of the core or of a backend, so
/// every front end that can ask both refuses the pair.
const RULES: &[Rule] = &[
    Rule {
        ask: Ask::Displace,
        with: &[
            Ask::Spacing,
            Ask::FractionalLevel,
            Ask::Lod,
            Ask::PerEdgeLevels,
        ],
        why: "displacement follows the uniform grid's output layout, a whole level on the grid \
              pattern",
    },
    Rule {
        ask: Ask::Displace,
        with: &[Ask::GlBackend],
        why: "the GL tessellator has no displacement stage; the CPU and GPU backends displace",
    },
    Rule {
        ask: Ask::Origin,
        with: &[Ask::GlBackend],
        why: "the GL tessellator does not report origins; the CPU backend does",
    },
    Rule {
        ask: Ask::Uvs,
        with: &[Ask::GlBackend],
        why: "the GL tessellator does not carry texture coordinates; the CPU backend does",
    },
];

impl RefineOptions {
    /// The asks the levels make: a tessellator spacing, a fractional level, LOD or per-edge
    /// levels (none for a whole level on the grid).
    pub fn level_asks(&self) -> Vec<Ask> {
        let mut asks = Vec::new();
        if self.spacing != Spacing::Grid {
            asks.push(Ask::Spacing);
        }
        match &self.levels {
            Levels::Uniform(x) if x.fract() != 0.0 => asks.push(Ask::FractionalLevel),
            Levels::Uniform(_) => {}
            Levels::Lod(_) => asks.push(Ask::Lod),
            Levels::PerEdge { .. } => asks.push(Ask::PerEdgeLevels),
        }
        asks
    }

    /// The first pair among these options' [`level_asks`](RefineOptions::level_asks) and
    /// `asks` that cannot go together, checked in the rules' order. A front end lists what it
    /// may have been asked for as options (`[displace.then_some(Ask::Displace), ...]`, flattened).
    pub fn conflict(&self, asks: impl IntoIterator<Item = Ask>) -> Result<(), Conflict> {
        let all: Vec<Ask> = self.level_asks().into_iter().chain(asks).collect();
        for rule in RULES {
            if !all.contains(&rule.ask) {
                continue;
            }
            if let Some(&with) = rule.with.iter().find(|w| all.contains(w)) {
                return Err(Conflict {
                    ask: rule.ask,
                    with,
                    why: rule.why,
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::Lod;
    use crate::Scheme;

    #[test]
    fn each_rule_refuses_its_pairs_and_nothing_else() {
        let grid = RefineOptions::new(Scheme::Pn, 4);
        let adaptive = [
            (grid.clone().with_spacing(Spacing::Equal), Ask::Spacing),
            (grid.clone().with_uniform_level(4.5), Ask::FractionalLevel),
            (
                grid.clone().with_levels(Levels::Lod(Lod::Tolerance {
                    max_deviation: 0.01,
                })),
                Ask::Lod,
            ),
        ];
        for (options, level_ask) in &adaptive {
            assert_eq!(options.level_asks(), vec![*level_ask]);
            let c = options.conflict([Ask::Displace]).unwrap_err();
            assert_eq!((c.ask, c.with), (Ask::Displace, *level_ask));
            // Origins and texture coordinates go with any levels.
            assert!(options.conflict([Ask::Origin, Ask::Uvs]).is_ok());
        }
        for ask in [Ask::Displace, Ask::Origin, Ask::Uvs] {
            assert!(grid.conflict([ask]).is_ok());
            let c = grid.conflict([Ask::GlBackend, ask]).unwrap_err();
            assert_eq!((c.ask, c.with), (ask, Ask::GlBackend));
        }
        assert!(grid.conflict([Ask::GlBackend]).is_ok());
        // The levels' rule comes first: both are named in the order of the rules.
        let both = adaptive[0].0.conflict([Ask::GlBackend, Ask::Displace]);
        assert_eq!(both.unwrap_err().with, Ask::Spacing);
    }
}
