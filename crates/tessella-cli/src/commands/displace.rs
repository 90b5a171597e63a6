//! `--displace SPEC`: displacement along the normal after refinement, on the CPU or the GPU.

use anyhow::{bail, Context};
use tessella_core::displace::Displacement;

/// Parses `sine:AMP,FREQ`, `perlin:AMP,FREQ[,SEED]`, `heightmap:IMAGE,AMP`.
pub fn parse(spec: Option<&str>) -> anyhow::Result<Displacement> {
    let Some(spec) = spec else {
        return Ok(Displacement::None);
    };
    let (kind, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let parts: Vec<&str> = rest
        .split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect();
    let number = |i: usize, what: &str| -> anyhow::Result<f32> {
        let text = parts
            .get(i)
            .with_context(|| format!("--displace {spec}: missing {what}"))?;
        text.parse()
            .with_context(|| format!("--displace {spec}: {what} '{text}' is not a number"))
    };
    let displacement = match kind {
        "sine" => Displacement::Sine { amplitude: number(0, "amplitude")?, frequency: number(1, "frequency")? },
        "perlin" => Displacement::Perlin {
            amplitude: number(0, "amplitude")?,
            frequency: number(1, "frequency")?,
            seed: match parts.get(2) {
                Some(s) => s.parse().with_context(|| format!("--displace {spec}: seed '{s}' is not a whole number"))?,
                None => 0,
            },
        },
        "heightmap" => {
            let path = parts.first().with_context(|| format!("--displace {spec}: missing the image path"))?;
            Displacement::HeightMap { amplitude: number(1, "amplitude")?, map: tessella_io::read_height_map(path.as_ref())? }
        }
        _ => bail!("--displace {spec}: unknown kind '{kind}'; use sine:AMP,FREQ, perlin:AMP,FREQ[,SEED] or heightmap:IMAGE,AMP"),
    };
    Ok(displacement)
}
