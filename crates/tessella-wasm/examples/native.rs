//! The native side of the npm package's checks, on the same machine:
//!
//! - `native digests OUT.json`: for every sample mesh (`samples/*.obj`), scheme flat, phong, pn
//!   and png1, and level 1 to 16, the vertex and triangle counts and digests of the native CPU's
//!   output bits, which `js/test/native.test.js` compares with the wasm build's;
//! - `native bench MESH.obj SCHEME LEVEL SECONDS`: single-thread native throughput, one-shot
//!   `refine` and per-frame `Plan::update` + `Plan::evaluate`, as JSON, for `js/bench/bench.js`.

use std::path::Path;
use std::time::Instant;
use tessella_core::refine::{Plan, VertexOutput};
use tessella_core::{refine, RefineOptions, Scheme};

/// Two 32-bit hashes of a sequence of 32-bit words (FNV-1a and a multiplicative one), as
/// `js/test/digest.js` computes them.
fn digest(words: &[u32]) -> String {
    let (mut a, mut b) = (0x811c9dc5u32, 0x12345678u32);
    for &w in words {
        a = (a ^ w).wrapping_mul(16777619);
        b = (b ^ w).wrapping_mul(0x9e3779b1).rotate_left(13);
    }
    format!("{a:08x}{b:08x}")
}

fn words<T: bytemuck::Pod>(values: &[T]) -> &[u32] {
    bytemuck::cast_slice(values)
}

fn digests(out: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples");
    let mut names: Vec<String> = std::fs::read_dir(&root)
        .expect("samples/")
        .map(|e| {
            e.expect("a sample")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|n| n.ends_with(".obj"))
        .collect();
    names.sort();
    let mut entries = Vec::new();
    for name in &names {
        let read = tessella_io::read_mesh(&root.join(name)).expect("a sample mesh");
        // The arrays `readMesh` hands to JS, validated again as `refine` does with them (given
        // normals are normalised once more, which can move a last bit).
        let mesh = tessella_core::Mesh::new(
            read.positions().to_vec(),
            Some(read.normals().to_vec()),
            read.uvs().map(<[_]>::to_vec),
            read.triangles().to_vec(),
        )
        .expect("the same mesh");
        for scheme in ["flat", "phong", "pn", "png1"] {
            let parsed: Scheme = scheme.parse().expect("a scheme");
            for level in 1..=16 {
                let r = refine(&mesh, &RefineOptions::new(parsed, level)).expect("refine");
                entries.push(serde_json::json!({
                    "mesh": name, "scheme": scheme, "level": level,
                    "vertices": r.positions.len(), "triangles": r.triangles.len(),
                    "positions": digest(words(&r.positions)),
                    "normals": digest(words(&r.normals)),
                    "indices": digest(words(&r.triangles)),
                }));
            }
        }
    }
    let text = serde_json::to_string_pretty(&entries).expect("json");
    std::fs::write(out, text).expect("write the digests");
}

fn bench(mesh: &Path, scheme: &str, level: u32, seconds: f64) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()
        .expect("one thread");
    let mesh = tessella_io::read_mesh(mesh).expect("the mesh");
    let options = RefineOptions::new(scheme.parse().expect("a scheme"), level);
    let time = |f: &mut dyn FnMut()| {
        f();
        let (start, mut runs) = (Instant::now(), 0u32);
        while runs < 3 || start.elapsed().as_secs_f64() < seconds {
            f();
            runs += 1;
        }
        start.elapsed().as_secs_f64() / runs as f64
    };
    let mut vertices = 0;
    let one_shot =
        time(&mut || vertices = refine(&mesh, &options).expect("refine").positions.len());
    let plan = Plan::new(&mesh, &options).expect("plan");
    let mut frame = plan.frame(&mesh).expect("frame");
    let (mut p, mut n) = (
        vec![[0.0f32; 3]; plan.vertex_count()],
        vec![[0.0f32; 3]; plan.vertex_count()],
    );
    let per_frame = time(&mut || {
        plan.update(&mut frame, mesh.positions(), Some(mesh.normals()))
            .expect("update");
        let out = VertexOutput::Separate {
            positions: &mut p,
            normals: Some(&mut n),
            uvs: None,
        };
        plan.evaluate(&frame, out).expect("evaluate");
    });
    println!(
        "{}",
        serde_json::json!({
            "vertices": vertices, "triangles": plan.triangle_count(),
            "oneShotSeconds": one_shot, "frameSeconds": per_frame,
        })
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .as_slice()
    {
        ["digests", out] => digests(Path::new(out)),
        ["bench", mesh, scheme, level, seconds] => bench(
            Path::new(mesh),
            scheme,
            level.parse().expect("a level"),
            seconds.parse().expect("seconds"),
        ),
        _ => {
            eprintln!("usage: native digests OUT.json | native bench MESH SCHEME LEVEL SECONDS");
            std::process::exit(2);
        }
    }
}
