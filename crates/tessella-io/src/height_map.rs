//! Height maps for displacement, read from image files.
//!
//! The displacement itself (sampling, offsets, directions) is geometry and lives in
//! [`tessella_core::displace`]; this crate only turns a file into a [`HeightMap`].

use crate::error::IoError;
use std::path::Path;
use tessella_core::displace::HeightMap;

/// Reads a height map from an image file (PNG): its luminance in `0..=1`, row-major from the
/// image's top row (the map's `v = 1`).
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("ramp.png");
/// let image = image::GrayImage::from_fn(2, 1, |x, _| image::Luma([(x * 255) as u8]));
/// image.save(&path).unwrap();
/// let map = tessella_io::read_height_map(&path)?;
/// assert_eq!((map.width, map.height), (2, 1));
/// assert_eq!(map.heights, vec![0.0, 1.0]);
/// # Ok::<(), tessella_io::IoError>(())
/// ```
pub fn read_height_map(path: &Path) -> Result<HeightMap, IoError> {
    let parse = |message: String| IoError::Parse {
        path: path.to_path_buf(),
        format: "height map image",
        message,
    };
    let image = image::open(path).map_err(|e| match e {
        image::ImageError::IoError(source) => IoError::Read {
            path: path.to_path_buf(),
            source,
        },
        e => parse(e.to_string()),
    })?;
    let gray = image.to_luma32f();
    let (width, height) = gray.dimensions();
    HeightMap::new(width, height, gray.into_raw()).map_err(|e| parse(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn luminance_rows_from_the_top() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("map.png");
        // 3x2: top row 0, 51, 102; bottom row 153, 204, 255 (grey levels / 255).
        let image = image::GrayImage::from_fn(3, 2, |x, y| image::Luma([(51 * (x + 3 * y)) as u8]));
        image.save(&path).unwrap();
        let map = read_height_map(&path).unwrap();
        assert_eq!((map.width, map.height), (3, 2));
        for (i, h) in map.heights.iter().enumerate() {
            assert!((h - 0.2 * i as f32).abs() < 1e-6, "texel {i}: {h}");
        }
        // v = 1 is the top row: the bilinear sample at the top-left texel's centre is 0.
        assert!(map.sample([1.0 / 6.0, 0.75]).abs() < 1e-6);
    }

    #[test]
    fn missing_and_malformed_files_are_clear_errors() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("none.png");
        assert!(matches!(
            read_height_map(&missing),
            Err(IoError::Read { .. })
        ));
        let garbage = dir.path().join("garbage.png");
        std::fs::write(&garbage, b"not a png").unwrap();
        let err = read_height_map(&garbage).unwrap_err();
        assert!(matches!(err, IoError::Parse { .. }), "{err}");
        assert!(err.to_string().contains("garbage.png"), "{err}");
    }
}
