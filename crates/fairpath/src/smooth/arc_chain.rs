//! `arc-fit`'s run assembly: the fitter over one chain's vertices
//! ([`Fitter`], its thresholds [`Limits`]), the search for the longest
//! stretch a block fits ([`longest`]: expand, then bisect) and the greedy
//! walk along the chain that writes the block reaching furthest from each
//! vertex, line, tangent arc or free arc ([`fit_chain`]; module docs of
//! `arc_fit.rs`, "The fit").

use super::arc_fit::{
    ArcFitOptions, ARC_MAX_RADIUS_PER_TOL, ARC_MIN_CHORD_PER_TOL, ARC_SAMPLE_SHARE,
};
use super::chains::{CleanTolerances, LineChain};
use super::kept_joints::end_tangent;
use super::SmoothedRun;
use crate::geom::{Arc, Curve, JointTolerances, Line, Vec3};
use crate::path::Piece;
use alloc::vec::Vec;

/// The unit XY direction of `v`, if it has one.
fn xy_dir(v: Vec3) -> Option<Vec3> {
    Vec3::new(v.x, v.y, 0.0).normalized(0.0)
}

/// The thresholds of one fit, in mm.
pub(super) struct Limits {
    /// Fit tolerance.
    pub(super) tol: f64,
    /// Chord deviation allowed to samples of an arc.
    pub(super) sample: f64,
    pub(super) max_radius: f64,
    pub(super) min_chord: f64,
    /// Below this, points coincide (the cleaning's zero length).
    pub(super) coincident: f64,
}

/// The fitter over one chain's vertices (its candidates are in
/// `arc_candidates.rs`, its checks in `arc_check.rs`).
pub(super) struct Fitter<'a> {
    pub(super) pts: &'a [Vec3],
    /// Cumulative length at each vertex.
    pub(super) cum: Vec<f64>,
    pub(super) lim: Limits,
    /// Scratch: the vertices' angles along the arc being checked, as a
    /// running maximum.
    pub(super) angles: Vec<f64>,
}

/// The largest `j` in `lo..=hi` for which `fits(j)` holds, found by
/// expanding `j - lo = 0, 1, 2, 4, ...` until a failure, then bisecting
/// (fits need not be monotone in `j`; every `j` returned did fit).
fn longest(lo: usize, hi: usize, mut fits: impl FnMut(usize) -> bool) -> Option<usize> {
    if lo > hi || !fits(lo) {
        return None;
    }
    let mut good = lo;
    let mut bad;
    let mut step = 1;
    loop {
        let j = lo + step;
        if j >= hi {
            if good < hi && fits(hi) {
                return Some(hi);
            }
            bad = hi;
            break;
        }
        if fits(j) {
            good = j;
            step *= 2;
        } else {
            bad = j;
            break;
        }
    }
    while bad - good > 1 {
        let mid = good + (bad - good) / 2;
        if fits(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(good)
}

/// Fits one chain of lines with the fewest blocks (module docs).
pub(super) fn fit_chain(
    chain: &LineChain,
    tolerance: f64,
    o: &ArcFitOptions,
    out: &mut SmoothedRun,
) {
    let tangent_angle = JointTolerances::from_tolerance(tolerance).angle;
    let pts = &chain.pts;
    let n = chain.segments();
    if n == 0 {
        return;
    }
    let tol = tolerance * o.fit_share;
    let mut cum = Vec::with_capacity(n + 1);
    let mut acc = 0.0;
    cum.push(0.0);
    for w in pts.windows(2) {
        acc += w[0].dist(w[1]);
        cum.push(acc);
    }
    // The last vertex each segment's feed reaches.
    let mut feed_end = alloc::vec![n; n];
    for k in (0..n.saturating_sub(1)).rev() {
        feed_end[k] = if chain.feed[k] == chain.feed[k + 1] {
            feed_end[k + 1]
        } else {
            k + 1
        };
    }
    let mut f = Fitter {
        pts,
        cum,
        lim: Limits {
            tol,
            sample: tol * ARC_SAMPLE_SHARE,
            max_radius: tolerance * ARC_MAX_RADIUS_PER_TOL,
            min_chord: tolerance * ARC_MIN_CHORD_PER_TOL,
            coincident: CleanTolerances::from_tolerance(tolerance).min_segment,
        },
        angles: Vec::new(),
    };
    let mut tangent = out
        .pieces
        .last()
        .filter(|p| p.end() == pts[0])
        .and_then(|p| xy_dir(end_tangent(&p.curve)));
    let mut i = 0;
    while i < n {
        let hi = feed_end[i].min(i + o.max_lookahead);
        let line_j = longest(i + 1, hi, |j| f.line_fits(i, j)).unwrap_or(i + 1);
        let mut best: (usize, Option<Arc>) = (line_j, None);
        if line_j < hi {
            let free_j = longest(i + 2, hi, |j| f.free_arc(i, j).is_some());
            if let Some(j) = free_j.filter(|&j| j > best.0) {
                best = (j, f.free_arc(i, j));
            }
        }
        if let (true, Some(t)) = (o.tangent, tangent) {
            // The tangent arc wins ties, but not against a line that is
            // tangent itself.
            let line_tangent = best.1.is_none()
                && xy_dir(pts[line_j] - pts[i]).is_some_and(|d| d.angle_to(t) <= tangent_angle);
            let floor = if line_tangent { best.0 + 1 } else { best.0 };
            if floor <= hi {
                let tan_j = longest(i + 2, hi, |j| {
                    f.tangent_arc(i, j, t).is_some_and(|a| f.arc_fits(&a, i, j))
                });
                if let Some(j) = tan_j.filter(|&j| j >= floor) {
                    best = (j, f.tangent_arc(i, j, t));
                }
            }
        }
        let (j, arc) = best;
        let curve = match arc {
            Some(a) => {
                out.transitions += j - i - 1;
                Curve::from(a)
            }
            None => {
                out.merged_collinear += j - i - 1;
                Curve::Line(Line::new(pts[i], pts[j]))
            }
        };
        tangent = xy_dir(end_tangent(&curve));
        out.pieces.push(Piece {
            curve,
            rapid: false,
            source_lines: (chain.lines[i].0, chain.lines[j - 1].1),
            feed: chain.feed[i],
        });
        i = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn longest_finds_the_end_of_a_monotone_predicate() {
        for end in 3..40 {
            assert_eq!(longest(3, 39, |j| j <= end), Some(end));
        }
        assert_eq!(longest(3, 39, |_| false), None);
        assert_eq!(longest(3, 3, |_| true), Some(3));
        assert_eq!(longest(4, 3, |_| true), None);
    }
}
