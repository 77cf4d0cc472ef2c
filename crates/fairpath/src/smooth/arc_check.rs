//! `arc-fit`'s acceptance tests: whether a line or an arc from `P_i` to
//! `P_j` stays within the fit tolerance of the polyline `P_i..P_j` and
//! passes its vertices in order, the arc everywhere by sampled chords and
//! the convexity bound (module docs of `arc_fit.rs`, "The check").

use super::arc_chain::Fitter;
use super::arc_fit::ARC_MAX_SPLIT_DEPTH;
use crate::geom::{point_segment_distance, Arc, ParamCurve, Vec3};
use crate::math;
use core::f64::consts::PI;

/// Most samples of one arc; an arc needing more is rejected.
const MAX_SAMPLES: f64 = 1e6;

/// Segments searched either side of the one at a sample's angle.
const WINDOW: usize = 2;

/// `x <= limit`, false for NaN: every check rejects what it cannot
/// compare.
pub(super) fn within(x: f64, limit: f64) -> bool {
    x <= limit
}

impl Fitter<'_> {
    /// Whether the line `P_i P_j` stays within the fit tolerance of the
    /// polyline and passes its vertices in order (module docs).
    pub(super) fn line_fits(&self, i: usize, j: usize) -> bool {
        if j == i + 1 {
            return true;
        }
        let (a, b) = (self.pts[i], self.pts[j]);
        let d = b - a;
        let l2 = d.norm_sq();
        let l = math::sqrt(l2);
        if !(l > self.lim.coincident && l.is_finite()) {
            return false;
        }
        let slack = self.lim.tol / l;
        let mut smax: f64 = 0.0;
        for &q in &self.pts[i + 1..j] {
            let w = q - a;
            let s = w.dot(d) / l2;
            if !(s >= smax - slack && s <= 1.0 + slack) {
                return false;
            }
            smax = smax.max(s);
            if !within((w - d * s).norm(), self.lim.tol) {
                return false;
            }
        }
        true
    }

    /// Whether `arc` (from `P_i` to `P_j`) is within the fit tolerance of
    /// the polyline `P_i..P_j` and passes its vertices in order (module
    /// docs).
    pub(super) fn arc_fits(&mut self, arc: &Arc, i: usize, j: usize) -> bool {
        let tol = self.lim.tol;
        let rmin = arc.r0.min(arc.r1);
        let rmax = arc.r0.max(arc.r1);
        let sweep = arc.sweep;
        let (c, u) = (arc.center, arc.u);
        let v = arc.normal.cross(u);
        let slack = (tol / rmin).min(0.25 * PI);
        // 1. In order, and every vertex near the arc.
        self.angles.clear();
        self.angles.push(0.0);
        let mut prev = 0.0;
        let mut angle = 0.0;
        let mut top: f64 = 0.0;
        for k in i + 1..=j {
            let w = self.pts[k] - c;
            let a = math::atan2(w.dot(v), w.dot(u));
            let mut da = a - prev;
            if da > PI {
                da -= 2.0 * PI;
            } else if da <= -PI {
                da += 2.0 * PI;
            }
            prev = a;
            angle += da;
            if !(angle >= top - slack && angle >= -slack && angle <= sweep + slack) {
                return false;
            }
            top = top.max(angle);
            self.angles.push(top);
            if k < j {
                let t = (angle / sweep).clamp(0.0, 1.0);
                if !within(arc.eval(t).dist(self.pts[k]), tol) {
                    return false;
                }
            }
        }
        if !within(math::abs(angle - sweep), slack) {
            return false;
        }
        // 2. Everywhere, by sampled chords.
        let m2 = rmax * sweep * sweep + 2.0 * math::abs(arc.r1 - arc.r0) * sweep;
        let n = if m2 > 0.0 {
            math::ceil(math::sqrt(m2 / (8.0 * self.lim.sample)))
        } else {
            1.0
        };
        if !(n.is_finite() && n <= MAX_SAMPLES) {
            return false;
        }
        let n = (n as usize).max(1);
        // The uniform samples merged with the vertices' angles, so that
        // most spans lie along one segment, where the convexity bound is
        // tight.
        let last = self.angles.len() - 1;
        let (mut s, mut kv) = (1, 1);
        let (mut ta, mut pa, mut ka) = (0.0, arc.p0, 0);
        while s <= n {
            let tu = s as f64 / n as f64;
            let tv = if kv < last {
                self.angles[kv] / sweep
            } else {
                f64::INFINITY
            };
            let tb = if tv < tu {
                kv += 1;
                tv
            } else {
                s += 1;
                tu
            };
            if tb <= ta {
                continue;
            }
            let pb = arc.eval(tb);
            let kb = self.vertex_at(ka, tb * sweep);
            if !self.span_fits(arc, i, j, (ta, tb), (pa, pb), (ka, kb), m2, 0) {
                return false;
            }
            (ta, pa, ka) = (tb, pb, kb);
        }
        true
    }

    /// The last vertex (offset from `i`), from `from` on, whose running
    /// angle is at most `angle`.
    fn vertex_at(&self, from: usize, angle: f64) -> usize {
        let mut k = from;
        while k + 1 < self.angles.len() && self.angles[k + 1] <= angle {
            k += 1;
        }
        k
    }

    /// Whether the arc between parameters `t.0` and `t.1` (points `p`,
    /// vertices at their angles `k`, offsets from `i`) is within the fit
    /// tolerance of the polyline `P_i..P_j`.
    #[allow(clippy::too_many_arguments)]
    fn span_fits(
        &self,
        arc: &Arc,
        i: usize,
        j: usize,
        t: (f64, f64),
        p: (Vec3, Vec3),
        k: (usize, usize),
        m2: f64,
        depth: u32,
    ) -> bool {
        let h = m2 * (t.1 - t.0) * (t.1 - t.0) / 8.0;
        let lo = i + k.0.saturating_sub(WINDOW);
        let hi = (i + k.1 + WINDOW).min(j - 1);
        let (mut best, mut near_a, mut near_b) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        for s in lo..=hi {
            let (a, b) = (self.pts[s], self.pts[s + 1]);
            let (da, db) = (
                point_segment_distance(p.0, a, b),
                point_segment_distance(p.1, a, b),
            );
            best = best.min(da.max(db));
            near_a = near_a.min(da);
            near_b = near_b.min(db);
        }
        if best + h <= self.lim.tol {
            return true;
        }
        // An end already too far (from the segments near it) fails however
        // finely the span is cut.
        if depth >= ARC_MAX_SPLIT_DEPTH || !within(near_a.max(near_b), self.lim.tol) {
            return false;
        }
        let tm = 0.5 * (t.0 + t.1);
        let pm = arc.eval(tm);
        let km = self.vertex_at(k.0, tm * arc.sweep).min(k.1);
        self.span_fits(arc, i, j, (t.0, tm), (p.0, pm), (k.0, km), m2, depth + 1)
            && self.span_fits(arc, i, j, (tm, t.1), (pm, p.1), (km, k.1), m2, depth + 1)
    }
}
