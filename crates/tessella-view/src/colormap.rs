//! Colormaps for pictures coloured by a scalar field, and the colour bar drawn beside them.
//!
//! The samples are matplotlib's (3.11): `matplotlib.colormaps[name](np.linspace(0, 1, 17))`,
//! rounded to 8-bit sRGB. viridis is van der Walt and Smith's perceptually uniform map
//! (matplotlib's `_cm_listed._viridis_data`), coolwarm Moreland's diverging map
//! ("Diverging Color Maps for Scientific Visualization", 2009). Between samples the colour is
//! interpolated linearly in sRGB, here and in the shader.

use image::{Rgba, RgbaImage};
use std::str::FromStr;

/// A colormap by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Colormap {
    /// Dark purple (low) through blue and green to yellow (high).
    #[default]
    Viridis,
    /// Blue (low) through grey to red (high), for values about a middle.
    Coolwarm,
}

const VIRIDIS: [[u8; 3]; 17] = [
    [68, 1, 84],
    [72, 24, 106],
    [71, 45, 123],
    [66, 64, 134],
    [59, 82, 139],
    [51, 99, 141],
    [44, 114, 142],
    [38, 130, 142],
    [33, 145, 140],
    [31, 160, 136],
    [40, 174, 128],
    [63, 188, 115],
    [94, 201, 98],
    [132, 212, 75],
    [173, 220, 48],
    [216, 226, 25],
    [253, 231, 37],
];

const COOLWARM: [[u8; 3]; 17] = [
    [59, 76, 192],
    [78, 104, 216],
    [98, 130, 234],
    [119, 154, 247],
    [141, 176, 254],
    [163, 194, 254],
    [185, 208, 249],
    [204, 217, 237],
    [221, 220, 220],
    [236, 211, 197],
    [245, 196, 172],
    [247, 176, 147],
    [244, 152, 122],
    [235, 125, 98],
    [221, 95, 75],
    [202, 59, 55],
    [180, 4, 38],
];

impl Colormap {
    /// Every colormap's name.
    pub const NAMES: [&'static str; 2] = ["viridis", "coolwarm"];

    /// The name [`Colormap::from_str`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Colormap::Viridis => "viridis",
            Colormap::Coolwarm => "coolwarm",
        }
    }

    /// The sRGB samples, evenly spaced from low to high.
    pub fn samples(self) -> &'static [[u8; 3]] {
        match self {
            Colormap::Viridis => &VIRIDIS,
            Colormap::Coolwarm => &COOLWARM,
        }
    }

    /// The samples as `0..=1` floats, for the renderer.
    pub fn samples_f32(self) -> Vec<[f32; 3]> {
        self.samples()
            .iter()
            .map(|c| c.map(|x| x as f32 / 255.0))
            .collect()
    }

    /// The sRGB colour at `t` in `[0, 1]` (clamped), interpolated between samples.
    pub fn color(self, t: f32) -> [u8; 3] {
        let s = self.samples();
        let x = t.clamp(0.0, 1.0) * (s.len() - 1) as f32;
        let k = (x.floor() as usize).min(s.len() - 1);
        let k1 = (k + 1).min(s.len() - 1);
        let f = x - k as f32;
        std::array::from_fn(|c| {
            (s[k][c] as f32 + (s[k1][c] as f32 - s[k][c] as f32) * f).round() as u8
        })
    }
}

impl FromStr for Colormap {
    type Err = String;
    fn from_str(s: &str) -> Result<Colormap, String> {
        match s.to_ascii_lowercase().as_str() {
            "viridis" => Ok(Colormap::Viridis),
            "coolwarm" => Ok(Colormap::Coolwarm),
            _ => Err(format!(
                "unknown colormap {s:?}; use one of {:?}",
                Colormap::NAMES
            )),
        }
    }
}

