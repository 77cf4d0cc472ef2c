//! What a controller sees of a motion sampled every servo period: the
//! velocity, acceleration and jerk of the commanded positions by finite
//! differences, measured the way LinuxCNC timing rigs measure executed
//! motion (`scripts/linuxcnc/`), so that a stream can be checked before
//! it is played.
//!
//! With positions `p_k` every period `T`:
//!
//! * velocity `v_k+1/2 = (p_k+1 - p_k) / T`;
//! * acceleration `a_k = (p_k+1 - 2 p_k + p_k-1) / T^2`;
//! * jerk `j_k+1/2 = (a_k+1 - a_k) / T`, and its average over
//!   [`JERK_AVERAGE_PERIODS`] periods `(a_k+5 - a_k) / (5 T)`.
//!
//! Each difference is a weighted mean of the continuous quantity over the
//! periods it spans (a B-spline kernel), so a motion whose continuous
//! acceleration and jerk vectors stay within limits samples within them.
//! A direction change inside one period is an impulse: it shows in the
//! raw jerk of one period, and averaged over five periods as `dv / (5 T^2)`.

use crate::geom::Vec3;
use crate::math;
use alloc::vec::Vec;

/// Periods over which the jerk is averaged before it is held to the jerk
/// limit: a drive filters single-period impulses; LinuxCNC timing rigs
/// report the jerk averaged over 5 ms at a 1 ms period.
pub const JERK_AVERAGE_PERIODS: usize = 5;

/// Limits a sampled motion is held to: the path's (3D magnitudes) and each
/// axis' (X, Y, Z components).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleLimits {
    /// Servo period, s.
    pub period: f64,
    /// Largest speed, acceleration and averaged jerk along the path.
    pub vel: f64,
    pub acc: f64,
    pub jerk: f64,
    /// Largest velocity, acceleration and averaged jerk of each axis.
    pub axis_vel: [f64; 3],
    pub axis_acc: [f64; 3],
    pub axis_jerk: [f64; 3],
}

/// The peaks of a sampled motion.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Peaks {
    /// Largest speed, mm/s.
    pub vel: f64,
    /// Largest acceleration magnitude (3D), mm/s^2.
    pub acc: f64,
    /// Largest jerk magnitude (3D), one period, mm/s^3.
    pub jerk: f64,
    /// Largest jerk magnitude averaged over [`JERK_AVERAGE_PERIODS`].
    pub jerk_avg: f64,
    /// Per axis: velocity, acceleration, averaged jerk.
    pub axis_vel: [f64; 3],
    pub axis_acc: [f64; 3],
    pub axis_jerk_avg: [f64; 3],
}

/// Which limit a sample exceeds, and by how much.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Excess {
    /// Index of the sample the difference is centred on (for the velocity
    /// `v_k+1/2`, `k`; for the averaged jerk, the middle of its periods).
    pub index: usize,
    /// Which quantity.
    pub what: Quantity,
    /// `limit / measured` (below 1).
    pub ratio: f64,
}

/// A measured quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    Velocity,
    Acceleration,
    Jerk,
}

fn axes(v: Vec3) -> [f64; 3] {
    [math::abs(v.x), math::abs(v.y), math::abs(v.z)]
}

fn acc_at(p: &[Vec3], k: usize, t: f64) -> Vec3 {
    (p[k + 1] - p[k] * 2.0 + p[k - 1]) / (t * t)
}

/// The acceleration vector of every sample (zero at both ends).
pub fn accelerations(p: &[Vec3], period: f64) -> Vec<Vec3> {
    let mut a = alloc::vec![Vec3::ZERO; p.len()];
    for (k, ak) in a
        .iter_mut()
        .enumerate()
        .take(p.len().saturating_sub(1))
        .skip(1)
    {
        *ak = acc_at(p, k, period);
    }
    a
}

