//! The writers' bytes against an independent encoding written out here value by value, on a
//! mesh large enough that the writers split it into many blocks (block edges are where an
//! order or a record could go wrong).

use tessella_core::{refine, samples, RefineOptions, Scheme};
use tessella_io::MeshView;

fn big_mesh() -> tessella_core::RefinedMesh {
    // 5120 faces at level 6: 92k vertices, 184k triangles; several MB in every format.
    refine(&samples::icosphere_4k(), &RefineOptions::new(Scheme::Pn, 6)).unwrap()
}

fn after_header(bytes: &[u8]) -> &[u8] {
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    &bytes[end..]
}

#[test]
fn binary_ply_is_every_value_little_endian_in_order() {
    let mesh = big_mesh();
    let mut out = Vec::new();
    tessella_io::ply::write(&mut out, &MeshView::from(&mesh), false).unwrap();
    let mut want = Vec::new();
    for v in 0..mesh.positions.len() {
        for x in mesh.positions[v].iter().chain(&mesh.normals[v]) {
            want.extend_from_slice(&x.to_le_bytes());
        }
    }
    for t in &mesh.triangles {
        want.push(3);
        for i in t {
            want.extend_from_slice(&i.to_le_bytes());
        }
    }
    assert!(want.len() > 4 << 20);
    assert!(after_header(&out) == want.as_slice());
}

#[test]
fn ascii_ply_and_obj_numbers_read_back_exactly() {
    let mesh = big_mesh();
    let view = MeshView::from(&mesh);
    let mut ply = Vec::new();
    tessella_io::ply::write(&mut ply, &view, true).unwrap();
    let text = std::str::from_utf8(after_header(&ply)).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), mesh.positions.len() + mesh.triangles.len());
    for (v, line) in lines[..mesh.positions.len()].iter().enumerate() {
        let values: Vec<f32> = line.split(' ').map(|x| x.parse().unwrap()).collect();
        let want: Vec<f32> = mesh.positions[v]
            .iter()
            .chain(&mesh.normals[v])
            .copied()
            .collect();
        assert_eq!(values, want, "vertex {v}: {line}");
    }
    for (f, line) in lines[mesh.positions.len()..].iter().enumerate() {
        let t = mesh.triangles[f];
        assert_eq!(*line, format!("3 {} {} {}", t[0], t[1], t[2]));
    }

    let mut obj = Vec::new();
    tessella_io::obj::write(&mut obj, &view).unwrap();
    let text = String::from_utf8(obj).unwrap();
    let (mut v, mut vn, mut f) = (0, 0, 0);
    for line in text.lines().skip(1) {
        let mut words = line.split(' ');
        match words.next().unwrap() {
            "v" => {
                let p: Vec<f32> = words.map(|x| x.parse().unwrap()).collect();
                assert_eq!(p, mesh.positions[v], "{line}");
                v += 1;
            }
            "vn" => {
                let n: Vec<f32> = words.map(|x| x.parse().unwrap()).collect();
                assert_eq!(n, mesh.normals[vn], "{line}");
                vn += 1;
            }
            "f" => {
                let t = mesh.triangles[f].map(|i| i + 1);
                assert_eq!(
                    line,
                    format!("f {0}//{0} {1}//{1} {2}//{2}", t[0], t[1], t[2])
                );
                f += 1;
            }
            other => panic!("unexpected line kind {other}"),
        }
    }
    assert_eq!(
        (v, vn, f),
        (
            mesh.positions.len(),
            mesh.normals.len(),
            mesh.triangles.len()
        )
    );
}

#[test]
fn stl_records_are_facet_normal_corners_and_two_zero_bytes() {
    let mesh = big_mesh();
    let mut out = Vec::new();
    tessella_io::stl::write(&mut out, &MeshView::from(&mesh)).unwrap();
    assert_eq!(out.len(), 84 + 50 * mesh.triangles.len());
    assert!(
        !out.starts_with(b"solid"),
        "a binary STL must not look like ascii"
    );
    let count = u32::from_le_bytes(out[80..84].try_into().unwrap());
    assert_eq!(count as usize, mesh.triangles.len());
    for (f, record) in out[84..].chunks(50).enumerate() {
        let float = |i: usize| f32::from_le_bytes(record[4 * i..4 * i + 4].try_into().unwrap());
        let corners = mesh.triangles[f].map(|i| mesh.positions[i as usize]);
        for (c, corner) in corners.iter().enumerate() {
            for (k, &x) in corner.iter().enumerate() {
                assert_eq!(float(3 + 3 * c + k), x);
            }
        }
        // The facet normal, computed here in f64: unit, and along the corners' cross product.
        let d = |a: [f32; 3], b: [f32; 3]| [0, 1, 2].map(|k| b[k] as f64 - a[k] as f64);
        let (e1, e2) = (d(corners[0], corners[1]), d(corners[0], corners[2]));
        let cross = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let len = cross.iter().map(|x| x * x).sum::<f64>().sqrt();
        for (k, x) in cross.iter().enumerate() {
            assert!((float(k) as f64 - x / len).abs() < 1e-3, "facet {f}");
        }
        assert_eq!(&record[48..], &[0, 0]);
    }
}