/// A scalar field to colour a picture by: one value per vertex of the mesh drawn (mid-edge
/// nodes of second-order faces included), interpolated with each face's shape functions.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldColors {
    /// Shown above the colour bar.
    pub name: String,
    pub values: Vec<f32>,
    pub colormap: Colormap,
    /// Values mapped to the colormap's ends; `None`: the field's smallest and largest value.
    pub range: Option<[f32; 2]>,
}

impl FieldColors {
    /// The range the colours span: [`FieldColors::range`] or the data's.
    pub fn resolved_range(&self) -> [f32; 2] {
        self.range.unwrap_or_else(|| {
            let lo = self.values.iter().copied().fold(f32::INFINITY, f32::min);
            let hi = self
                .values
                .iter()
                .copied()
                .fold(f32::NEG_INFINITY, f32::max);
            if lo <= hi {
                [lo, hi]
            } else {
                [0.0, 1.0]
            }
        })
    }
}

/// Text for a range end: up to four significant digits, scientific for very large or small.
pub fn format_value(x: f32) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-2..1e5).contains(&a) {
        return format!("{x:.2e}");
    }
    let decimals = if a == 0.0 {
        0
    } else {
        (3 - a.log10().floor() as i32).clamp(0, 3) as usize
    };
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The font scale of a colour bar for a picture `height` pixels tall.
fn scale(height: u32) -> u32 {
    (height / 300).clamp(1, 3)
}

/// Width in pixels of the strip [`color_bar`] draws for a picture `height` pixels tall.
pub fn bar_width(height: u32) -> u32 {
    84 * scale(height)
}

/// The colour bar: a vertical gradient of `field`'s colormap (high at the top) with the range's
/// ends written beside it and the field's name above, on `background`, `height` pixels tall.
pub fn color_bar(field: &FieldColors, height: u32, background: [u8; 4]) -> RgbaImage {
    let s = scale(height);
    let width = bar_width(height);
    let mut out = RgbaImage::from_pixel(width, height, Rgba(background));
    let [lo, hi] = field.resolved_range();
    let (x0, bar_w) = (4 * s, 14 * s);
    let (top, bottom) = (24 * s, height.saturating_sub(14 * s));
    if bottom <= top + 1 {
        return out;
    }
    for y in top..bottom {
        let t = (bottom - 1 - y) as f32 / (bottom - 1 - top) as f32;
        let [r, g, b] = field.colormap.color(t);
        for x in x0..x0 + bar_w {
            out.put_pixel(x, y, Rgba([r, g, b, 255]));
        }
    }
    let name: String = field.name.chars().take(12).collect();
    crate::font::draw_label(&mut out, &name, s, 4 * s, s);
    let label_x = x0 + bar_w + 2 * s;
    crate::font::draw_label(&mut out, &format_value(hi), label_x, top, s);
    crate::font::draw_label(
        &mut out,
        &format_value(lo),
        label_x,
        bottom.saturating_sub(9 * s),
        s,
    );
    out
}

/// `picture` with `bar` appended on its right.
pub fn with_bar(picture: &RgbaImage, bar: &RgbaImage) -> RgbaImage {
    let mut out = RgbaImage::new(picture.width() + bar.width(), picture.height());
    image::imageops::replace(&mut out, picture, 0, 0);
    image::imageops::replace(&mut out, bar, picture.width() as i64, 0);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_colors_and_labels() {
        assert_eq!("coolwarm".parse(), Ok(Colormap::Coolwarm));
        let err = "nope".parse::<Colormap>().unwrap_err();
        assert_eq!(
            err,
            r#"unknown colormap "nope"; use one of ["viridis", "coolwarm"]"#
        );
        assert_eq!(Colormap::Viridis.color(0.0), [68, 1, 84]);
        assert_eq!(Colormap::Viridis.color(1.0), [253, 231, 37]);
        assert_eq!(Colormap::Viridis.color(0.5), [33, 145, 140]);
        assert_eq!(format_value(20.0), "20");
        assert_eq!(format_value(-0.125), "-0.125");
        assert_eq!(format_value(99.96), "99.96");
        assert_eq!(format_value(1.5e6), "1.50e6");
    }
}
