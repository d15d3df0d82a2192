//! Keyframes in, a value at a time out: glTF 2.0's three interpolations (§3.11.2 and
//! Appendix C). STEP holds a key until the next; LINEAR blends neighbours (rotations by
//! spherical interpolation); CUBICSPLINE is a cubic Hermite spline whose keys carry an
//! in-tangent, a value and an out-tangent. Before the first key the first value holds,
//! after the last the last.

use glam::{Quat, Vec4};

/// How a sampler blends between keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The previous key's value until the next key.
    Step,
    /// Linear blend; spherical for rotations.
    Linear,
    /// Cubic Hermite spline through the keys, with the file's tangents.
    CubicSpline,
}

/// Keyframes of one animated property: `width` floats per value (3 for a translation or
/// scale, 4 for a rotation, the target count for morph weights).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframes {
    /// Key times in seconds, strictly increasing.
    pub times: Vec<f32>,
    /// Values, `width` floats each; for CUBICSPLINE three per key (in-tangent, value,
    /// out-tangent).
    pub values: Vec<f32>,
    /// Floats per value.
    pub width: usize,
    /// How keys blend.
    pub interpolation: Interpolation,
}

/// Where a time falls among the keys: key `k` and the fraction `s` of the way to key `k + 1`
/// (`s = 0` past either end, where the end key holds).
fn locate(times: &[f32], t: f32) -> (usize, f32) {
    let last = times.len() - 1;
    if t <= times[0] {
        return (0, 0.0);
    }
    if t >= times[last] {
        return (last, 0.0);
    }
    // The first key after t; t lies in [times[k], times[k + 1]).
    let next = times.partition_point(|&key| key <= t);
    let k = next - 1;
    let span = times[k + 1] - times[k];
    (k, ((t - times[k]) / span).clamp(0.0, 1.0))
}

impl Keyframes {
    /// The last key's time: how long this property animates.
    pub fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// Value `key` (the middle of a CUBICSPLINE triple).
    fn value(&self, key: usize) -> &[f32] {
        let w = self.width;
        match self.interpolation {
            Interpolation::CubicSpline => &self.values[(3 * key + 1) * w..(3 * key + 2) * w],
            _ => &self.values[key * w..(key + 1) * w],
        }
    }

    fn in_tangent(&self, key: usize) -> &[f32] {
        &self.values[3 * key * self.width..(3 * key + 1) * self.width]
    }

    fn out_tangent(&self, key: usize) -> &[f32] {
        &self.values[(3 * key + 2) * self.width..(3 * key + 3) * self.width]
    }

    /// The property at `t` seconds, componentwise (rotations: see [`Keyframes::rotation`]).
    pub fn sample(&self, t: f32) -> Vec<f32> {
        let (k, s) = locate(&self.times, t);
        if s == 0.0 || self.interpolation == Interpolation::Step {
            return self.value(k).to_vec();
        }
        match self.interpolation {
            Interpolation::Linear => {
                let (a, b) = (self.value(k), self.value(k + 1));
                a.iter().zip(b).map(|(a, b)| a + (b - a) * s).collect()
            }
            _ => {
                let dt = self.times[k + 1] - self.times[k];
                let (v0, b0) = (self.value(k), self.out_tangent(k));
                let (v1, a1) = (self.value(k + 1), self.in_tangent(k + 1));
                let h = hermite(s);
                (0..self.width).map(|i| h[0] * v0[i] + h[1] * dt * b0[i] + h[2] * v1[i] + h[3] * dt * a1[i]).collect()
            }
        }
    }

    /// A rotation at `t`: STEP and CUBICSPLINE as [`Keyframes::sample`] (the spline's
    /// result normalised), LINEAR by slerp along the shorter arc.
    pub fn rotation(&self, t: f32) -> Quat {
        let (k, s) = locate(&self.times, t);
        let quat = |v: &[f32]| Quat::from_vec4(Vec4::new(v[0], v[1], v[2], v[3]));
        if self.interpolation == Interpolation::Linear && s > 0.0 {
            return quat(self.value(k)).normalize().slerp(quat(self.value(k + 1)).normalize(), s);
        }
        let q = quat(&self.sample(t));
        let length = q.length();
        if length > 1e-12 && length.is_finite() { q / length } else { Quat::IDENTITY }
    }
}

