//! A tessellated entity's surface as drawn: what posing moves, the LOD reads and picking casts
//! rays against.

use bevy::prelude::*;
use std::sync::Arc;
use tessella_core::refine::{Frame, Plan};

/// A tessellated entity's surface as drawn: the plan and the current frame (posed, for an
/// animated entity), with a count that changes whenever the frame does.
#[derive(Component)]
pub(crate) struct Surface {
    pub plan: Arc<Plan>,
    pub frame: Frame<'static>,
    pub version: u64,
}
