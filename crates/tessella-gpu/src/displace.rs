//! Displacement along the normal (GMR section 4): the Rust twin of `shaders/displace.wgsl`.
//!
//! A refined vertex `P` with unit normal `N` and texture coordinate `uv` moves to
//! `P + d(P, uv) N`. Displacement is applied after evaluation, once per output vertex, so in
//! welded output a vertex on a shared coarse edge (one slot) moves once and the surface stays
//! closed. Normals are left as evaluated (the undisplaced surface's); the renderer shades
//! displaced surfaces with facet normals instead.
//!
//! ```
//! use tessella_gpu::Displacement;
//! let d = Displacement::Sine { amplitude: 0.1, frequency: 10.0 };
//! assert!((d.offset([0.3, 0.4, 0.0], [0.0, 0.0]) - 0.1 * 5.0f32.sin()).abs() < 1e-6);
//! ```

use crate::error::GpuError;
use crate::gpu_types::DisplaceParams;
use tessella_core::RefinedMesh;

/// A scalar height field; samples are bilinear and repeat, `v = 0` is the bottom row.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    pub width: u32,
    pub height: u32,
    /// Row-major from the image's top row, values in `0..=1`.
    pub heights: Vec<f32>,
}

impl HeightMap {
    /// The luminance of an image, `0..=1`.
    pub fn from_image(image: &image::DynamicImage) -> Result<HeightMap, GpuError> {
        let gray = image.to_luma32f();
        if gray.width() == 0 || gray.height() == 0 {
            return Err(GpuError::BadOption("the height map image is empty".into()));
        }
        Ok(HeightMap {
            width: gray.width(),
            height: gray.height(),
            heights: gray.into_raw(),
        })
    }

    /// Loads a height map from an image file (PNG).
    pub fn load(path: &std::path::Path) -> Result<HeightMap, GpuError> {
        let image = image::open(path).map_err(|e| {
            GpuError::BadOption(format!("cannot read height map '{}': {e}", path.display()))
        })?;
        Self::from_image(&image)
    }

    fn texel(&self, x: i32, y: i32) -> f32 {
        let (w, h) = (self.width as i32, self.height as i32);
        let xx = ((x % w) + w) % w;
        let yy = ((y % h) + h) % h;
        self.heights[(yy * w + xx) as usize]
    }

    /// Bilinear sample at `uv`, repeating.
    pub fn sample(&self, uv: [f32; 2]) -> f32 {
        let px = uv[0] * self.width as f32 - 0.5;
        let py = (1.0 - uv[1]) * self.height as f32 - 0.5;
        let (x0, y0) = (px.floor(), py.floor());
        let (tx, ty) = (px - x0, py - y0);
        let (ix, iy) = (x0 as i32, y0 as i32);
        let top = lerp(self.texel(ix, iy), self.texel(ix + 1, iy), tx);
        let bottom = lerp(self.texel(ix, iy + 1), self.texel(ix + 1, iy + 1), tx);
        lerp(top, bottom, ty)
    }
}

/// How refined vertices move along their normals.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Displacement {
    #[default]
    None,
    /// `a · sin(f · ‖P‖)` (GMR section 4, Figure 4).
    Sine { amplitude: f32, frequency: f32 },
    /// `a · noise(f · P)`, Perlin's improved noise (2002) with a permutation shuffled by `seed`.
    Perlin {
        amplitude: f32,
        frequency: f32,
        seed: u32,
    },
    /// `a · h(uv)`: needs a mesh with texture coordinates.
    HeightMap { amplitude: f32, map: HeightMap },
}

impl Displacement {
    /// `true` unless [`Displacement::None`].
    pub fn is_some(&self) -> bool {
        !matches!(self, Displacement::None)
    }

