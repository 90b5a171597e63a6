//! How every picture frames a mesh: `tessella render`'s, the viewer's (WebGPU and its WebGL2
//! fallback, through the npm package's `sceneCamera`) and the Bevy example's. A camera frames a
//! bounding sphere with the vertical field of view [`FOV_Y_DEGREES`], orbits it (yaw about +Y,
//! pitch up), zooms and pans; a key light sits above-left of the viewer.
//!
//! ```
//! use tessella_core::framing::Framing;
//! // Yaw, pitch (degrees), zoom and pan; then the width-to-height ratio.
//! let f = Framing::sphere([0.0, 0.0, 0.0], 1.0, (0.0, 0.0, 1.0, [0.0, 0.0]), 1.0);
//! // Yaw 0, pitch 0: the eye on +Z, looking down -Z.
//! assert!(f.eye[2] > 0.0 && (f.forward[2] + 1.0).abs() < 1e-6);
//! ```

use glam::{Mat4, Vec3};

/// Vertical field of view.
pub const FOV_Y_DEGREES: f32 = 30.0;

/// A framed view: where the camera is, how it projects, and the light.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Framing {
    /// Projection times view, column-major columns, onto wgpu's clip space (depth `0..=w`).
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 3],
    /// The point looked at: the framed centre, moved by the pan.
    pub target: [f32; 3],
    /// The world's up direction the view was made with (+Y, or +Z looking straight down).
    pub up: [f32; 3],
    /// Unit direction towards the light: a key light above-left of the viewer.
    pub light_dir: [f32; 3],
    /// The view's unit axes: right, up (on screen) and forward (into the screen).
    pub right: [f32; 3],
    pub view_up: [f32; 3],
    pub forward: [f32; 3],
    /// From the eye to the target.
    pub distance: f32,
}

/// Centre and radius of a sphere around `points` (the bounding box's centre; a radius of at
/// least `1e-6`).
pub fn bounding_sphere(points: &[[f32; 3]]) -> ([f32; 3], f32) {
    let (lo, hi) = crate::mesh::bounds(points);
    let center = (Vec3::from(lo) + Vec3::from(hi)) * 0.5;
    let radius = points
        .iter()
        .map(|&p| Vec3::from(p).distance(center))
        .fold(0.0f32, f32::max);
    (center.into(), radius.max(1e-6))
}

impl Framing {
    /// The view of `points`: their bounding sphere grown by 1.2, since curved patches bulge
    /// past the coarse hull, plus `reach` (how far displacement can move a point); see
    /// [`Framing::sphere`] for the rest.
    pub fn points(
        points: &[[f32; 3]],
        reach: f32,
        (yaw, pitch, zoom, pan): (f32, f32, f32, [f32; 2]),
        aspect: f32,
    ) -> Framing {
        let (center, radius) = bounding_sphere(points);
        Framing::sphere(
            center,
            radius * 1.2 + reach,
            (yaw, pitch, zoom, pan),
            aspect,
        )
    }

    /// Frames the sphere `(center, radius)` with the width-to-height ratio `aspect`: `yaw`
    /// turns about +Y and `pitch` raises the eye (degrees), `zoom > 1` moves closer, `pan`
    /// moves the point looked at (and the eye with it) along the view's right and up axes by
    /// `pan × radius`. A radius, zoom or aspect that is not positive and finite gives a
    /// matrix of infinities or NaN: callers with user input check them first (the npm
    /// package's `sceneCamera` does).
    pub fn sphere(
        center: [f32; 3],
        radius: f32,
        (yaw, pitch, zoom, pan): (f32, f32, f32, [f32; 2]),
        aspect: f32,
    ) -> Framing {
        let center = Vec3::from(center);
        let fov_y = FOV_Y_DEGREES.to_radians();
        let half_x = ((fov_y * 0.5).tan() * aspect).atan();
        let half = (fov_y * 0.5).min(half_x);
        let distance = radius / half.sin() / zoom;
        let (yaw, pitch) = (yaw.to_radians(), pitch.to_radians());
        let dir = Vec3::new(
            pitch.cos() * yaw.sin(),
            pitch.sin(),
            pitch.cos() * yaw.cos(),
        );
        let up = if dir.y.abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let center = if pan == [0.0, 0.0] {
            center
        } else {
            let right = (-dir).cross(up).normalize();
            let view_up = right.cross(-dir);
            center + (right * pan[0] + view_up * pan[1]) * radius
        };
        let eye = center + dir * distance;
        let view = glam::camera::rh::view::look_at_mat4(eye, center, up);
        let near = (distance - radius * 1.5).max(distance * 0.01);
        let far = distance + radius * 1.5;
        // glam's right-handed projection onto wgpu's NDC (depth `0..=1`, Y up: DirectX's).
        let proj = glam::camera::rh::proj::directx::perspective(fov_y, aspect, near, far);
        let forward = (center - eye).normalize();
        let right = forward.cross(up).normalize();
        let view_up = right.cross(forward);
        let light_dir = (-0.45 * right + 0.6 * view_up - 0.65 * forward).normalize();
        Framing {
            view_proj: (proj * view).to_cols_array_2d(),
            eye: eye.into(),
            target: center.into(),
            up: up.into(),
            light_dir: light_dir.into(),
            right: right.into(),
            view_up: view_up.into(),
            forward: forward.into(),
            distance,
        }
    }

