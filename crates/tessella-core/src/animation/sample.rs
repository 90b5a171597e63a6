//! Keyframe sampling, as the glTF 2.0 specification's Appendix C defines it: before the first
//! key the first value, after the last key the last value; `STEP` holds a key's value until the
//! next; `LINEAR` interpolates linearly, rotations by spherical linear interpolation along the
//! shorter arc; `CUBICSPLINE` is a cubic Hermite spline whose tangents are scaled by the key
//! interval. Rotations are normalised after interpolation.

use super::model::{Interpolation, Sampler};

/// Samples `sampler` at `time` into `out`, whose length is the number of components per key
/// (validated against the sampler's values). `rotation` marks a quaternion `[x, y, z, w]`:
/// interpolated along the shorter arc and normalised (the identity if it has no length).
pub(crate) fn sample(sampler: &Sampler, time: f32, rotation: bool, out: &mut [f32]) {
    let c = out.len();
    let times = &sampler.times;
    let cubic = sampler.interpolation == Interpolation::CubicSpline;
    // Key k's value: the middle of (in-tangent, value, out-tangent) for a cubic spline.
    let value = |k: usize| {
        let start = if cubic { (3 * k + 1) * c } else { k * c };
        &sampler.values[start..start + c]
    };
    let last = times.len() - 1;
    if last == 0 || time <= times[0] {
        out.copy_from_slice(value(0));
    } else if time >= times[last] {
        out.copy_from_slice(value(last));
    } else {
        // times[k] <= time < times[k + 1], with 0 <= k < last.
        let k = times.partition_point(|&t| t <= time) - 1;
        let dt = times[k + 1] - times[k];
        let s = (time - times[k]) / dt;
        match sampler.interpolation {
            Interpolation::Step => out.copy_from_slice(value(k)),
            Interpolation::Linear if rotation => slerp(value(k), value(k + 1), s, out),
            Interpolation::Linear => {
                for ((o, a), b) in out.iter_mut().zip(value(k)).zip(value(k + 1)) {
                    *o = a + s * (b - a);
                }
            }
            Interpolation::CubicSpline => {
                let v = &sampler.values;
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                for (i, o) in out.iter_mut().enumerate() {
                    let p0 = v[(3 * k + 1) * c + i];
                    let m0 = dt * v[(3 * k + 2) * c + i]; // key k's out-tangent
                    let p1 = v[(3 * k + 4) * c + i];
                    let m1 = dt * v[(3 * k + 3) * c + i]; // key k + 1's in-tangent
                    *o = h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1;
                }
            }
        }
    }
    if rotation {
        normalize(out);
    }
}

/// Scales a quaternion to unit length; the identity if it has none.
fn normalize(q: &mut [f32]) {
    let length = q.iter().map(|v| v * v).sum::<f32>().sqrt();
    if length > 0.0 && length.is_finite() {
        q.iter_mut().for_each(|v| *v /= length);
    } else {
        q.copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
    }
}

/// Spherical linear interpolation of two quaternions (normalised first) along the shorter arc.
/// The angle comes from `2·atan2(|a − b|, |a + b|)`, which stays accurate for nearby
/// quaternions, where `acos` of their dot product does not.
fn slerp(a: &[f32], b: &[f32], s: f32, out: &mut [f32]) {
    let mut a: [f32; 4] = [a[0], a[1], a[2], a[3]];
    let mut b: [f32; 4] = [b[0], b[1], b[2], b[3]];
    normalize(&mut a);
    normalize(&mut b);
    if a.iter().zip(&b).map(|(x, y)| x * y).sum::<f32>() < 0.0 {
        b = b.map(|v| -v);
    }
    let norm = |f: &dyn Fn(usize) -> f32| (0..4).map(|i| f(i) * f(i)).sum::<f32>().sqrt();
    let theta = 2.0 * norm(&|i| a[i] - b[i]).atan2(norm(&|i| a[i] + b[i]));
    let sin = theta.sin();
    let (wa, wb) = if sin < 1e-6 {
        (1.0 - s, s)
    } else {
        (((1.0 - s) * theta).sin() / sin, (s * theta).sin() / sin)
    };
    for i in 0..4 {
        out[i] = wa * a[i] + wb * b[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampler(interpolation: Interpolation, times: &[f32], values: &[f32]) -> Sampler {
        Sampler {
            interpolation,
            times: times.to_vec(),
            values: values.to_vec(),
        }
    }

    #[test]
    fn clamps_and_interpolates() {
        let s = sampler(Interpolation::Linear, &[1.0, 3.0], &[10.0, 20.0]);
        let mut out = [0.0];
        for (t, want) in [
            (0.0, 10.0),
            (1.0, 10.0),
            (2.0, 15.0),
            (3.0, 20.0),
            (9.0, 20.0),
        ] {
            sample(&s, t, false, &mut out);
            assert_eq!(out[0], want, "at {t}");
        }
        let s = sampler(Interpolation::Step, &[1.0, 3.0], &[10.0, 20.0]);
        sample(&s, 2.9, false, &mut out);
        assert_eq!(out[0], 10.0);
    }

    #[test]
    fn cubic_hits_its_keys_and_follows_tangents() {
        // in, value, out per key: a straight line of slope 5 through (0, 0) and (2, 10).
        let s = sampler(
            Interpolation::CubicSpline,
            &[0.0, 2.0],
            &[5.0, 0.0, 5.0, 5.0, 10.0, 5.0],
        );
        let mut out = [0.0];
        for t in [0.0, 0.5, 1.0, 1.5, 2.0] {
            sample(&s, t, false, &mut out);
            assert!((out[0] - 5.0 * t).abs() < 1e-5, "{t}: {}", out[0]);
        }
    }

    #[test]
    fn slerp_takes_the_shorter_arc() {
        let h = std::f32::consts::FRAC_1_SQRT_2;
        // 0° and 90° about z, the second negated: the midpoint is 45° about z.
        let s = sampler(
            Interpolation::Linear,
            &[0.0, 1.0],
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -h, -h],
        );
        let mut out = [0.0; 4];
        sample(&s, 0.5, true, &mut out);
        let want = [
            0.0,
            0.0,
            (std::f32::consts::PI / 8.0).sin(),
            (std::f32::consts::PI / 8.0).cos(),
        ];
        for (o, w) in out.iter().zip(want) {
            assert!((o - w).abs() < 1e-6, "{out:?}");
        }
    }
}
