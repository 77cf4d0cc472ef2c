//! The planned speed along a run, looked up by piece and curve parameter:
//! what the renderer needs to know how fast the machine will pass each
//! place of the exact curves, and so how much curvature step a joint there
//! can take.

use crate::feed::plan::{PlannedSegment, RunPlan};
use alloc::vec::Vec;
use core::borrow::Borrow;

/// Planned speed samples of each piece of a run: `(parameter, mm/s)`,
/// increasing in the parameter. The samples of all pieces are held in one
/// vector, piece after piece (a vector per piece held a quarter more on a
/// long run, in 200,000 small blocks).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlannedSpeed {
    samples: Vec<(f64, f64)>,
    /// Where each piece's samples start in `samples`, and where the last
    /// piece's end.
    starts: Vec<usize>,
}

/// Most samples taken of one planned segment: beyond this the sampling step
/// grows past `dt` (a day of machining at 1 ms is 8.6e7 samples; the speed
/// between samples of a long segment changes slowly anyway).
const MAX_SAMPLES_PER_SEGMENT: f64 = 1e6;

/// Steps `seg` is sampled in: one per `dt` of its duration, at least
/// one, at most [`MAX_SAMPLES_PER_SEGMENT`].
fn steps(seg: &PlannedSegment, dt: f64) -> usize {
    let d = seg.profile.duration();
    if d > 0.0 && dt > 0.0 {
        crate::math::ceil(d / dt).clamp(1.0, MAX_SAMPLES_PER_SEGMENT) as usize
    } else {
        1
    }
}

/// Samples [`PlannedSpeed::sample`] takes of `segments` at most.
fn sample_count(segments: &[PlannedSegment], dt: f64) -> usize {
    segments
        .iter()
        .filter(|s| !s.parts.is_empty())
        .map(|s| steps(s, dt) + 1)
        .sum()
}

impl PlannedSpeed {
    /// Samples `plan` (of a run of `n_pieces` pieces) every `dt` seconds of
    /// its profiles, and at both ends of each segment.
    pub fn new(n_pieces: usize, plan: &RunPlan, dt: f64) -> PlannedSpeed {
        let count = sample_count(&plan.segments, dt);
        PlannedSpeed::sample(n_pieces, plan.segments.iter(), dt, count)
    }

    /// [`PlannedSpeed::new`] of a plan whose segments are taken: each is
    /// dropped once sampled, so that a long run's plan and its samples are
    /// not held whole at once (the same samples).
    pub fn from_segments(n_pieces: usize, segments: Vec<PlannedSegment>, dt: f64) -> PlannedSpeed {
        let count = sample_count(&segments, dt);
        PlannedSpeed::sample(n_pieces, segments.into_iter(), dt, count)
    }

