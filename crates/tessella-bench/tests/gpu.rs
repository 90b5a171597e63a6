//! The benchmark functions run, report the sizes they claim, and draw what they time.

// The GPU crate's test setup (one software device, CPU-vs-GPU comparisons), shared rather than copied.
#[path = "../../tessella-gpu/tests/common/mod.rs"]
mod common;

use common::ctx;
use tessella_bench::gpu::{
    figure7, figure7_table, mesh_with_faces, refine_table, refine_throughput, Figure7Config,
};
use tessella_core::{samples, Pattern, RefineOptions, Refiner, Scheme};

/// A Figure 7 run of one mesh of `faces` triangles at `level`, one small PN frame.
fn one_frame_config(faces: usize, level: u32) -> Figure7Config {
    Figure7Config {
        faces: vec![faces],
        levels: vec![level],
        frames: 1,
        size: (32, 32),
        scheme: Scheme::Pn,
    }
}

#[test]
fn figure7_rows_count_vertices_like_the_paper() {
    let config = one_frame_config(10, 4);
    let rows = figure7(ctx(), &config).unwrap();
    assert_eq!(rows.len(), 1);
    let r = &rows[0];
    assert_eq!(r.faces, 10);
    // The pattern stores one triangle's (N+1)(N+2)/2 points, whatever the mesh.
    assert_eq!(r.pattern_vertices, Pattern::point_count(4));
    let mesh = mesh_with_faces(10).unwrap();
    let welded = Refiner::new(&mesh, &RefineOptions::new(Scheme::Pn, 4))
        .unwrap()
        .layout()
        .vertex_count;
    assert_eq!(r.static_vertices, welded);
    // Both paths drew the same surface (a blank or broken frame would differ in most pixels),
    // and drawing took time.
    let differ = r.pictures_differ.expect("the static buffer fits");
    assert!(differ < 0.02, "pictures differ in {differ}");
    assert!(r.static_ms.is_some_and(|ms| ms > 0.0) && r.pattern_ms > 0.0);
    assert!(r.static_note.is_none());
    assert!(
        r.adapter.contains("software"),
        "lavapipe rows are labelled: {}",
        r.adapter
    );
    let table = figure7_table(&rows);
    assert_eq!(table.lines().count(), 3);
}

#[test]
fn throughput_rows_report_layout_sizes() {
    let mesh = samples::icosphere(0);
    let rows = refine_throughput(ctx(), &mesh, Scheme::Pn, &[2, 3], 1).unwrap();
    assert_eq!(rows.iter().map(|r| r.level).collect::<Vec<_>>(), vec![2, 3]);
    assert_eq!(rows[0].triangles, 20 * 4);
    assert!(refine_table(&rows).contains("| 3 |"));
    for faces in [1, 10, 100, 1000] {
        assert_eq!(mesh_with_faces(faces).unwrap().face_count(), faces);
    }
}

#[test]
fn mixed_patterns_are_timed_against_one_uniform_pattern() {
    let ctx = tessella_gpu::GpuContext::new(tessella_gpu::AdapterChoice::Software).unwrap();
    let mesh = tessella_core::samples::icosphere(2);
    let (u, m, ut, mt, draws) =
        tessella_bench::gpu::mixed_pattern_frame_times(&ctx, &mesh, 8, 5, (256, 256)).unwrap();
    println!("uniform {u:.3} ms ({ut} triangles), mixed {m:.3} ms ({mt} triangles, {draws} draws), ratio {:.2}", m / u);
    assert!(u > 0.0 && m > 0.0);
    assert!(draws > 1);
}

#[test]
fn changing_levels_are_timed_rebuilt_and_adaptive() {
    let ctx = tessella_gpu::GpuContext::new(tessella_gpu::AdapterChoice::Software).unwrap();
    let mesh = tessella_core::samples::icosphere(1);
    let rows = tessella_bench::gpu::changing_levels(&ctx, &mesh, 9.0, 3, (128, 128)).unwrap();
    let table = tessella_bench::gpu::changing_levels_table(&rows);
    println!("{table}");
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert!(r.triangles > mesh.face_count() as u64 * 4, "{r:?}");
        assert!(r.rebuild_ms > 0.0 && r.adaptive_ms > 0.0 && r.adaptive_draw_ms > 0.0);
        // The adaptive renderer uploads coarse data only: at most 112 bytes per face, while
        // a rebuilt renderer uploads its patterns and stencils again.
        assert!(r.adaptive_bytes <= 112 * mesh.face_count() as u64, "{r:?}");
        assert!(r.rebuild_bytes > 10 * r.adaptive_bytes, "{r:?}");
    }
    assert!(table.contains("| fractional-odd |"));
}

#[test]
fn figure7_says_when_the_static_buffer_does_not_fit() {
    // The device's limit as tessella reads it, lowered: the row is still made, not drawn.
    let mut small = ctx().clone();
    small.limits.max_buffer_size = 40_000;
    let config = one_frame_config(100, 8);
    let rows = figure7(&small, &config).unwrap();
    let r = &rows[0];
    assert!(r.static_bytes > 40_000);
    assert!(r.static_ms.is_none() && r.pictures_differ.is_none());
    let note = r.static_note.as_deref().unwrap();
    assert!(note.contains("40000-byte buffer limit"), "{note}");
    assert!(r.pattern_ms > 0.0);
    let table = figure7_table(&rows);
    assert!(table.contains("| — |") && table.contains(note), "{table}");
}

#[test]
fn ratios_of_a_time_that_read_zero_are_left_out() {
    use tessella_bench::gpu::ratio;
    assert_eq!(ratio(3.0, 1.5), Some(2.0));
    assert_eq!(ratio(1.0, 0.0), None);
    assert_eq!(ratio(0.0, 1.0), None);
    assert_eq!(ratio(f64::NAN, 1.0), None);
    assert_eq!(ratio(f64::MAX, f64::MIN_POSITIVE), None);
}

/// The three paths of an animated frame upload what each is meant to: the nets (16 entries of
/// 12 bytes a triangle), nothing but the caller's own vertices, or the deform matrices (64
/// bytes each) and morph weights (4 bytes each).
#[test]
fn animated_paths_upload_nets_nothing_or_matrices() {
    use tessella_bench::gpu_animated::{animated_paths, animated_paths_table, PATHS};
    let poser = tessella_core::animation::Poser::new(samples::animated_creature(1)).unwrap();
    let rows = animated_paths(ctx(), &poser, 0, &[2], 2, (32, 32)).unwrap();
    assert_eq!(rows.iter().map(|r| r.path).collect::<Vec<_>>(), PATHS);
    let faces = poser.model().triangles.len();
    let joints: usize = poser.model().skins.iter().map(|s| s.joints.len()).sum();
    let weights: usize = poser
        .model()
        .instances
        .iter()
        .map(|i| i.targets.len())
        .sum();
    let expected = [
        (faces * 16 * 12, 0),
        (0, poser.vertex_count() * 24),
        (joints * 64 + weights * 4, 0),
    ];
    for (row, (tessella, caller)) in rows.iter().zip(expected) {
        assert_eq!(row.coarse_triangles, faces);
        assert_eq!(
            (row.tessella_bytes, row.caller_bytes),
            (tessella as u64, caller as u64),
            "{}",
            row.path
        );
        assert!(row.frame_ms > 0.0);
    }
    assert_eq!(animated_paths_table(&rows).lines().count(), 5);
}
