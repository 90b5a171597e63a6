//! The paper's picture: the input triangulation, PN with quadratic ("fake") normals, PN with
//! real normals, coloured by normal (`0.5 n + 0.5`), drawn by the GL tessellation stages.
//!
//! `cargo run --release -p tessella-gl --example picture -- OUT.png [LEVEL]`

use glam::{Mat4, Vec3, Vec4};
use tessella_core::refine::{Levels, Spacing};
use tessella_core::{samples, NormalMode, RefineOptions, Scheme};
use tessella_gl::{GlContext, GlTessellator};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "gl-normals.png".into());
    let level: f32 = args.next().and_then(|a| a.parse().ok()).unwrap_or(8.0);
    let ctx = GlContext::new()?;
    let mut gl = GlTessellator::new(&ctx)?;
    let mesh = samples::by_name("torus").ok_or("no torus sample")?;
    let (lo, hi) = mesh.bounds();
    let centre = (Vec3::from(lo) + Vec3::from(hi)) * 0.5;
    let r = mesh.diagonal() * 0.5;
    let (w, h) = (360, 360);
    let view = look_at(centre + Vec3::new(0.0, -1.6, 1.6) * r, centre, Vec3::Z);
    let proj = perspective(40f32.to_radians(), 1.0, 0.05 * r, 10.0 * r);
    let vp = (proj * view).to_cols_array();
    let panels = [
        (Scheme::Flat, NormalMode::Linear, 1.0, true),
        (Scheme::Pn, NormalMode::Quadratic, level, false),
        (Scheme::Pn, NormalMode::Real, level, false),
    ];
    let mut picture = image::RgbaImage::new(w as u32 * 3, h as u32);
    for (i, (scheme, normals, level, wire)) in panels.into_iter().enumerate() {
        let o = RefineOptions::new(scheme, 1)
            .with_normals(normals)
            .with_spacing(Spacing::Equal)
            .with_levels(Levels::Uniform(level));
        let p = gl.prepare(&mesh, &o, None)?;
        let pixels = gl.render(&p, &vp, w, h, wire)?;
        for y in 0..h as u32 {
            for x in 0..w as u32 {
                let k = (((h as u32 - 1 - y) * w as u32 + x) * 4) as usize;
                let px = [pixels[k], pixels[k + 1], pixels[k + 2], 255];
                picture.put_pixel(i as u32 * w as u32 + x, y, image::Rgba(px));
            }
        }
    }
    picture.save(&out)?;
    println!(
        "{out}: input triangulation | PN, quadratic normals | PN, real normals (level {level}, {})",
        ctx.info().renderer
    );
    Ok(())
}

/// Right-handed view matrix looking from `eye` at `center`.
fn look_at(eye: Vec3, center: Vec3, up: Vec3) -> Mat4 {
    let f = (center - eye).normalize();
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -f.x, 0.0),
        Vec4::new(s.y, u.y, -f.y, 0.0),
        Vec4::new(s.z, u.z, -f.z, 0.0),
        Vec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// Right-handed perspective projection onto GL's depth range `-1..=1`.
fn perspective(fov_y: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let h = 1.0 / (fov_y * 0.5).tan();
    Mat4::from_cols(
        Vec4::new(h / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, h, 0.0, 0.0),
        Vec4::new(0.0, 0.0, (far + near) / (near - far), -1.0),
        Vec4::new(0.0, 0.0, 2.0 * far * near / (near - far), 0.0),
    )
}
