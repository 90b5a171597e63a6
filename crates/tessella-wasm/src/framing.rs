//! The camera the viewer and `tessella render` frame a mesh with ([`tessella_core::framing`]),
//! for the web page's own renderers: one definition, not a port.

use crate::{arrays, errors};
use tessella_core::framing::Framing;
use wasm_bindgen::prelude::*;

/// Numbers [`scene_camera`] returns.
const FRAMING_LEN: usize = 36;

/// The framing of `positions` (3 per vertex) seen from `view` = `[yaw, pitch, zoom, aspect,
/// reach, pan_x, pan_y]` (degrees; `aspect` width over height; `reach` added to the grown
/// radius; pan in framed radii). Returns 36 numbers: `viewProj` (16, column-major, wgpu's clip
/// depth), then `eye`, `target`, `lightDir`, `right`, `up` (the view's), `forward` (3 each),
/// then `distance` and the vertical field of view in degrees. The npm package's `sceneCamera`
/// unpacks them.
#[wasm_bindgen(js_name = "sceneCamera")]
pub fn scene_camera(positions: &[f32], view: &[f32]) -> Result<Vec<f32>, JsError> {
    let points = arrays::as_points(positions, "positions").map_err(errors::text)?;
    framing(points, view)
        .map(|f| pack(&f).to_vec())
        .map_err(errors::text)
}

fn framing(points: &[[f32; 3]], view: &[f32]) -> Result<Framing, String> {
    let &[yaw, pitch, zoom, aspect, reach, pan_x, pan_y] = view else {
        return Err(format!(
            "a view is 7 numbers (yaw, pitch, zoom, aspect, reach, pan x, pan y), not {}",
            view.len()
        ));
    };
    if let Some(x) = view.iter().find(|x| !x.is_finite()) {
        return Err(format!("the view's numbers must be finite, not {x}"));
    }
    if !(zoom > 0.0 && aspect > 0.0 && reach >= 0.0) {
        return Err(format!("zoom and aspect must be positive and reach not negative (zoom {zoom}, aspect {aspect}, reach {reach})"));
    }
    if let Some(p) = points.iter().find(|p| !p.iter().all(|x| x.is_finite())) {
        return Err(format!("positions must be finite, not {p:?}"));
    }
    Ok(Framing::points(
        points,
        reach,
        (yaw, pitch, zoom, [pan_x, pan_y]),
        aspect,
    ))
}

fn pack(f: &Framing) -> [f32; FRAMING_LEN] {
    let mut out = [0.0; FRAMING_LEN];
    let vectors = [f.eye, f.target, f.light_dir, f.right, f.view_up, f.forward];
    let values = f.view_proj.iter().flatten().chain(vectors.iter().flatten());
    let last = [f.distance, tessella_core::framing::FOV_Y_DEGREES];
    for (o, &v) in out.iter_mut().zip(values.chain(&last)) {
        *o = v;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_packed_framing_is_the_cores() {
        let points = [[0.0, 0.0, 0.0], [1.0, 2.0, 0.5], [-1.0, 0.5, 2.0]];
        let view = [30.0, 20.0, 1.5, 1.25, 0.1, 0.2, -0.1];
        let f = Framing::points(&points, 0.1, (30.0, 20.0, 1.5, [0.2, -0.1]), 1.25);
        let packed = pack(&framing(&points, &view).unwrap());
        assert_eq!(packed[..16], f.view_proj.concat()[..]);
        assert_eq!(packed[16..19], f.eye[..]);
        assert_eq!(packed[28..31], f.view_up[..]);
        assert_eq!(packed[31..34], f.forward[..]);
        assert_eq!(packed[34..], [f.distance, 30.0]);
    }

    #[test]
    fn bad_views_are_errors() {
        let points = [[0.0, 0.0, 0.0]];
        for (view, says) in [
            (&[0.0; 6][..], "7 numbers"),
            (&[0.0, 0.0, 1.0, 1.0, 0.0, f32::NAN, 0.0][..], "finite"),
            (&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0][..], "positive"),
            (&[0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0][..], "positive"),
        ] {
            let e = framing(&points, view).unwrap_err();
            assert!(e.contains(says), "{e}");
        }
        let e = framing(
            &[[f32::INFINITY, 0.0, 0.0]],
            &[0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0],
        );
        assert!(e.unwrap_err().contains("finite"));
    }
}
