//! The layout constants Rust and WGSL share, written once here and prepended to every shader
//! as WGSL `const`s (the `.wgsl` files declare none of them), so the two cannot drift apart.

use crate::gpu_types::{normal_mode_code, NORMAL_NET_BYTES};
use tessella_core::NormalMode;

/// The shared constants as WGSL source.
pub(crate) fn source() -> String {
    [
        ("TESSELLA_NORMAL_NET_LEN", NORMAL_NET_BYTES as u32 / 12),
        ("TESSELLA_EDGE_ROWS_AT", crate::canonical::ROWS_AT as u32),
        ("TESSELLA_EDGE_ROW_LEN", crate::canonical::ROW_LEN as u32),
        ("TESSELLA_MODE_REAL", normal_mode_code(NormalMode::Real)),
    ]
    .iter()
    .map(|(name, value)| format!("const {name}: u32 = {value}u;\n"))
    .collect()
}
