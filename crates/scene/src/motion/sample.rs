//! Sampling an animation channel at a moment, exactly as glTF 2.0 defines it (§3.11 and
//! Appendix C): before the first key the first value, after the last the last; STEP holds a
//! key's value until the next; LINEAR interpolates (rotations by the shortest-path slerp);
//! CUBICSPLINE is the Hermite spline whose tangents are scaled by the key interval.
//! Keys are validated when read (`read.rs`): finite, never going back, outputs sized.
//! Equal neighbouring times (which glTF forbids and exporters write: a jump cut as two keys)
//! are sampled as three.js samples them: the interval holding `t` is the one whose start is
//! the last key at or before `t`, so the earlier of two keys at a shared time is reached
//! just before it and the later one holds from it on; no interval of zero length is ever
//! divided by.

/// How values between keys are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Interp {
    Step,
    Linear,
    /// Per key: in-tangent, value, out-tangent.
    Cubic,
}

/// One sampler's keys: `times` never decreasing, and `width` floats per value (3 for a
/// translation or scale, 4 for a rotation, the number of morph targets for weights); a
/// cubic sampler stores three values per key (in-tangent, value, out-tangent).
#[derive(Clone, Debug)]
pub(crate) struct Keys {
    pub(crate) times: Vec<f32>,
    pub(crate) values: Vec<f32>,
    pub(crate) width: usize,
    pub(crate) interp: Interp,
    /// Values are quaternions: interpolated on the sphere and normalised.
    pub(crate) rotation: bool,
}

impl Keys {
    /// Value `which` (0 in-tangent, 1 value, 2 out-tangent for cubic; 0 otherwise) of key k.
    fn at(&self, k: usize, which: usize) -> &[f32] {
        let per = if self.interp == Interp::Cubic { 3 } else { 1 };
        let start = (k * per + which) * self.width;
        &self.values[start..start + self.width]
    }

    fn value(&self, k: usize) -> &[f32] {
        self.at(k, if self.interp == Interp::Cubic { 1 } else { 0 })
    }

    /// The channel's value at `t` seconds, `width` floats.
    pub(crate) fn sample(&self, t: f64) -> Vec<f32> {
        let n = self.times.len();
        let first = f64::from(self.times[0]);
        let last = f64::from(self.times[n - 1]);
        // At `first` itself the search below gives the same value (s = 0), or the later of
        // keys that share the first time.
        if n == 1 || t < first {
            return self.finish(self.value(0).to_vec());
        }
        if t >= last {
            return self.finish(self.value(n - 1).to_vec());
        }
        // The key interval holding t: times[k] <= t < times[k + 1].
        let k = self.times.partition_point(|&x| f64::from(x) <= t) - 1;
        let (t0, t1) = (f64::from(self.times[k]), f64::from(self.times[k + 1]));
        let td = t1 - t0;
        let s = (t - t0) / td;
        let out = match self.interp {
            Interp::Step => self.value(k).to_vec(),
            Interp::Linear if self.rotation => slerp(self.value(k), self.value(k + 1), s),
            Interp::Linear => lerp(self.value(k), self.value(k + 1), s),
            Interp::Cubic => hermite(
                [
                    self.value(k),
                    self.at(k, 2),
                    self.value(k + 1),
                    self.at(k + 1, 0),
                ],
                s,
                td,
            ),
        };
        self.finish(out)
    }

    /// Rotations are unit quaternions (a spline or a file's value may not be).
    fn finish(&self, mut v: Vec<f32>) -> Vec<f32> {
        if self.rotation {
            let len = v.iter().map(|&x| f64::from(x).powi(2)).sum::<f64>().sqrt();
            if len > 0.0 {
                v.iter_mut().for_each(|x| *x = (f64::from(*x) / len) as f32);
            }
        }
        v
    }

    /// The last key's time: the animation lasts as long as its longest channel.
    pub(crate) fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }
}

fn lerp(a: &[f32], b: &[f32], s: f64) -> Vec<f32> {
    a.iter()
        .zip(b)
        .map(|(&a, &b)| (f64::from(a) * (1.0 - s) + f64::from(b) * s) as f32)
        .collect()
}

/// The spec's slerp (Appendix C): the shorter arc (the second quaternion negated when the
/// dot product is negative), a plain lerp where the arc is too short to divide by its sine.
fn slerp(a: &[f32], b: &[f32], s: f64) -> Vec<f32> {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| f64::from(x) * f64::from(y))
        .sum();
    let sign = if d < 0.0 { -1.0 } else { 1.0 };
    let d = d.abs().min(1.0);
    let (wa, wb) = if d > 1.0 - 1e-9 {
        (1.0 - s, s)
    } else {
        let angle = d.acos();
        let sin = angle.sin();
        (((1.0 - s) * angle).sin() / sin, (s * angle).sin() / sin)
    };
    a.iter()
        .zip(b)
        .map(|(&x, &y)| (wa * f64::from(x) + sign * wb * f64::from(y)) as f32)
        .collect()
}

