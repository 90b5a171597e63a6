//! Tags from a sidecar JSON and PLY properties, and how `tags::gather` layers every source.

use std::collections::BTreeMap;
use std::io::ErrorKind;
use tessella_core::tags::{EdgeTag, TagError, Tags, VertexTag};
use tessella_core::{samples, Mesh, Scheme};
use tessella_io::tags::{self, JsonSource, JsonTagError, TagSourceError, TagSources};
use tessella_io::{read_raw, RawEdge};

#[test]
fn json_sidecar_round_trip_and_errors() {
    let mesh = samples::tetrahedron();
    let tags = tags::from_json(
        &mesh,
        r#"{"edges": [{"vertices": [0, 1], "sharpness": 0.5, "kappa": -0.1}],
            "vertices": [{"index": 2, "tension": 0.25, "sharpness": 1, "crease": [0, 1, 0]}]}"#,
    )
    .unwrap();
    assert_eq!(
        tags.edge(1, 0),
        EdgeTag {
            sharpness: 0.5,
            kappa: -0.1
        }
    );
    assert_eq!(tags.vertex(2).tension, 0.25);
    assert_eq!(tags.vertex(2).crease, [0.0, 1.0, 0.0]);
    assert_eq!(tags.vertex(3), VertexTag::default());

    let err = |text: &str| tags::from_json(&mesh, text).unwrap_err();
    assert!(matches!(
        err(r#"{"vertices": [{"index": 9}]}"#),
        JsonTagError::Tag(TagError::UnknownVertex {
            vertex: 9,
            count: 4,
            ..
        })
    ));
    assert!(matches!(
        err(r#"{"edges": [{"vertices": [0, 7]}]}"#),
        JsonTagError::Tag(TagError::UnknownVertex { vertex: 7, .. })
    ));
    assert!(matches!(
        err(r#"{"edges": [{"vertices": [0, 1], "sharpness": 2}]}"#),
        JsonTagError::Tag(TagError::OutOfRange { .. })
    ));
    assert!(matches!(
        err(r#"{"vertices": [{"index": 0, "sharpness": -3}]}"#),
        JsonTagError::Tag(TagError::OutOfRange { .. })
    ));
    assert!(matches!(
        err(r#"{"edges": [{"vertices": [0, 1], "bogus": 1}]}"#),
        JsonTagError::Json(_)
    ));
    assert!(matches!(err("not json"), JsonTagError::Json(_)));
    // Every message names the problem.
    assert!(err(r#"{"vertices": [{"index": 9}]}"#)
        .to_string()
        .contains("vertex 9"));
    assert!(err(r#"{"edge": []}"#)
        .to_string()
        .starts_with("tags JSON: unknown field `edge`"));
}

fn edge(vertices: [u32; 2], scalars: &[(&str, f32)]) -> RawEdge {
    RawEdge {
        vertices,
        scalars: scalars.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
    }
}

#[test]
fn ply_properties_become_tags_and_nan_is_refused() {
    let mesh = samples::tetrahedron();
    let mut vertex = BTreeMap::new();
    vertex.insert("tension".to_string(), vec![0.0, 0.5, 0.0, 0.0]);
    vertex.insert("red".to_string(), vec![1.0; 4]); // unrelated properties are ignored
    let sharp = edge([2, 3], &[("sharpness", 1.0)]);
    let tags = tags::from_ply(&mesh, &vertex, std::slice::from_ref(&sharp)).unwrap();
    assert_eq!(tags.vertex(1).tension, 0.5);
    assert_eq!(tags.vertex_count(), 1);
    assert_eq!(tags.edge(2, 3).sharpness, 1.0);

    vertex.insert("bias".to_string(), vec![0.0, f32::NAN, 0.0, 0.0]);
    assert!(matches!(
        tags::from_ply(&mesh, &vertex, &[]),
        Err(TagError::NotFinite { .. })
    ));
    vertex.insert("bias".to_string(), vec![0.0; 3]);
    assert!(matches!(
        tags::from_ply(&mesh, &vertex, &[]),
        Err(TagError::OutOfRange { .. })
    ));
    vertex.remove("bias");
    assert!(matches!(
        tags::from_ply(&mesh, &vertex, &[edge([2, 3], &[("sharpness", f32::NAN)])]),
        Err(TagError::NotFinite { .. })
    ));
    assert!(matches!(
        tags::from_ply(&mesh, &BTreeMap::new(), &[edge([2, 40], &[])]),
        Err(TagError::UnknownVertex { vertex: 40, .. })
    ));
}

/// A quad of two triangles with a vertex tag column, an unrelated column and an `edge` element
/// on its diagonal.
const TAGGED_QUAD: &str = "ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property float tension
property float red
element face 2
property list uchar int vertex_indices
element edge 1
property int vertex1
property int vertex2
property float sharpness
property float kappa
end_header
0 0 0 0 1
1 0 0 0.5 1
1 1 0.5 0 1
0 1 0 0 1
3 0 1 2
3 0 2 3
0 2 1 -0.25
";

#[test]
fn a_tagged_ply_file_gives_its_tags() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("quad.ply");
    std::fs::write(&path, TAGGED_QUAD).unwrap();
    let raw = read_raw(&path).unwrap();
    let mesh = Mesh::new(
        raw.positions.clone(),
        raw.normals.clone(),
        raw.uvs.clone(),
        raw.triangles.clone(),
    )
    .unwrap();
    let sources = TagSources {
        file: Some(&raw),
        ..TagSources::default()
    };
    let tags = tags::gather(&mesh, Scheme::Pn, &sources).unwrap().unwrap();
    assert_eq!(tags.vertex(1).tension, 0.5);
    assert_eq!(tags.vertex_count(), 1);
    assert_eq!(
        tags.edge(2, 0),
        EdgeTag {
            sharpness: 1.0,
            kappa: -0.25
        }
    );
    assert_eq!(tags.edge_count(), 1);
}

#[test]
fn gather_layers_split_normals_crease_angle_ply_then_json() {
    let cube = samples::hard_cube();
    let split = Tags::from_split_normals(&cube);
    assert!(split.edge_count() > 0);

    // Nothing to tag: no split normals for PN, no sources.
    assert_eq!(
        tags::gather(&cube, Scheme::Pn, &TagSources::default()).unwrap(),
        None
    );
    // The scalar-tagged scheme takes the file's hard edges on its own.
    let st = tags::gather(&cube, Scheme::ScalarTagged, &TagSources::default()).unwrap();
    assert_eq!(st.as_ref(), Some(&split));
    // A crease angle adds the same edges for any scheme.
    let angle = TagSources {
        crease_angle: Some(30.0),
        ..TagSources::default()
    };
    let creased = tags::gather(&cube, Scheme::Png1, &angle).unwrap().unwrap();
    assert_eq!(creased.edge_count(), 12);

    // Later sources win: PLY over the crease angle, JSON over the PLY, on a creased edge.
    let ids = tessella_core::mesh::topology::position_ids(cube.positions());
    let [a, b] = cube
        .triangles()
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .find(|&[a, b]| creased.edge(ids[a as usize], ids[b as usize]).sharpness == 1.0)
        .expect("a cube edge");
    let mut raw = tessella_io::RawMesh {
        positions: cube.positions().to_vec(),
        triangles: cube.triangles().to_vec(),
        ..Default::default()
    };
    raw.edges.push(edge([a, b], &[("sharpness", 0.5)]));
    let json = format!(r#"{{"edges": [{{"vertices": [{a}, {b}], "sharpness": 0.25}}]}}"#);
    let mut sources = TagSources {
        crease_angle: Some(30.0),
        file: Some(&raw),
        json: None,
    };
    let layered = tags::gather(&cube, Scheme::Png1, &sources)
        .unwrap()
        .unwrap();
    assert_eq!(
        layered.edge(ids[a as usize], ids[b as usize]).sharpness,
        0.5
    );
    sources.json = Some(JsonSource::Text {
        text: &json,
        origin: "in the test",
    });
    let layered = tags::gather(&cube, Scheme::Png1, &sources)
        .unwrap()
        .unwrap();
    assert_eq!(
        layered.edge(ids[a as usize], ids[b as usize]).sharpness,
        0.25
    );
    assert_eq!(layered.edge_count(), 12);
}

#[test]
fn gather_names_the_source_of_bad_tags() {
    let mesh = samples::tetrahedron();
    let dir = tempfile::tempdir().unwrap();
    let gather = |sources: TagSources| tags::gather(&mesh, Scheme::Png1, &sources).unwrap_err();

    let err = gather(TagSources {
        crease_angle: Some(181.0),
        ..TagSources::default()
    });
    assert!(matches!(
        err,
        TagSourceError::CreaseAngle(TagError::BadAngle(_))
    ));
    assert!(err.to_string().starts_with("crease angle must be"), "{err}");

    let missing = dir.path().join("missing.json");
    let err = gather(TagSources {
        json: Some(JsonSource::File(&missing)),
        ..TagSources::default()
    });
    match &err {
        TagSourceError::Read { path, error } => {
            assert_eq!(path, &missing);
            assert_eq!(error.kind(), ErrorKind::NotFound);
        }
        other => panic!("expected a read error, got {other:?}"),
    }
    assert!(
        err.to_string().starts_with("cannot read tags from "),
        "{err}"
    );
    assert!(err.to_string().contains("missing.json"), "{err}");

    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, r#"{"vertices": [{"index": 40}]}"#).unwrap();
    let err = gather(TagSources {
        json: Some(JsonSource::File(&bad)),
        ..TagSources::default()
    });
    assert!(matches!(
        err,
        TagSourceError::Json {
            error: JsonTagError::Tag(TagError::UnknownVertex { vertex: 40, .. }),
            ..
        }
    ));
    let message = err.to_string();
    assert!(message.starts_with("bad tags in "), "{message}");
    assert!(
        message.contains("bad.json: vertex tag names vertex 40"),
        "{message}"
    );

    let err = gather(TagSources {
        json: Some(JsonSource::Text {
            text: r#"{"edges": ["#,
            origin: "in the tags string",
        }),
        ..TagSources::default()
    });
    assert!(
        err.to_string()
            .starts_with("bad tags in the tags string: tags JSON:"),
        "{err}"
    );

    let mut raw = tessella_io::RawMesh::default();
    raw.vertex_scalars
        .insert("sharpness".to_string(), vec![0.0, 2.0, 0.0, 0.0]);
    let err = gather(TagSources {
        file: Some(&raw),
        ..TagSources::default()
    });
    assert!(matches!(
        err,
        TagSourceError::Ply(TagError::OutOfRange { .. })
    ));
    assert!(
        err.to_string()
            .starts_with("bad tags in the PLY file: vertex 1 sharpness is 2"),
        "{err}"
    );
}