    /// Checks the parameters; `has_uvs` says whether the mesh has texture coordinates.
    pub fn validate(&self, has_uvs: bool) -> Result<(), GpuError> {
        let (a, f) = match self {
            Displacement::None => return Ok(()),
            Displacement::Sine {
                amplitude,
                frequency,
            }
            | Displacement::Perlin {
                amplitude,
                frequency,
                ..
            } => (*amplitude, *frequency),
            Displacement::HeightMap { amplitude, map } => {
                if !has_uvs {
                    return Err(GpuError::BadOption(
                        "a height map needs texture coordinates; the mesh has none".into(),
                    ));
                }
                if map.heights.len() != (map.width as usize) * (map.height as usize)
                    || map.heights.is_empty()
                {
                    return Err(GpuError::BadOption(
                        "the height map's size does not match its data".into(),
                    ));
                }
                (*amplitude, 1.0)
            }
        };
        if !a.is_finite() || !f.is_finite() {
            return Err(GpuError::BadOption(format!(
                "displacement amplitude and frequency must be finite, got {a} and {f}"
            )));
        }
        Ok(())
    }

    /// The offset along the unit normal at surface point `p` with texture coordinate `uv`.
    pub fn offset(&self, p: [f32; 3], uv: [f32; 2]) -> f32 {
        match self {
            Displacement::None => 0.0,
            Displacement::Sine {
                amplitude,
                frequency,
            } => {
                let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                amplitude * (frequency * len).sin()
            }
            Displacement::Perlin {
                amplitude,
                frequency,
                seed,
            } => {
                let perm = permutation(*seed);
                amplitude * perlin(&perm, p.map(|x| frequency * x))
            }
            Displacement::HeightMap { amplitude, map } => amplitude * map.sample(uv),
        }
    }

    /// Displaces every vertex of `mesh` on the CPU (the reference for the GPU path).
    pub fn apply(&self, mesh: &mut RefinedMesh) -> Result<(), GpuError> {
        self.validate(mesh.uvs.is_some())?;
        if !self.is_some() {
            return Ok(());
        }
        let perm = match self {
            Displacement::Perlin { seed, .. } => Some(permutation(*seed)),
            _ => None,
        };
        for i in 0..mesh.positions.len() {
            let p = mesh.positions[i];
            let n = mesh.normals[i];
            let uv = mesh.uvs.as_ref().map_or([0.0; 2], |u| u[i]);
            let d = match (&perm, self) {
                (
                    Some(perm),
                    Displacement::Perlin {
                        amplitude,
                        frequency,
                        ..
                    },
                ) => amplitude * perlin(perm, p.map(|x| frequency * x)),
                _ => self.offset(p, uv),
            };
            mesh.positions[i] = [p[0] + d * n[0], p[1] + d * n[1], p[2] + d * n[2]];
        }
        Ok(())
    }

    /// The uniform and data buffer contents for `displace.wgsl`.
    pub(crate) fn gpu_data(&self) -> (DisplaceParams, Vec<f32>) {
        let mut params = DisplaceParams {
            kind: 0,
            amplitude: 0.0,
            frequency: 0.0,
            map_width: 1,
            map_height: 1,
            _pad: [0; 3],
        };
        let data = match self {
            Displacement::None => vec![0.0],
            Displacement::Sine {
                amplitude,
                frequency,
            } => {
                (params.kind, params.amplitude, params.frequency) = (1, *amplitude, *frequency);
                vec![0.0]
            }
            Displacement::Perlin {
                amplitude,
                frequency,
                seed,
            } => {
                (params.kind, params.amplitude, params.frequency) = (2, *amplitude, *frequency);
                permutation(*seed).iter().map(|&x| x as f32).collect()
            }
            Displacement::HeightMap { amplitude, map } => {
                (params.kind, params.amplitude) = (3, *amplitude);
                (params.map_width, params.map_height) = (map.width, map.height);
                map.heights.clone()
            }
        };
        (params, data)
    }
}

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

/// Perlin's permutation of 0..256, shuffled by `seed` (Fisher-Yates on a 32-bit LCG), doubled
/// to 512 entries so lookups need no wrap.
pub fn permutation(seed: u32) -> [u32; 512] {
    let mut p: [u32; 256] = std::array::from_fn(|i| i as u32);
    let mut state = seed.wrapping_mul(2_654_435_761).wrapping_add(1);
    for i in (1..256).rev() {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let j = ((state >> 8) as usize) % (i + 1);
        p.swap(i, j);
    }
    std::array::from_fn(|i| p[i & 255])
}

fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn grad(hash: i32, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Perlin's improved noise (Perlin 2002, "Improving noise"), in about `-1..=1`.
pub fn perlin(perm: &[u32; 512], p: [f32; 3]) -> f32 {
    let pm = |i: i32| perm[(i & 511) as usize] as i32;
    let f = p.map(f32::floor);
    let (xi, yi, zi) = (f[0] as i32 & 255, f[1] as i32 & 255, f[2] as i32 & 255);
    let (x, y, z) = (p[0] - f[0], p[1] - f[1], p[2] - f[2]);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let a = pm(xi) + yi;
    let aa = pm(a) + zi;
    let ab = pm(a + 1) + zi;
    let b = pm(xi + 1) + yi;
    let ba = pm(b) + zi;
    let bb = pm(b + 1) + zi;
    let x1 = lerp(grad(pm(aa), x, y, z), grad(pm(ba), x - 1.0, y, z), u);
    let x2 = lerp(
        grad(pm(ab), x, y - 1.0, z),
        grad(pm(bb), x - 1.0, y - 1.0, z),
        u,
    );
    let y1 = lerp(x1, x2, v);
    let x3 = lerp(
        grad(pm(aa + 1), x, y, z - 1.0),
        grad(pm(ba + 1), x - 1.0, y, z - 1.0),
        u,
    );
    let x4 = lerp(
        grad(pm(ab + 1), x, y - 1.0, z - 1.0),
        grad(pm(bb + 1), x - 1.0, y - 1.0, z - 1.0),
        u,
    );
    let y2 = lerp(x3, x4, v);
    lerp(y1, y2, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_is_a_permutation() {
        let p = permutation(7);
        let mut seen = [false; 256];
        for &x in &p[..256] {
            seen[x as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
        assert_eq!(p[..256], p[256..]);
        assert_ne!(permutation(7), permutation(8));
    }

    #[test]
    fn perlin_vanishes_on_lattice_and_is_bounded_and_continuous() {
        let perm = permutation(1);
        // Perlin noise is zero at integer lattice points (all gradients dotted with 0).
        for p in [[0.0, 0.0, 0.0], [3.0, -2.0, 5.0], [17.0, 4.0, -9.0]] {
            assert_eq!(perlin(&perm, p), 0.0);
        }
        let mut max: f32 = 0.0;
        for i in 0..2000 {
            let t = i as f32 * 0.0137;
            let p = [t * 1.3, 0.7 - t, 2.0 * t.sin()];
            let v = perlin(&perm, p);
            max = max.max(v.abs());
            // Lipschitz-continuous: a tiny step changes the value a little.
            let w = perlin(&perm, [p[0] + 1e-3, p[1], p[2]]);
            assert!((v - w).abs() < 0.01, "jump at {p:?}: {v} vs {w}");
        }
        assert!(max > 0.2 && max <= 1.1, "max |noise| {max}");
    }

    #[test]
    fn height_map_bilinear_matches_hand_values() {
        let map = HeightMap {
            width: 2,
            height: 2,
            heights: vec![0.0, 1.0, 0.5, 0.25],
        };
        // Texel centres: (0.25, 0.75) is the top-left texel, (0.75, 0.25) the bottom-right.
        assert!((map.sample([0.25, 0.75]) - 0.0).abs() < 1e-6);
        assert!((map.sample([0.75, 0.75]) - 1.0).abs() < 1e-6);
        assert!((map.sample([0.25, 0.25]) - 0.5).abs() < 1e-6);
        assert!((map.sample([0.75, 0.25]) - 0.25).abs() < 1e-6);
        // The centre averages all four.
        assert!((map.sample([0.5, 0.5]) - 0.4375).abs() < 1e-6);
    }

    #[test]
    fn height_map_without_uvs_is_an_error() {
        let d = Displacement::HeightMap {
            amplitude: 1.0,
            map: HeightMap {
                width: 1,
                height: 1,
                heights: vec![1.0],
            },
        };
        assert!(matches!(d.validate(false), Err(GpuError::BadOption(_))));
    }
}
