//! The band's width at a turn (module docs of [`super`], step 7): how high
//! a band path can rise in the turn's normal direction, and from that the
//! least time between two gates on either side of a turn for a given
//! least speed of its window.

use super::samples::SampleGrid;
use crate::geom::Vec3;
use crate::math;

/// Samples of a polyline bucketed in a uniform grid, for the highest
/// sample along a direction within a ball.
pub(super) struct Heights {
    grid: SampleGrid,
    /// Spacing of the samples along the polyline.
    pub(super) step: f64,
}

impl Heights {
    /// Samples spaced `step` along the polyline `pts` (arc lengths `s`),
    /// bucketed in cells of `cell` mm.
    pub(super) fn new(pts: &[Vec3], s: &[f64], step: f64, cell: f64) -> Heights {
        Heights {
            grid: SampleGrid::new(pts, s, step, cell),
            step,
        }
    }

    /// An upper bound of `n . y` over the polyline points `y` within
    /// `radius` (at most the cell size) of `m`: the highest sample within
    /// `radius + step / 2`, plus `step / 2` (every polyline point is within
    /// `step / 2` of a sample).
    pub(super) fn top(&self, m: Vec3, radius: f64, n: Vec3) -> f64 {
        let reach = radius + 0.5 * self.step;
        let mut top = f64::NEG_INFINITY;
        self.grid.any_near(m, |_, p| {
            if p.dist(m) <= reach {
                top = top.max(n.dot(p));
            }
            false
        });
        top + 0.5 * self.step
    }
}

/// A gate as the width argument sees it: its centre's height `n . q`
/// above the band's top `H` and its radius.
#[derive(Clone, Copy, Debug)]
pub(super) struct GateHeight {
    pub(super) height: f64,
    pub(super) radius: f64,
}

/// `G` of step 7 for a rise from gate `lo` to gate `hi` (passed in this
/// order along the rise): `sqrt(e - max h at lo) - sqrt(e - min h at hi)`,
/// with `h = n . x - H <= e` on the band inside the ball.
pub(super) fn rise(e: f64, lo: GateHeight, hi: GateHeight) -> f64 {
    let w_lo = math::sqrt((e - (lo.height + lo.radius)).max(0.0));
    let w_hi = math::sqrt((e - (hi.height - hi.radius)).max(0.0));
    (w_lo - w_hi).max(0.0)
}

/// The largest curvature a path can have everywhere in a window whose
/// least speed is `c`: `k v^2 <= A_n` and, with the jerk cap on curves,
/// `k^2 v^3 <= J`, at the slowest point.
pub(super) fn curvature_cap(c: f64, normal_acc: f64, jerk: Option<f64>) -> f64 {
    if c <= 0.0 {
        return f64::INFINITY;
    }
    let mut k = normal_acc / (c * c);
    if let Some(j) = jerk {
        k = k.min(math::sqrt(j / (c * c * c)));
    }
    k
}

/// A lower bound of the time of a rise `g` (step 7) at speeds `<= f` with
/// curvature `<= k` everywhere after it until the tangent turns down:
/// `sqrt(e - h)` falls at most at `f sqrt(k / 2)` per second.
pub(super) fn rise_time(g: f64, f: f64, k: f64) -> f64 {
    if g <= 0.0 {
        return 0.0;
    }
    if !k.is_finite() {
        return 0.0;
    }
    if k <= 0.0 {
        return f64::INFINITY;
    }
    g / (f * math::sqrt(0.5 * k))
}
