//! `tessella.render`: a picture of the refined surface through tessella-view (the CLI's
//! `tessella render`), optionally coloured by a per-vertex field with a colour bar
//! (`--color-by`, `--colormap`, `--range`) and as labelled panels of several schemes
//! (`--compare`). Needs the `gpu` feature (wgpu; lavapipe counts); without it a `ValueError`.
//! The arrays are read with the GIL held, everything else runs without it.

#[cfg(feature = "gpu")]
use crate::arrays::FieldIn;
use numpy::PyArray3;
#[cfg(feature = "gpu")]
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;

/// What `tessella.render` raises in a build without the `gpu` feature.
#[cfg(not(feature = "gpu"))]
pub const NO_GPU_RENDER: &str = "this tessella package was built without GPU support (the \
     \"gpu\" cargo feature is off), which tessella.render needs; rebuild with the default \
     features";

/// Without the `gpu` feature: a `ValueError`, whatever the arguments (the Python wrapper
/// `tessella.render` holds the signature).
#[cfg(not(feature = "gpu"))]
#[pyfunction]
#[pyo3(signature = (*_args, **_kwargs))]
pub fn render<'py>(
    _args: &Bound<'py, pyo3::types::PyTuple>,
    _kwargs: Option<&Bound<'py, pyo3::types::PyDict>>,
) -> PyResult<Bound<'py, PyArray3<u8>>> {
    Err(crate::errors::bad_option(NO_GPU_RENDER))
}

/// Renders a mesh; see `tessella.render` (the Python wrapper) for the full documentation.
#[cfg(feature = "gpu")]
#[pyfunction]
#[pyo3(signature = (vertices, faces, mids=None, normals=None, *, scheme="pn", level=8,
                    size=(512, 512), yaw=30.0, pitch=20.0, zoom=1.0, wireframe=false,
                    compare=None, point_data=Vec::new(), color_by=None, colormap="viridis",
                    range=None, colorbar=true, label=None, path=None))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: &Bound<'py, PyAny>,
    mids: Option<PyReadonlyArray2<'py, i64>>,
    normals: Option<&Bound<'py, PyAny>>,
    scheme: &str,
    level: i64,
    size: (i64, i64),
    yaw: f64,
    pitch: f64,
    zoom: f64,
    wireframe: bool,
    compare: Option<Vec<String>>,
    point_data: Vec<FieldIn<'py>>,
    color_by: Option<String>,
    colormap: &str,
    range: Option<(f64, f64)>,
    colorbar: bool,
    label: Option<String>,
    path: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyArray3<u8>>> {
    use crate::errors::{bad_option, gpu_failure};
    use crate::{errors, gpu, options};
    use numpy::ndarray::Array3;
    use tessella_core::RefineOptions;
    use tessella_view::{colormap as bar, Colormap, FieldColors, RenderOptions};

    let refine_for = |name: &str| -> PyResult<(String, RefineOptions)> {
        let options = options::refine_options(options::Given {
            scheme: name,
            level: level.to_string(),
            ..Default::default()
        })?;
        Ok((options.scheme.name().to_string(), options))
    };
    let single = refine_for(scheme)?;
    let panels = compare
        .map(|names| {
            names
                .iter()
                .map(|n| refine_for(n))
                .collect::<PyResult<Vec<_>>>()
        })
        .transpose()?;
    let side = |x: i64, what: &str| {
        u32::try_from(x).map_err(|_| {
            bad_option(format!(
                "size=({}, {}): the {what} must be a whole number of pixels, 1 or more",
                size.0, size.1
            ))
        })
    };
    let size = (side(size.0, "width")?, side(size.1, "height")?);
    let colormap: Colormap = colormap.parse().map_err(bad_option)?;
    let range = match range {
        None => None,
        Some((lo, hi)) if lo.is_finite() && hi.is_finite() && lo < hi => {
            Some([lo as f32, hi as f32])
        }
        Some((lo, hi)) => {
            return Err(bad_option(format!(
                "range=({lo}, {hi}): give (min, max), two finite numbers with min < max"
            )))
        }
    };
    let field = match color_by {
        None => None,
        Some(name) => {
            let Some((_, values)) = point_data.iter().find(|(n, _)| *n == name) else {
                let have: Vec<&str> = point_data.iter().map(|(n, _)| n.as_str()).collect();
                return Err(bad_option(format!(
                    "color_by={name:?}: no such field in point_data; {}",
                    if have.is_empty() {
                        "it has none (give point_data={name: values})".to_string()
                    } else {
                        format!("it has {}", have.join(", "))
                    }
                )));
            };
            let a = values.as_array();
            if a.ncols() != 1 {
                return Err(bad_option(format!(
                    "color_by={name:?}: the field has {} components; colour by one (a 1-D \
                     array or one column)",
                    a.ncols()
                )));
            }
            Some(FieldColors {
                name,
                values: a.iter().copied().collect(),
                colormap,
                range,
            })
        }
    };
    drop(point_data);
    let mesh = crate::mesh_with_mids_from(py, vertices, faces, mids, normals, None)?;
    let picture = py.detach(|| -> PyResult<_> {
        // Without the bar: drawn as wide as asked plus the bar, which is then cut off.
        let bar_cut = match (&field, colorbar) {
            (Some(_), false) => bar::bar_width(size.1),
            _ => 0,
        };
        let view = RenderOptions {
            size: (size.0.saturating_add(bar_cut), size.1),
            yaw: yaw as f32,
            pitch: pitch as f32,
            zoom: zoom as f32,
            wireframe,
            field,
            ..RenderOptions::default()
        };
        let ctx = gpu::any()
            .map_err(|e| gpu_failure(format!("tessella.render needs a GPU adapter: {e}")))?;
        let mut picture = match &panels {
            None => tessella_view::render(&ctx, &mesh, &single.1, &view),
            Some(panels) => tessella_view::render_compare(&ctx, &mesh, panels, &view),
        }
        .map_err(errors::gpu_error)?;
        if bar_cut > 0 {
            picture = image_crop(&picture, size.0, size.1);
        }
        if let Some(text) = label.as_deref().filter(|t| !t.is_empty()) {
            let scale = (size.0.min(size.1) / 128).clamp(1, 4);
            tessella_view::font::draw_label(&mut picture, text, 2 * scale, 2 * scale, scale);
        }
        if let Some(path) = &path {
            tessella_view::save_png(&picture, path).map_err(|e| match e {
                tessella_view::GpuError::Write { .. } => {
                    errors::os_error(std::io::ErrorKind::Other, e.to_string())
                }
                e => errors::gpu_error(e),
            })?;
        }
        Ok(picture)
    })?;
    let (w, h) = picture.dimensions();
    let a = Array3::from_shape_vec((h as usize, w as usize, 4), picture.into_raw())
        .map_err(|e| gpu_failure(e.to_string()))?;
    Ok(PyArray3::from_owned_array(py, a))
}

/// The left `w` x `h` pixels of `picture`.
#[cfg(feature = "gpu")]
fn image_crop(picture: &tessella_view::RgbaImage, w: u32, h: u32) -> tessella_view::RgbaImage {
    let mut out = tessella_view::RgbaImage::new(w, h);
    for (x, y, p) in out.enumerate_pixels_mut() {
        *p = *picture.get_pixel(x, y);
    }
    out
}
