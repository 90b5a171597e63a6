//! The GPU side of displacement: what `shaders/displace.wgsl` reads. The formulas and the
//! direction rule live in `tessella_core::displace`, from which the WGSL is generated.
//!
//! `displace_data` holds Perlin's permutation (512 entries) or the height map's texels, then,
//! from `DisplaceParams::faces_at`, one record per coarse face: `mask, M1, M2, M3` (10 floats,
//! [`FaceFrame`]). Records start zeroed (mask 0: every vertex along its normal) and are written
//! per frame by [`face_records`] (see `PatchBuffers::update_displace_faces`).

use crate::gpu_types::DisplaceParams;
pub(crate) use tessella_core::displace::Displacement;
use tessella_core::displace::FaceFrame;

/// Floats per face record in `displace_data`.
pub(crate) const FACE_RECORD_LEN: usize = 10;

/// `DisplaceParams::faces_at` when there are no face records (no displacement).
pub(crate) const NO_FACES: u32 = u32::MAX;

/// `DISPLACE_KIND` of `d` in `displace.wgsl`: 0 none, 1 sine, 2 Perlin, 3 height map.
pub(crate) fn kind_code(d: &Displacement) -> u32 {
    match d {
        Displacement::None => 0,
        Displacement::Sine { .. } => 1,
        Displacement::Perlin { .. } => 2,
        Displacement::HeightMap { .. } => 3,
    }
}

/// The uniform and the data buffer contents for `displace.wgsl`, with room for `face_count`
/// zeroed face records after the displacement's own data (none without displacement).
pub(crate) fn gpu_data(d: &Displacement, face_count: usize) -> (DisplaceParams, Vec<f32>) {
    let mut params = DisplaceParams {
        amplitude: 0.0,
        frequency: 0.0,
        map_width: 1,
        map_height: 1,
        faces_at: NO_FACES,
        _pad: [0; 3],
    };
    let mut data = match d {
        Displacement::None => return (params, vec![0.0]),
        Displacement::Sine {
            amplitude,
            frequency,
        } => {
            (params.amplitude, params.frequency) = (*amplitude, *frequency);
            vec![0.0]
        }
        Displacement::Perlin {
            amplitude,
            frequency,
            seed,
        } => {
            (params.amplitude, params.frequency) = (*amplitude, *frequency);
            tessella_core::displace::permutation(*seed)
                .iter()
                .map(|&x| x as f32)
                .collect()
        }
        Displacement::HeightMap { amplitude, map } => {
            params.amplitude = *amplitude;
            (params.map_width, params.map_height) = (map.width, map.height);
            map.heights.clone()
        }
    };
    params.faces_at = data.len() as u32;
    data.resize(data.len() + face_count * FACE_RECORD_LEN, 0.0);
    (params, data)
}

/// The face records of `faces`, as `displace.wgsl` reads them: `mask` (a small whole number,
/// exact in f32), then the three position means.
pub(crate) fn face_records(faces: &[FaceFrame]) -> Vec<f32> {
    let mut out = Vec::with_capacity(faces.len() * FACE_RECORD_LEN);
    for face in faces {
        out.push(face.mask as f32);
        out.extend(face.means.iter().flatten());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_follow_the_displacement_data() {
        let d = Displacement::Perlin {
            amplitude: 1.0,
            frequency: 1.0,
            seed: 3,
        };
        let (params, data) = gpu_data(&d, 2);
        assert_eq!(params.faces_at, 512);
        assert_eq!(data.len(), 512 + 2 * FACE_RECORD_LEN);
        assert!(data[512..].iter().all(|&x| x == 0.0));
        let (none, _) = gpu_data(&Displacement::None, 2);
        assert_eq!(none.faces_at, NO_FACES);
        let face = FaceFrame {
            means: [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]],
            mask: FaceFrame::EDGE[2] | FaceFrame::CORNER[0],
        };
        let records = face_records(&[face]);
        assert_eq!(records[0], 12.0);
        assert_eq!(
            &records[1..],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
        );
    }
}
