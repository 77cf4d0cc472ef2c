//! The iterations (thesis sections 3.9 to 3.11, "3.7" and "3.8" in the
//! checklist): categorise, find directions, scale the move distances by the
//! inverse sensitivities, move (`P_new = P_old + MD_i DV_i`, eq. 3-47),
//! measure, until the curve touches the tube.
//!
//! One iteration:
//! 1. `D_allow = R - max |P_orig(t) - P_cur(t)|`, sampled (eq. 3-39,
//!    [`super::tube::sampled_deviation`]). Within `accuracy * R` of the tube: stop
//!    ([`Termination::Touching`], section 3.11).
//! 2. Categories and directions of the current polygon
//!    ([`categorize`], [`directions`]).
//! 3. `MD_i = D_allow * S_inv_i` (eqs. 3-40, 3-41) from the sensitivities
//!    of the previous move (the mock iteration's before the first), each
//!    move at most the point's reach; the new polygon.
//! 4. **Acceptance on a sure bound**: the new polygon passes when
//!    [`super::tube::deviation_bound`] (exact to `accuracy * R`) of its difference from
//!    the original is at most `R`. The thesis moves by the sampled
//!    allowance and, on termination, returns "the previous iteration
//!    control polygon ... because the spline has passed the tolerance
//!    band"; here a polygon that fails is never taken: the move is made
//!    again with the sure allowance `D_sure = R - bound(current) -
//!    accuracy * R`, which cannot fail (the step's own convex hull moves
//!    the curve by at most `D_sure`, and the bound is within `accuracy *
//!    R` of the truth), and when even that leaves no room the fairing
//!    stops ([`Termination::TubeFull`]). So every polygon the fairing
//!    keeps, the last one included, is surely inside the tube.
//! 5. The U-to-V guard ([`undo_rises`]) puts back the points of spans
//!    whose peak curvature rose above the original's there (optional, on
//!    by default).
//! 6. Sensitivities of the move made (eq. 3-38).
//!
//! Stops also when nothing moves ([`Termination::Stationary`]: every
//! point straight or pinned, or every move put back by the guard) and
//! after `max_iterations` ([`Termination::IterationCap`]; the thesis has
//! no cap).

use super::categories::categorize;
use super::directions::{directions, Direction, STILL_SHARE};
use super::guard::{undo_rises, PeakReference};
use super::polygon::Polygon;
use super::sensitivity::{move_distances, point_parameters, scaled_inverse, sensitivities};
use super::slide::Original;
use super::spans::nonempty_spans;
use super::spans::Basis;
use super::tube::{difference, hull_bound};
use super::{IterationRecord, Termination, TubeFairOptions};
use crate::geom::Vec3;
use alloc::vec;
use alloc::vec::Vec;

/// What the iterations work on.
pub(super) struct Setup<'a> {
    /// The clamped knot vector, degree and weights.
    pub basis: Basis<'a>,
    /// The original control points (all `m`).
    pub orig: &'a [Vec3],
    pub poly: Polygon,
    /// Ring points that never move.
    pub pinned: Vec<bool>,
    /// Original lengths of the two end legs.
    pub legs: [f64; 2],
    pub opts: &'a TubeFairOptions,
    /// The original's spans, for the sliding tube.
    pub original: Option<&'a Original<'a>>,
}

/// What the iterations did.
pub(super) struct Outcome {
    pub points: Vec<Vec3>,
    pub records: Vec<IterationRecord>,
    pub termination: Termination,
    pub undone: usize,
    /// Sure bound of the result's distance from the original.
    pub bound: f64,
    /// Sampled distance of the result from the original.
    pub sampled: f64,
}

fn add(a: &[Vec3], b: &[Vec3]) -> Vec<Vec3> {
    a.iter().zip(b).map(|(p, q)| *p + *q).collect()
}

