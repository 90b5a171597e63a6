//! Labelled side-by-side panels, with a tiny built-in 5x7 bitmap font (the classic column-major
//! glyphs; bit 0 is the top row). Lowercase letters are drawn as capitals.

use image::{Rgba, RgbaImage};

/// Separator width between panels, pixels.
/// Pixels between panels.
pub const GAP: u32 = 2;

fn glyph(c: char) -> [u8; 5] {
    match c.to_ascii_uppercase() {
        '(' => [0x00, 0x1C, 0x22, 0x41, 0x00],
        ')' => [0x00, 0x41, 0x22, 0x1C, 0x00],
        '+' => [0x08, 0x08, 0x3E, 0x08, 0x08],
        ',' => [0x00, 0x50, 0x30, 0x00, 0x00],
        '-' => [0x08, 0x08, 0x08, 0x08, 0x08],
        '.' => [0x00, 0x60, 0x60, 0x00, 0x00],
        '/' => [0x20, 0x10, 0x08, 0x04, 0x02],
        '0' => [0x3E, 0x51, 0x49, 0x45, 0x3E],
        '1' => [0x00, 0x42, 0x7F, 0x40, 0x00],
        '2' => [0x42, 0x61, 0x51, 0x49, 0x46],
        '3' => [0x21, 0x41, 0x45, 0x4B, 0x31],
        '4' => [0x18, 0x14, 0x12, 0x7F, 0x10],
        '5' => [0x27, 0x45, 0x45, 0x45, 0x39],
        '6' => [0x3C, 0x4A, 0x49, 0x49, 0x30],
        '7' => [0x01, 0x71, 0x09, 0x05, 0x03],
        '8' => [0x36, 0x49, 0x49, 0x49, 0x36],
        '9' => [0x06, 0x49, 0x49, 0x29, 0x1E],
        ':' => [0x00, 0x36, 0x36, 0x00, 0x00],
        '=' => [0x14, 0x14, 0x14, 0x14, 0x14],
        'A' => [0x7E, 0x11, 0x11, 0x11, 0x7E],
        'B' => [0x7F, 0x49, 0x49, 0x49, 0x36],
        'C' => [0x3E, 0x41, 0x41, 0x41, 0x22],
        'D' => [0x7F, 0x41, 0x41, 0x22, 0x1C],
        'E' => [0x7F, 0x49, 0x49, 0x49, 0x41],
        'F' => [0x7F, 0x09, 0x09, 0x09, 0x01],
        'G' => [0x3E, 0x41, 0x49, 0x49, 0x7A],
        'H' => [0x7F, 0x08, 0x08, 0x08, 0x7F],
        'I' => [0x00, 0x41, 0x7F, 0x41, 0x00],
        'J' => [0x20, 0x40, 0x41, 0x3F, 0x01],
        'K' => [0x7F, 0x08, 0x14, 0x22, 0x41],
        'L' => [0x7F, 0x40, 0x40, 0x40, 0x40],
        'M' => [0x7F, 0x02, 0x0C, 0x02, 0x7F],
        'N' => [0x7F, 0x04, 0x08, 0x10, 0x7F],
        'O' => [0x3E, 0x41, 0x41, 0x41, 0x3E],
        'P' => [0x7F, 0x09, 0x09, 0x09, 0x06],
        'Q' => [0x3E, 0x41, 0x51, 0x21, 0x5E],
        'R' => [0x7F, 0x09, 0x19, 0x29, 0x46],
        'S' => [0x46, 0x49, 0x49, 0x49, 0x31],
        'T' => [0x01, 0x01, 0x7F, 0x01, 0x01],
        'U' => [0x3F, 0x40, 0x40, 0x40, 0x3F],
        'V' => [0x1F, 0x20, 0x40, 0x20, 0x1F],
        'W' => [0x3F, 0x40, 0x38, 0x40, 0x3F],
        'X' => [0x63, 0x14, 0x08, 0x14, 0x63],
        'Y' => [0x07, 0x08, 0x70, 0x08, 0x07],
        'Z' => [0x61, 0x51, 0x49, 0x45, 0x43],
        '_' => [0x40, 0x40, 0x40, 0x40, 0x40],
        // Space and anything unknown: blank.
        _ => [0; 5],
    }
}

/// Draws `text` with its top-left corner at `(x, y)`, each font pixel `scale` pixels wide,
/// on a light box so it reads on any background. Clipped to the image.
pub fn draw_label(image: &mut RgbaImage, text: &str, x: u32, y: u32, scale: u32) {
    let chars = text.chars().count() as u32;
    let (bw, bh) = ((chars * 6 + 1) * scale, 9 * scale);
    let put = |image: &mut RgbaImage, px: u32, py: u32, color: Rgba<u8>| {
        if px < image.width() && py < image.height() {
            image.put_pixel(px, py, color);
        }
    };
    for py in y..y + bh {
        for px in x..x + bw {
            put(image, px, py, Rgba([255, 255, 255, 220]));
        }
    }
    for (i, c) in text.chars().enumerate() {
        for (col, bits) in glyph(c).iter().enumerate() {
            for row in 0..7 {
                if bits >> row & 1 == 1 {
                    let gx = x + (1 + i as u32 * 6 + col as u32) * scale;
                    let gy = y + (1 + row) * scale;
                    for dy in 0..scale {
                        for dx in 0..scale {
                            put(image, gx + dx, gy + dy, Rgba([20, 20, 30, 255]));
                        }
                    }
                }
            }
        }
    }
}

/// Puts pictures in a row, separated by dark lines, each labelled at its top left (widths may
/// differ; the row is as tall as the tallest).
pub fn side_by_side(pictures: &[RgbaImage], labels: &[&str]) -> RgbaImage {
    let h = pictures.iter().map(|p| p.height()).max().unwrap_or(0);
    let n = pictures.len() as u32;
    let width = pictures.iter().map(|p| p.width()).sum::<u32>() + n.saturating_sub(1) * GAP;
    let mut out = RgbaImage::from_pixel(width, h, Rgba([40, 40, 48, 255]));
    let scale = (pictures.first().map_or(0, |p| p.width()) / 128).clamp(1, 4);
    let mut x0 = 0;
    for (picture, label) in pictures.iter().zip(labels) {
        image::imageops::replace(&mut out, picture, x0 as i64, 0);
        draw_label(&mut out, label, x0 + 2 * scale, 2 * scale, scale);
        x0 += picture.width() + GAP;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_are_placed_with_separators_and_labels() {
        let red = RgbaImage::from_pixel(20, 10, Rgba([255, 0, 0, 255]));
        let blue = RgbaImage::from_pixel(20, 10, Rgba([0, 0, 255, 255]));
        let out = side_by_side(&[red, blue], &["", ""]);
        assert_eq!(out.dimensions(), (42, 10));
        assert_eq!(out.get_pixel(19, 9), &Rgba([255, 0, 0, 255]));
        assert_eq!(out.get_pixel(20, 9), &Rgba([40, 40, 48, 255]));
        assert_eq!(out.get_pixel(22, 9), &Rgba([0, 0, 255, 255]));
        // A label darkens some pixels inside its box.
        let mut img = RgbaImage::from_pixel(40, 20, Rgba([255, 255, 255, 255]));
        draw_label(&mut img, "PN", 0, 0, 1);
        let dark = img.pixels().filter(|p| p.0[0] < 100).count();
        assert!(dark > 10, "{dark} dark pixels");
    }
}
