//! What several commands share about the GPU: choosing an adapter, parsing displacement.

use crate::args::BackendArg;
use anyhow::{bail, Context};
use tessella_core::displace::Displacement;
use tessella_gpu::{AdapterChoice, GpuContext};

/// The GPU context `backend` asks for, or `None` to use the CPU.
///
/// `auto` takes a hardware adapter when there is one (a software adapter is slower than the CPU
/// path) and the CPU otherwise; `gpu` takes any adapter, software included, and fails with the
/// reason when there is none.
pub fn context_for(backend: BackendArg) -> anyhow::Result<Option<GpuContext>> {
    match backend {
        BackendArg::Cpu => Ok(None),
        // No hardware GPU is the ordinary case on servers: the CPU is the documented fallback,
        // so it goes quietly.
        BackendArg::Auto => Ok(GpuContext::new(AdapterChoice::Hardware).ok()),
        BackendArg::Gpu => Ok(Some(
            GpuContext::new(AdapterChoice::Auto).context("--backend gpu needs a GPU adapter")?,
        )),
    }
}

/// Any adapter, for pictures: a hardware GPU, else the software one.
pub fn render_context() -> anyhow::Result<GpuContext> {
    GpuContext::new(AdapterChoice::Auto).context(
        "rendering needs a GPU adapter; without a GPU install Mesa's software Vulkan driver \
         (Debian: apt-get install mesa-vulkan-drivers libvulkan1)",
    )
}

/// Parses `sine:AMP,FREQ`, `perlin:AMP,FREQ[,SEED]`, `heightmap:IMAGE,AMP`.
pub fn parse_displacement(spec: Option<&str>) -> anyhow::Result<Displacement> {
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