/// The cubic Hermite spline between key k (value `v0`, out-tangent `b0`) and key k+1 (value
/// `v1`, in-tangent `a1`); tangents are per second, so they are scaled by the interval `td`.
fn hermite([v0, b0, v1, a1]: [&[f32]; 4], s: f64, td: f64) -> Vec<f32> {
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    (0..v0.len())
        .map(|i| {
            let f = |x: &[f32]| f64::from(x[i]);
            (h00 * f(v0) + h10 * td * f(b0) + h01 * f(v1) + h11 * td * f(a1)) as f32
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(times: &[f32], values: &[f32], width: usize, interp: Interp) -> Keys {
        Keys {
            times: times.to_vec(),
            values: values.to_vec(),
            width,
            interp,
            rotation: false,
        }
    }

    fn close(a: &[f32], b: &[f32]) {
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() < 1e-6, "{a:?} != {b:?}");
        }
    }

    #[test]
    fn linear_is_the_straight_line_between_keys_and_holds_outside_them() {
        let k = keys(&[1.0, 3.0], &[0.0, 10.0, 4.0, 30.0], 2, Interp::Linear);
        close(&k.sample(2.0), &[2.0, 20.0]);
        close(&k.sample(1.5), &[1.0, 15.0]);
        // Before the first key and after the last: those keys' values, not extrapolated.
        close(&k.sample(0.0), &[0.0, 10.0]);
        close(&k.sample(9.0), &[4.0, 30.0]);
    }

    #[test]
    fn step_holds_each_value_until_the_next_key() {
        let k = keys(&[0.0, 1.0, 2.0], &[5.0, 7.0, 9.0], 1, Interp::Step);
        close(&k.sample(0.999), &[5.0]);
        close(&k.sample(1.0), &[7.0]);
        close(&k.sample(1.5), &[7.0]);
        close(&k.sample(2.5), &[9.0]);
    }

    #[test]
    fn equal_key_times_reach_the_earlier_key_before_and_hold_the_later_from_then_on() {
        // A jump written as two keys at t = 1 (values 10 and 20): three.js's interval search
        // (Interpolant.evaluate) stops at the first key later than t, so at t = 1 the
        // interval is [1, 2] from the second key; just before, [0, 1] towards the first.
        let k = keys(
            &[0.0, 1.0, 1.0, 2.0],
            &[0.0, 10.0, 20.0, 40.0],
            1,
            Interp::Linear,
        );
        close(&k.sample(0.5), &[5.0]);
        close(&k.sample(0.999), &[9.99]);
        close(&k.sample(1.0), &[20.0]);
        close(&k.sample(1.5), &[30.0]);
        let s = keys(
            &[0.0, 1.0, 1.0, 2.0],
            &[0.0, 10.0, 20.0, 40.0],
            1,
            Interp::Step,
        );
        close(&s.sample(0.999), &[0.0]);
        close(&s.sample(1.0), &[20.0]);
        // Shared first and last times: the later key at the start, the last key at the end.
        let e = keys(
            &[1.0, 1.0, 2.0, 2.0],
            &[1.0, 2.0, 3.0, 4.0],
            1,
            Interp::Linear,
        );
        close(&e.sample(0.0), &[1.0]);
        close(&e.sample(1.0), &[2.0]);
        close(&e.sample(1.5), &[2.5]);
        close(&e.sample(2.0), &[4.0]);
        // Cubic: (a, v, b) per key; at the shared time the later key's value, and the spline
        // from it, never an interval of zero length.
        let c = keys(
            &[0.0, 1.0, 1.0, 2.0],
            &[0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 5.0, 0.0, 0.0, 7.0, 0.0],
            1,
            Interp::Cubic,
        );
        close(&c.sample(1.0), &[5.0]);
        close(&c.sample(1.5), &[6.0]);
        close(&c.sample(0.5), &[0.5]);
        assert!(c.sample(1.0).iter().all(|v| v.is_finite()));
    }

    #[test]
    fn cubic_spline_scales_tangents_by_the_key_interval() {
        // Keys at 0 and 2 (td = 2): values 0 and 1, out-tangent of key 0 = 3, in-tangent of
        // key 1 = -1 (per second). At s = 0.5: h00 = 0.5, h10 = 0.125, h01 = 0.5,
        // h11 = -0.125, so p = 0.5·0 + 0.125·2·3 + 0.5·1 + (−0.125)·2·(−1) = 1.5.
        let values = [9.0, 0.0, 3.0, -1.0, 1.0, 9.0]; // (a0, v0, b0), (a1, v1, b1)
        let k = keys(&[0.0, 2.0], &values, 1, Interp::Cubic);
        close(&k.sample(1.0), &[1.5]);
        // At the keys the spline passes through the values, never the tangents.
        close(&k.sample(0.0), &[0.0]);
        close(&k.sample(2.0), &[1.0]);
        close(&k.sample(5.0), &[1.0]);
    }

    #[test]
    fn slerp_takes_the_short_path_and_stays_unit() {
        let h = std::f32::consts::FRAC_1_SQRT_2;
        // Identity to 90° about Z; the second key written negated (the same rotation): the
        // short path still reaches 45° about Z at the midpoint, not the long way round.
        let mut k = keys(
            &[0.0, 1.0],
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -h, -h],
            4,
            Interp::Linear,
        );
        k.rotation = true;
        let q = k.sample(0.5);
        let half = (std::f64::consts::PI / 8.0) as f32;
        close(&q, &[0.0, 0.0, half.sin(), half.cos()]);
        let len: f32 = q.iter().map(|x| x * x).sum::<f32>().sqrt();
        assert!((len - 1.0).abs() < 1e-6);
    }

    #[test]
    fn slerp_of_near_equal_rotations_falls_back_to_a_normalised_lerp() {
        let mut k = keys(
            &[0.0, 1.0],
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1e-9, 1.0],
            4,
            Interp::Linear,
        );
        k.rotation = true;
        let q = k.sample(0.5);
        assert!(q.iter().all(|x| x.is_finite()));
        close(&q, &[0.0, 0.0, 0.0, 1.0]);
    }
}
