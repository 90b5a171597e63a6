//! `gltf::write_animated` and `read_animated` are inverses on the animated sample: nodes,
//! skins, influences (two sets), the morph target and the three clips come back equal, from
//! `.glb` and `.gltf` alike.

use tessella_core::samples::animated_creature;

#[test]
fn the_animated_sample_round_trips_through_glb_and_gltf() {
    let model = animated_creature(2);
    let dir = tempfile::tempdir().unwrap();
    for (name, binary) in [("creature.glb", true), ("creature.gltf", false)] {
        let path = dir.path().join(name);
        tessella_io::write_atomic(&path, |out| {
            tessella_io::gltf::write_animated(out, &model, binary)
        })
        .unwrap();
        let back = tessella_io::read_animated(&path).unwrap();
        assert_eq!(back, model, "{name}");
    }
}

#[test]
fn what_gltf_cannot_say_is_refused() {
    let mut model = animated_creature(0);
    let mut second = model.instances[0].clone();
    second.first_vertex = second.positions.len() as u32;
    model.instances.push(second); // the same node draws two instances
    let err = tessella_io::gltf::write_animated(&mut Vec::new(), &model, true).unwrap_err();
    assert!(
        err.to_string().contains("node 0 draws two instances"),
        "{err}"
    );
}