/// Measures `p` (one position per period) and lists every sample that
/// exceeds `lim` (each quantity at most once per sample). `slack` is the
/// relative excess tolerated (rounding of the positions).
pub fn measure(p: &[Vec3], lim: &SampleLimits, slack: f64) -> (Peaks, Vec<Excess>) {
    let t = lim.period;
    let mut peaks = Peaks::default();
    let mut out = Vec::new();
    let over = 1.0 + slack;
    let push = |out: &mut Vec<Excess>, index, what, ratio: f64| {
        if ratio < 1.0 / over {
            out.push(Excess { index, what, ratio });
        }
    };
    for k in 0..p.len().saturating_sub(1) {
        let v = (p[k + 1] - p[k]) / t;
        let m = v.norm();
        peaks.vel = peaks.vel.max(m);
        let mut r = lim.vel / m;
        for (i, c) in axes(v).iter().enumerate() {
            peaks.axis_vel[i] = peaks.axis_vel[i].max(*c);
            r = r.min(lim.axis_vel[i] / c);
        }
        push(&mut out, k, Quantity::Velocity, r);
    }
    let a = accelerations(p, t);
    for (k, ak) in a.iter().enumerate().take(p.len().saturating_sub(1)).skip(1) {
        let m = ak.norm();
        peaks.acc = peaks.acc.max(m);
        let mut r = lim.acc / m;
        for (i, c) in axes(*ak).iter().enumerate() {
            peaks.axis_acc[i] = peaks.axis_acc[i].max(*c);
            r = r.min(lim.axis_acc[i] / c);
        }
        push(&mut out, k, Quantity::Acceleration, r);
    }
    for k in 0..a.len().saturating_sub(1) {
        peaks.jerk = peaks.jerk.max(((a[k + 1] - a[k]) / t).norm());
    }
    let n = JERK_AVERAGE_PERIODS;
    for k in 0..a.len().saturating_sub(n) {
        let j = (a[k + n] - a[k]) / (n as f64 * t);
        let m = j.norm();
        peaks.jerk_avg = peaks.jerk_avg.max(m);
        let mut r = lim.jerk / m;
        for (i, c) in axes(j).iter().enumerate() {
            peaks.axis_jerk_avg[i] = peaks.axis_jerk_avg[i].max(*c);
            r = r.min(lim.axis_jerk[i] / c);
        }
        push(&mut out, k + n / 2, Quantity::Jerk, r);
    }
    (peaks, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lim() -> SampleLimits {
        SampleLimits {
            period: 0.001,
            vel: 400.0,
            acc: 4000.0,
            jerk: 20000.0,
            axis_vel: [400.0; 3],
            axis_acc: [4000.0; 3],
            axis_jerk: [20000.0; 3],
        }
    }

    #[test]
    fn a_constant_jerk_motion_measures_its_jerk() {
        // From rest: jerk +J for 20 ms, -J for 20 ms, then constant speed
        // (J = 10000): peak acceleration 200 mm/s^2, jerk J.
        let j = 10000.0;
        let x = |t: f64| -> f64 {
            let t1 = 0.02;
            if t <= t1 {
                j * t * t * t / 6.0
            } else if t <= 2.0 * t1 {
                let u = t - t1;
                let (x1, v1, a1) = (j * t1 * t1 * t1 / 6.0, j * t1 * t1 / 2.0, j * t1);
                x1 + v1 * u + a1 * u * u / 2.0 - j * u * u * u / 6.0
            } else {
                let (x2, v2) = (j * t1 * t1 * t1, j * t1 * t1);
                x2 + v2 * (t - 2.0 * t1)
            }
        };
        let p: Vec<Vec3> = (0..100)
            .map(|k| Vec3::new(x(k as f64 * 0.001), 0.0, 0.0))
            .collect();
        let (peaks, ex) = measure(&p, &lim(), 1e-6);
        assert!(ex.is_empty(), "{ex:?}");
        assert!((peaks.jerk_avg - j).abs() < 1e-3 * j, "{peaks:?}");
        // The second difference is the acceleration averaged over a hat of
        // two periods: at the peak of a triangle of slope J, 200 - J Ts / 3.
        assert!(
            (peaks.acc - (200.0 - j * 0.001 / 3.0)).abs() < 1e-6,
            "{peaks:?}"
        );
    }

    #[test]
    fn a_corner_at_speed_is_a_jerk_impulse() {
        // 50 mm/s along X, then along Y: dv = 50 sqrt(2) within a period.
        let mut p = Vec::new();
        for k in 0..20 {
            p.push(Vec3::new(0.05 * k as f64 - 1.0, 0.0, 0.0));
        }
        let c = *p.last().unwrap();
        for k in 1..20 {
            p.push(c + Vec3::new(0.0, 0.05 * k as f64, 0.0));
        }
        let (peaks, ex) = measure(&p, &lim(), 1e-9);
        let dv = 50.0 * 2f64.sqrt();
        assert!((peaks.jerk_avg - dv / 0.005 / 0.001).abs() < 1e-6 * dv / 5e-6);
        assert!(ex.iter().any(|e| e.what == Quantity::Jerk));
        assert!(ex.iter().any(|e| e.what == Quantity::Acceleration));
    }

    #[test]
    fn per_axis_limits_are_checked() {
        let p: Vec<Vec3> = (0..10)
            .map(|k| Vec3::new(0.3 * k as f64, 0.0, 0.0))
            .collect();
        let mut l = lim();
        l.axis_vel[0] = 200.0;
        let (peaks, ex) = measure(&p, &l, 1e-9);
        assert!((peaks.axis_vel[0] - 300.0).abs() < 1e-9);
        assert!(ex
            .iter()
            .all(|e| e.what == Quantity::Velocity && (e.ratio - 2.0 / 3.0).abs() < 1e-9));
        assert_eq!(ex.len(), 9);
    }
}