impl Setup<'_> {
    /// Directions of the ring points of `cur`.
    fn plan(&self, cur: &[Vec3]) -> Vec<Direction> {
        let n = self.poly.n;
        let res = self.opts.resolution();
        let cats = categorize(&cur[..n], &self.poly, res);
        directions(
            &cur[..n],
            &self.poly,
            &cats,
            &self.pinned,
            self.opts.ends,
            self.legs,
            STILL_SHARE * self.opts.radius,
        )
    }

    /// The step of all `m` control points for move distances `md` (ring
    /// indices), each at most its reach (a closed path's last point goes
    /// with the seam, which never moves).
    fn step(&self, dirs: &[Direction], md: &[f64]) -> Vec<Vec3> {
        let m = self.orig.len();
        let mut step = vec![Vec3::ZERO; m];
        for (i, d) in dirs.iter().enumerate() {
            if d.moves() {
                step[i] = d.dv * md[i].min(d.reach);
            }
        }
        if self.poly.closed {
            step[m - 1] = step[0];
        }
        step
    }

    /// A sure bound of `pts`' distance from the original, as the tube is
    /// measured.
    fn bound(&self, pts: &[Vec3]) -> f64 {
        let (basis, orig) = (&self.basis, self.orig);
        let spans = nonempty_spans(basis, orig.len());
        let diff = difference(pts, orig);
        let res = self.opts.resolution();
        self.opts
            .tube
            .bound_on(pts, self.original, &diff, basis, &spans, res)
    }

    /// `pts`' distance from the original sampled at `precision` steps of
    /// every span, as the tube is measured.
    fn sampled(&self, pts: &[Vec3]) -> f64 {
        let o = self.opts;
        o.tube.sampled(
            pts,
            self.orig,
            self.original,
            &self.basis,
            o.precision,
            o.resolution(),
        )
    }

    /// Which of the `m` control points move under `dirs`.
    fn moving(&self, dirs: &[Direction]) -> Vec<bool> {
        (0..self.orig.len())
            .map(|i| dirs.get(i).is_some_and(|d| d.moves()))
            .collect()
    }

    pub fn run(&self) -> Outcome {
        let (basis, orig, opts) = (&self.basis, self.orig, self.opts);
        let m = orig.len();
        let r = opts.radius;
        let res = opts.resolution();
        let params = point_parameters(basis, m);

        // The mock iteration (section 3.7): D_max = R, every move R.
        let dirs = self.plan(orig);
        let ones: Vec<f64> = self
            .moving(&dirs)
            .iter()
            .map(|&mv| if mv { 1.0 } else { 0.0 })
            .collect();
        let mock = self.step(&dirs, &move_distances(&ones, r));
        let mut sens = sensitivities(&mock, basis, &params);

        let reference = opts
            .peak_guard
            .then(|| PeakReference::new(basis, orig, opts.accuracy));
        let mut cur = orig.to_vec();
        let (mut cur_bound, mut sampled) = (0.0, 0.0);
        let mut records = Vec::new();
        let mut undone_total = 0;
        let mut termination = Termination::IterationCap;
        for _ in 0..opts.max_iterations {
            let d_allow = r - sampled;
            if d_allow <= res {
                termination = Termination::Touching;
                break;
            }
            let dirs = self.plan(&cur);
            let moving = self.moving(&dirs);
            if !moving.iter().any(|&mv| mv) {
                termination = Termination::Stationary;
                break;
            }
            let s_inv = scaled_inverse(&sens, &moving);
            let mut new = add(&cur, &self.step(&dirs, &move_distances(&s_inv, d_allow)));
            let mut bound = self.bound(&new);
            let mut sure_step = false;
            if bound > r {
                let d_sure = r - cur_bound - res;
                if d_sure <= res {
                    termination = Termination::TubeFull;
                    break;
                }
                sure_step = true;
                new = add(&cur, &self.step(&dirs, &move_distances(&s_inv, d_sure)));
                bound = self.bound(&new);
                if bound > r {
                    termination = Termination::TubeFull;
                    break;
                }
            }
            let mut undone = 0;
            if let Some(reference) = &reference {
                undone = undo_rises(basis, &cur, &mut new, reference);
                if undone > 0 {
                    undone_total += undone;
                    bound = self.bound(&new);
                    if bound > r {
                        termination = Termination::TubeFull;
                        break;
                    }
                }
            }
            let step = difference(&new, &cur);
            let largest_move = hull_bound(&step);
            if largest_move == 0.0 {
                termination = Termination::Stationary;
                break;
            }
            sens = sensitivities(&step, basis, &params);
            cur = new;
            cur_bound = bound;
            sampled = self.sampled(&cur);
            records.push(IterationRecord {
                max_deviation: sampled,
                deviation_bound: bound,
                largest_move,
                undone,
                sure_step,
            });
        }
        Outcome {
            points: cur,
            records,
            termination,
            undone: undone_total,
            bound: cur_bound,
            sampled,
        }
    }
}
