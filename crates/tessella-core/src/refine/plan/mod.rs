//! The layer built once per topology and levels: everything a [`Plan`] holds and how it is
//! made. Nothing here imports the evaluator (`refine::cpu`), which sits on top.
//!
//! - [`options`]: what to refine into ([`RefineOptions`](options::RefineOptions)),
//!   [`options_text`], its `key=value` text form that every front end parses, and
//!   [`conflicts`], which asks cannot go together;
//! - [`levels`], [`lod`]: the levels asked for and the LOD functions that compute them;
//! - [`tiling`], [`instanced`], [`morph`], [`canonical`]: adaptive plans' per-face patterns,
//!   their instanced parts, geomorphs and canonical edge weights; [`grid_point`], a grid
//!   point's snap and geomorph sources, written once for the CPU and the shaders; [`driver`], an instanced
//!   renderer's per-frame levels and instances; [`packed`], its records packed for a texture;
//! - [`layout`], [`indices`], [`pieces`], [`stream`]: where the output's vertices go, its
//!   triangles, and its cut into pieces; [`sizes`], what a plan's buffers are sized by;
//! - [`surface`]: topology and scheme, which build each frame's nets;
//! - [`table`]: the [`Plan`](table::Plan) itself.

pub mod canonical;
pub mod conflicts;
pub mod driver;
pub(crate) mod grid_point;
pub mod indices;
pub mod instanced;
pub mod layout;
pub mod levels;
pub mod lod;
pub mod morph;
pub mod options;
pub mod options_text;
pub mod packed;
pub mod pieces;
pub mod sizes;
pub mod stream;
pub mod surface;
pub mod table;
pub mod tiling;
