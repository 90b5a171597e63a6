//! A camera that frames a bounding sphere, orbits it (yaw, pitch) and zooms.

use glam::{Mat4, Vec3};

/// Vertical field of view.
pub const FOV_Y_DEGREES: f32 = 30.0;

/// Where the camera is and how it projects.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Camera {
    pub view_proj: Mat4,
    pub eye: Vec3,
    /// The point looked at: the framed centre, moved by the pan.
    pub target: Vec3,
    /// Unit direction towards the light: a key light above-left of the viewer.
    pub light_dir: Vec3,
    /// The world's up direction the view was made with (+Y, or +Z looking straight down).
    pub up: Vec3,
}

/// How every picture frames a mesh (`tessella render`'s, the viewer's, the Bevy example's): the
/// camera position, the point looked at, the up direction and the key light's direction, for a
/// view of points ([`frame_points`]) with the vertical field of view [`FOV_Y_DEGREES`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Framing {
    pub eye: [f32; 3],
    pub target: [f32; 3],
    pub up: [f32; 3],
    /// Unit direction towards the light: above-left of the viewer.
    pub light_dir: [f32; 3],
}

/// The camera that frames `points`: their bounding sphere (the box's centre, the farthest
/// point) grown by 1.2, since curved patches bulge past the coarse hull, and by `reach` (how
/// far displacement can move a point), seen from `yaw`, `pitch`, `zoom` and `pan` with the
/// `aspect` ratio.
pub(crate) fn framed_camera(
    points: &[[f32; 3]],
    reach: f32,
    (yaw, pitch, zoom, pan): (f32, f32, f32, [f32; 2]),
    aspect: f32,
) -> Camera {
    let (center, radius) = bounding_sphere(points);
    Camera::framing(center, radius * 1.2 + reach, yaw, pitch, zoom, pan, aspect)
}

/// The framing of `points` that `tessella render` draws them with (their bounding sphere grown
/// by 1.2, since curved patches bulge past the coarse hull), for a renderer of its own: the Bevy
/// example's camera and light.
pub fn frame_points(points: &[[f32; 3]], yaw: f32, pitch: f32, zoom: f32, aspect: f32) -> Framing {
    let cam = framed_camera(points, 0.0, (yaw, pitch, zoom, [0.0, 0.0]), aspect);
    Framing {
        eye: cam.eye.into(),
        target: cam.target.into(),
        up: cam.up.into(),
        light_dir: cam.light_dir.into(),
    }
}

/// Centre and radius of a sphere around `points` (the bounding box's centre).
pub(crate) fn bounding_sphere(points: &[[f32; 3]]) -> (Vec3, f32) {
    let (lo, hi) = tessella_core::mesh::bounds(points);
    let center = (Vec3::from(lo) + Vec3::from(hi)) * 0.5;
    let radius = points
        .iter()
        .map(|&p| Vec3::from(p).distance(center))
        .fold(0.0f32, f32::max);
    (center, radius.max(1e-6))
}

impl Camera {
    /// Frames the sphere `(center, radius)`: `yaw` turns about +Y, `pitch` raises the eye,
    /// `zoom > 1` moves closer, `pan` moves the point looked at (and the eye with it) along
    /// the view's right and up axes by `pan × radius`.
    pub fn framing(
        center: Vec3,
        radius: f32,
        yaw: f32,
        pitch: f32,
        zoom: f32,
        pan: [f32; 2],
        aspect: f32,
    ) -> Camera {
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
        let cam_up = right.cross(forward);
        let light_dir = (-0.45 * right + 0.6 * cam_up - 0.65 * forward).normalize();
        Camera {
            view_proj: proj * view,
            eye,
            target: center,
            light_dir,
            up,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framed_sphere_projects_inside_the_view() {
        let (c, r) = (Vec3::new(1.0, 2.0, 3.0), 2.0);
        for (yaw, pitch, aspect) in [(0.0, 0.0, 1.0), (45.0, 30.0, 2.0), (200.0, -60.0, 0.5)] {
            let cam = Camera::framing(c, r, yaw, pitch, 1.0, [0.0, 0.0], aspect);
            let centre = cam.view_proj * c.extend(1.0);
            let ndc = centre.truncate() / centre.w;
            assert!(ndc.x.abs() < 1e-4 && ndc.y.abs() < 1e-4 && ndc.z > 0.0 && ndc.z < 1.0);
            // Points on the sphere stay within the view (NDC x,y in -1..1, depth in 0..1).
            for d in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
                let p = cam.view_proj * (c + d * r).extend(1.0);
                let q = p.truncate() / p.w;
                assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "{q:?}");
                assert!(q.z > 0.0 && q.z < 1.0, "{q:?}");
            }
        }
    }

    #[test]
    fn pan_moves_the_centre_off_the_middle_of_the_view() {
        let (c, r) = (Vec3::new(1.0, 2.0, 3.0), 2.0);
        let cam = Camera::framing(c, r, 30.0, 20.0, 1.0, [0.25, -0.5], 1.0);
        // The panned target is in the middle; the sphere's centre left of and above it.
        let t = cam.view_proj * cam.target.extend(1.0);
        assert!((t.x / t.w).abs() < 1e-4 && (t.y / t.w).abs() < 1e-4);
        let p = cam.view_proj * c.extend(1.0);
        let (x, y) = (p.x / p.w, p.y / p.w);
        assert!(x < -0.01 && y > 0.01, "{x} {y}");
        assert!((cam.target.distance(c) - r * (0.25f32.hypot(0.5))).abs() < 1e-4);
    }
}
