//! The culling bound of a pose built on the GPU (`mesh::patch_bounds` with
//! `Scheme::control_reach`) against the CPU's own nets of that pose.

use glam::Vec3;
use tessella_core::animation::Poser;
use tessella_core::mesh::{bounds, patch_bounds};
use tessella_core::refine::{Surface, SurfaceOptions};
use tessella_core::{samples, MeshError, Scheme};

/// The bounds an engine culls a GPU-posed character by hold the posed surface: for the
/// sample creature (skinned and morphing) at times of each clip, every coarse triangle's
/// control net as the CPU builds it from the pose (its patch lies in the net's hull) is
/// inside `patch_bounds` of the posed coarse vertices with the scheme's reach, for each
/// scheme with a reach; and the box is tight (its diagonal under 1.4 times the nets'). An index past
/// the points is an error, not a panic.
#[test]
fn patch_bounds_hold_every_posed_control_net() {
    // The bundled file's creature: 320 triangles.
    let poser = Poser::new(samples::animated_creature(2)).unwrap();
    let rest = poser.mesh(None, 0.0).unwrap();
    for scheme in [
        Scheme::Pn,
        Scheme::PnAen,
        Scheme::Phong { alpha: 1.0 },
        Scheme::Phong { alpha: 0.6 },
        Scheme::Flat,
    ] {
        let reach = scheme.control_reach().unwrap();
        let surface = Surface::new(&rest, &SurfaceOptions::new(scheme)).unwrap();
        let mut worst = 0.0f32;
        for clip in 0..poser.clip_count() {
            for time in [0.1, 0.4, 0.7, 1.3] {
                let posed = poser.mesh(Some(clip), time).unwrap();
                let (lo, hi) = patch_bounds(posed.positions(), posed.triangles(), reach).unwrap();
                let nets = surface.frame(&posed).unwrap().nets().clone();
                let (nlo, nhi) = bounds(&nets.points);
                for p in &nets.points {
                    assert!(
                        (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]),
                        "{scheme:?}, clip {clip} at {time}: {p:?} outside {lo:?}..{hi:?}"
                    );
                }
                let size = |a: [f32; 3], b: [f32; 3]| Vec3::from(b).distance(Vec3::from(a));
                worst = worst.max(size(lo, hi) / size(nlo, nhi));
            }
        }
        eprintln!("{scheme:?}: the box's diagonal is at most {worst} times the nets'");
        assert!(
            worst < 1.4,
            "{scheme:?}: the box is {worst} times the nets'"
        );
    }
    for scheme in [Scheme::Png1, Scheme::ScalarTagged, Scheme::Quadratic] {
        assert_eq!(scheme.control_reach(), None);
    }
    let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert!(matches!(
        patch_bounds(&points, &[[0, 1, 7]], 0.5),
        Err(MeshError::IndexOutOfRange { index: 7, .. })
    ));
}