    /// [`Framing::view_proj`] as a `glam` matrix.
    pub fn view_proj_mat4(&self) -> Mat4 {
        Mat4::from_cols_array_2d(&self.view_proj)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framed_sphere_projects_inside_the_view() {
        let (c, r) = (Vec3::new(1.0, 2.0, 3.0), 2.0);
        for (yaw, pitch, aspect) in [(0.0, 0.0, 1.0), (45.0, 30.0, 2.0), (200.0, -60.0, 0.5)] {
            let f = Framing::sphere(c.into(), r, (yaw, pitch, 1.0, [0.0, 0.0]), aspect);
            let m = f.view_proj_mat4();
            let centre = m * c.extend(1.0);
            let ndc = centre.truncate() / centre.w;
            assert!(ndc.x.abs() < 1e-4 && ndc.y.abs() < 1e-4 && ndc.z > 0.0 && ndc.z < 1.0);
            // Points on the sphere stay within the view (NDC x,y in -1..1, depth in 0..1).
            for d in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
                let p = m * (c + d * r).extend(1.0);
                let q = p.truncate() / p.w;
                assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "{q:?}");
                assert!(q.z > 0.0 && q.z < 1.0, "{q:?}");
            }
            // The eye is `distance` from the target, along -forward; the axes are orthonormal.
            let (eye, target) = (Vec3::from(f.eye), Vec3::from(f.target));
            assert!((eye.distance(target) - f.distance).abs() < 1e-4 * f.distance);
            let [x, y, z] = [f.right, f.view_up, f.forward].map(Vec3::from);
            assert!((eye + z * f.distance).distance(target) < 1e-4 * f.distance);
            for (a, b) in [(x, y), (y, z), (z, x)] {
                assert!(a.dot(b).abs() < 1e-5 && (a.length() - 1.0).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn pan_moves_the_centre_off_the_middle_of_the_view() {
        let (c, r) = (Vec3::new(1.0, 2.0, 3.0), 2.0);
        let f = Framing::sphere(c.into(), r, (30.0, 20.0, 1.0, [0.25, -0.5]), 1.0);
        let m = f.view_proj_mat4();
        // The panned target is in the middle; the sphere's centre left of and above it.
        let t = m * Vec3::from(f.target).extend(1.0);
        assert!((t.x / t.w).abs() < 1e-4 && (t.y / t.w).abs() < 1e-4);
        let p = m * c.extend(1.0);
        let (x, y) = (p.x / p.w, p.y / p.w);
        assert!(x < -0.01 && y > 0.01, "{x} {y}");
        assert!((Vec3::from(f.target).distance(c) - r * (0.25f32.hypot(0.5))).abs() < 1e-4);
    }

    #[test]
    fn points_are_framed_by_their_grown_bounding_sphere() {
        let points = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
        let (c, r) = bounding_sphere(&points);
        assert_eq!(c, [1.0, 2.0, 0.0]);
        assert!((r - 5.0f32.sqrt()).abs() < 1e-6);
        let view = (10.0, 5.0, 1.0, [0.0, 0.0]);
        let f = Framing::points(&points, 0.5, view, 1.5);
        assert_eq!(f, Framing::sphere(c, r * 1.2 + 0.5, view, 1.5));
    }
}