/// Cubic Hermite basis at `s` in [0, 1]: weights of p0, m0, p1, m1 (Appendix C).
pub fn hermite(s: f32) -> [f32; 4] {
    let s2 = s * s;
    let s3 = s2 * s;
    [2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(times: &[f32], values: &[f32], width: usize, interpolation: Interpolation) -> Keyframes {
        Keyframes { times: times.to_vec(), values: values.to_vec(), width, interpolation }
    }

    #[test]
    fn step_holds_each_key_until_the_next_and_the_ends_hold() {
        let k = keys(&[1.0, 2.0, 4.0], &[10.0, 20.0, 40.0], 1, Interpolation::Step);
        for (t, want) in [(0.0, 10.0), (1.0, 10.0), (1.99, 10.0), (2.0, 20.0), (3.9, 20.0), (4.0, 40.0), (9.0, 40.0)] {
            assert_eq!(k.sample(t), vec![want], "t = {t}");
        }
    }

    #[test]
    fn linear_blends_neighbours() {
        let k = keys(&[0.0, 2.0], &[0.0, 1.0, 4.0, 3.0], 2, Interpolation::Linear);
        assert_eq!(k.sample(0.5), vec![1.0, 1.5]);
        assert_eq!(k.sample(-1.0), vec![0.0, 1.0]);
        assert_eq!(k.sample(3.0), vec![4.0, 3.0]);
    }

    #[test]
    fn cubic_spline_follows_the_hermite_formula_with_tangents_scaled_by_the_key_span() {
        // Keys at 1 s and 3 s: (in, value, out) triples.
        let (a0, v0, b0) = (9.0, 2.0, 0.5);
        let (a1, v1, b1) = (-1.5, 5.0, 7.0);
        let k = keys(&[1.0, 3.0], &[a0, v0, b0, a1, v1, b1], 1, Interpolation::CubicSpline);
        for t in [1.0f32, 1.3, 2.0, 2.75, 3.0] {
            let s = (t - 1.0) / 2.0;
            let dt = 2.0;
            let want = (2.0 * s.powi(3) - 3.0 * s.powi(2) + 1.0) * v0
                + (s.powi(3) - 2.0 * s.powi(2) + s) * dt * b0
                + (-2.0 * s.powi(3) + 3.0 * s.powi(2)) * v1
                + (s.powi(3) - s.powi(2)) * dt * a1;
            let got = k.sample(t)[0];
            assert!((got - want).abs() < 1e-5, "t = {t}: {got} != {want}");
        }
        // The in-tangent of the first key and the out-tangent of the last are unused.
        assert_eq!(k.sample(0.0), vec![v0]);
        assert_eq!(k.sample(5.0), vec![v1]);
    }

    #[test]
    fn linear_rotation_is_a_slerp_along_the_shorter_arc() {
        let a = Quat::from_rotation_y(0.0);
        let b = -Quat::from_rotation_y(1.0); // the same rotation, the other sign
        let values: Vec<f32> = a.to_array().into_iter().chain(b.to_array()).collect();
        let k = keys(&[0.0, 1.0], &values, 4, Interpolation::Linear);
        let q = k.rotation(0.25);
        assert!(q.angle_between(Quat::from_rotation_y(0.25)) < 1e-5, "{q}");
    }

    #[test]
    fn a_spline_rotation_is_normalised() {
        let v = Quat::from_rotation_x(0.3).to_array();
        let w = Quat::from_rotation_x(1.3).to_array();
        let zero = [0.0; 4];
        let values: Vec<f32> = [zero, v, zero, zero, w, zero].concat();
        let k = keys(&[0.0, 1.0], &values, 4, Interpolation::CubicSpline);
        assert!((k.rotation(0.5).length() - 1.0).abs() < 1e-6);
    }
}
