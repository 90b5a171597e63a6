//! The camera every picture frames a mesh with: [`tessella_core::framing`]'s, shared with the
//! web viewer (the npm package's `sceneCamera`) and the Bevy example.

pub use tessella_core::framing::{Framing, FOV_Y_DEGREES};

/// The framing of `points` that `tessella render` draws them with (their bounding sphere grown
/// by 1.2, since curved patches bulge past the coarse hull), for a renderer of its own: the Bevy
/// example's camera and light.
pub fn frame_points(points: &[[f32; 3]], yaw: f32, pitch: f32, zoom: f32, aspect: f32) -> Framing {
    Framing::points(points, 0.0, (yaw, pitch, zoom, [0.0, 0.0]), aspect)
}