    /// The samples of `segments`, at most `count` of them (room for them
    /// is taken at once: grown by doubling, the vector of a long run held
    /// three times its size while it moved).
    fn sample<S: Borrow<PlannedSegment>>(
        n_pieces: usize,
        segments: impl Iterator<Item = S>,
        dt: f64,
        count: usize,
    ) -> PlannedSpeed {
        let mut samples: Vec<(f64, f64)> = Vec::with_capacity(count);
        // The piece of each sample; a plan runs along its pieces in order,
        // so these do not decrease (were they to, the samples are sorted
        // by piece below, keeping their order within a piece).
        let mut piece_of: Vec<u32> = Vec::with_capacity(count);
        for seg in segments {
            let seg = seg.borrow();
            if seg.parts.is_empty() {
                continue;
            }
            let d = seg.profile.duration();
            let n = steps(seg, dt);
            let mut part = 0;
            let mut s0 = 0.0;
            for k in 0..=n {
                let st = seg.profile.eval(d * k as f64 / n as f64);
                while part + 1 < seg.parts.len() && st.q > s0 + seg.parts[part].length {
                    s0 += seg.parts[part].length;
                    part += 1;
                }
                let p = &seg.parts[part];
                let f = if p.length > 0.0 {
                    ((st.q - s0) / p.length).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                if let (true, Ok(piece)) = (p.piece < n_pieces, u32::try_from(p.piece)) {
                    samples.push((p.t0 + (p.t1 - p.t0) * f, st.v));
                    piece_of.push(piece);
                }
            }
        }
        if !piece_of.is_sorted() {
            let mut order: Vec<usize> = (0..samples.len()).collect();
            order.sort_by_key(|&i| piece_of[i]);
            samples = order.iter().map(|&i| samples[i]).collect();
            piece_of = order.iter().map(|&i| piece_of[i]).collect();
        }
        let mut starts = Vec::with_capacity(n_pieces + 1);
        let mut k = 0;
        for i in 0..n_pieces {
            starts.push(k);
            while k < piece_of.len() && piece_of[k] as usize == i {
                k += 1;
            }
        }
        starts.push(k);
        drop(piece_of);
        for w in starts.windows(2) {
            samples[w[0]..w[1]].sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        samples.shrink_to_fit();
        PlannedSpeed { samples, starts }
    }

    /// The samples of piece `i` (none past the last piece).
    fn piece(&self, i: usize) -> Option<&[(f64, f64)]> {
        let (&a, &b) = (self.starts.get(i)?, self.starts.get(i + 1)?);
        Some(&self.samples[a..b])
    }

    /// The speed on piece `i` at parameter `t`, interpolated between
    /// samples (the nearest sample outside them; 0 without samples).
    pub fn at(&self, i: usize, t: f64) -> f64 {
        let Some(s) = self.piece(i) else {
            return 0.0;
        };
        if s.is_empty() {
            return self.between(i);
        }
        let k = s.partition_point(|x| x.0 < t);
        if k == 0 {
            return s[0].1;
        }
        if k == s.len() {
            return s[k - 1].1;
        }
        let (a, b) = (s[k - 1], s[k]);
        if b.0 > a.0 {
            a.1 + (b.1 - a.1) * (t - a.0) / (b.0 - a.0)
        } else {
            a.1.max(b.1)
        }
    }

    /// The speed on piece `i` that holds no sample (shorter than the travel
    /// of one sampling step): the higher of the last sample before it and
    /// the first after it on the run, between which the machine passes it.
    /// (Taken as 0, as at rest, a piece of a micrometre between two
    /// transitions was written with the run's decimals, whose rounding
    /// kinked its joints: `regression_chirp_a_micrometre_line_is_passed_at_its_neighbours_speed`.)
    fn between(&self, i: usize) -> f64 {
        let Some(&k) = self.starts.get(i) else {
            return 0.0;
        };
        let before = k.checked_sub(1).and_then(|b| self.samples.get(b));
        let after = self.samples.get(k);
        before.map_or(0.0, |b| b.1).max(after.map_or(0.0, |a| a.1))
    }

    /// The largest planned speed on piece `i` over parameters `[t0, t1]`.
    pub fn max_over(&self, i: usize, t0: f64, t1: f64) -> f64 {
        let mut v = self.at(i, t0).max(self.at(i, t1));
        if let Some(s) = self.piece(i) {
            let k = s.partition_point(|x| x.0 < t0);
            for x in &s[k..] {
                if x.0 > t1 {
                    break;
                }
                v = v.max(x.1);
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feed::limits::MachineLimits;
    use crate::feed::plan::{plan_run, PlanOptions};
    use crate::geom::Vec3;
    use crate::path::Run;

    // A line of a micrometre between two long ones (what a corner
    // transition leaves of a move) holds no sample of a plan sampled
    // every millisecond; it was taken as passed at rest (speed 0), so the
    // writer gave it no more decimals than the run's, and their rounding
    // kinked its joints (a chirp smoothed by `bspline-corner`: written
    // 1.6% slower, `spiral_lines.ngc` 12.6% slower).
    #[test]
    fn regression_chirp_a_micrometre_line_is_passed_at_its_neighbours_speed() {
        let pts = [
            Vec3::ZERO,
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(10.001, 0.0, 0.0),
            Vec3::new(20.0, 0.0, 0.0),
        ];
        let pieces = Run::polyline(&pts, Some(24000.0)).pieces;
        let m = MachineLimits::thesis();
        let opts = PlanOptions {
            limits: m,
            override_feed: false,
            window: None,
            ends: Default::default(),
        };
        let plan = plan_run(&pieces, &opts).unwrap();
        let speed = PlannedSpeed::new(pieces.len(), &plan, m.period);
        assert_eq!(speed.piece(1).map(<[_]>::len), Some(0));
        let (before, after) = (speed.at(0, 1.0), speed.at(2, 0.0));
        let v = speed.at(1, 0.5);
        assert!(v > 0.0, "{v}");
        assert_eq!(v, speed.max_over(1, 0.0, 1.0));
        assert!(
            v >= before.min(after) && v <= before.max(after),
            "{v}: {before}, {after}"
        );
    }
}
