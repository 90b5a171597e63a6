//! `--displace SPEC`: displacement along the normal after refinement, on the CPU or the GPU.

use tessella_core::displace::Displacement;

/// Parses `sine:AMP,FREQ`, `perlin:AMP,FREQ[,SEED]`, `heightmap:IMAGE,AMP` (the core's
/// [`Displacement::parse`], with the height map read from the image file).
pub fn parse(spec: Option<&str>) -> anyhow::Result<Displacement> {
    let Some(spec) = spec else {
        return Ok(Displacement::None);
    };
    let read = |path: &str| tessella_io::read_height_map(path.as_ref()).map_err(|e| e.to_string());
    Displacement::parse(spec, read).map_err(|e| anyhow::anyhow!("--displace: {e}"))
}
