//! Which extensions a scene may require, and why the others are refused.
//!
//! An extension that changes no geometry is passed through untouched: the refined primitives
//! keep their materials, so lights, texture transforms, material models and image formats
//! mean what they meant. Geometry encodings are decoded on reading
//! (`KHR_mesh_quantization`, `EXT_meshopt_compression`) and the refined primitives are written
//! as plain floats. Draco is refused with a way out; an unknown required extension is refused
//! by name, since no reader may guess what it means (glTF 2.0 section 3.12).

/// Required extensions that refining passes through or decodes.
pub const ACCEPTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_texture_transform",
    "KHR_texture_basisu",
    "EXT_texture_webp",
    "EXT_texture_avif",
    "KHR_mesh_quantization",
    "EXT_meshopt_compression",
    "EXT_mesh_gpu_instancing",
    "KHR_materials_unlit",
    "KHR_materials_emissive_strength",
    "KHR_materials_pbrSpecularGlossiness",
];

/// Whether refining accepts `name` as a required extension: the list above and every
/// `KHR_materials_*` (material models only shade).
pub fn accepted(name: &str) -> bool {
    ACCEPTED.contains(&name) || name.starts_with("KHR_materials_")
}

/// Why the WebAssembly build refuses meshopt-compressed views (it has no decoder:
/// meshoptimizer is C++).
pub fn meshopt_unavailable() -> String {
    "the file uses EXT_meshopt_compression, which the WebAssembly build cannot decode (it has \
     no meshopt decoder); refine it with the native tool (`tessella refine`, Python), or decode \
     it first: `npx @gltf-transform/cli copy in.glb plain.glb` writes it uncompressed"
        .into()
}

/// Why a required extension is refused (`None`: accepted).
pub fn refusal(name: &str) -> Option<String> {
    if accepted(name) {
        return None;
    }
    if name == "KHR_draco_mesh_compression" {
        return Some(
            "the file requires KHR_draco_mesh_compression (Draco-compressed geometry), which \
             tessella does not decode; decompress it first: glTF-Transform decodes Draco on \
             reading and writes plain geometry, `npx @gltf-transform/cli copy in.glb plain.glb`"
                .into(),
        );
    }
    Some(format!(
        "the file requires the extension {name}, which tessella does not know; without it the \
         file cannot be read as its author meant (glTF 2.0, section 3.12)"
    ))
}
