//! What one `refine` made: its message, `--report` and `batch`'s rows read it.

use tessella_core::RefineOptions;

/// What one refinement made.
pub struct Refined {
    /// The coarse mesh (none for a glTF scene, refined primitive by primitive).
    pub mesh: Option<tessella_core::Mesh>,
    pub options: RefineOptions,
    pub input_triangles: usize,
    pub vertices: u64,
    pub triangles: u64,
    /// Scheme and level, for messages.
    pub what: String,
    /// Seconds spent refining (and, when streamed, writing).
    pub refine_seconds: f64,
    /// Whether the output was written piece by piece.
    pub streamed: bool,
}
