//! Pixel counts shared by the picture tests.

use image::RgbaImage;

/// The back-face colour of the crack pictures: on a closed, outward surface a back face seen is
/// the inside seen through a crack.
pub const MAGENTA: [u8; 3] = [255, 0, 255];

/// Pixels with a magenta tint (some sample of them saw a back face) inside the silhouette: at
/// least 2 pixels from the white background, since where the rim's front and back triangles
/// meet, depth ties can let a back face win a sample.
pub fn crack_pixels(image: &RgbaImage) -> usize {
    let (w, h) = image.dimensions();
    let background = |x: i64, y: i64| {
        x < 0
            || y < 0
            || x >= w as i64
            || y >= h as i64
            || image.get_pixel(x as u32, y as u32).0[..3] == [255; 3]
    };
    image
        .enumerate_pixels()
        .filter(|&(x, y, p)| {
            let [r, g, b, _] = p.0.map(i32::from);
            let (x, y) = (x as i64, y as i64);
            r > g + 24
                && b > g + 24
                && (-2..=2).all(|dy| (-2..=2).all(|dx| !background(x + dx, y + dy)))
        })
        .count()
}
