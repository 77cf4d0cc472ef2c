//! Points added on a polyline before `bspline-fit` fits it, so that least
//! squares sees the polyline between its vertices where it must (long
//! segments, sharply turning vertices). Not in seed 002; see
//! [`fill_segments`].

use crate::geom::Vec3;
use alloc::vec::Vec;

/// A segment longer than this many median segment lengths gets points
/// inside it (see [`fill_segments`]).
pub const LONG_SEGMENT_PER_MEDIAN: f64 = 2.0;

/// Spacing of the points added next to a vertex that turns by `phi`, as a
/// multiple of `target / phi` (see [`fill_segments`]). Chosen on the
/// issue-5 survey (`scripts/survey.sh`), where 1 planned faster than
/// closer and wider spacings (measurements: docs/tuning.md,
/// `CORNER_SPACING`).
pub const CORNER_SPACING: f64 = 1.0;

/// Points added next to each end of a segment at its corner spacing.
const CORNER_POINTS: usize = 8;

/// Most points added evenly inside one segment (besides those next to
/// its ends).
const MAX_FILL_PER_SEGMENT: usize = 16;

/// `pts` with points added inside segments (the points lie on the
/// polyline, so the deviation bound is unchanged):
///
/// * evenly, so that no piece is longer than [`LONG_SEGMENT_PER_MEDIAN`]
///   times the median segment length (at most [`MAX_FILL_PER_SEGMENT`]
///   per segment);
/// * next to a vertex turning by `phi`, [`CORNER_POINTS`] points spaced
///   `h = CORNER_SPACING * target / phi` (within half of each segment).
///
/// Least squares sees the polyline only at its points.
///
/// * A long segment between short ones (a CAM path that runs straight for
///   a few mm between curved stretches) leaves the fit free over its
///   length: the curve may bulge off it, and the knots that the fit's search
///   inserts there to pull it back have no data (Schoenberg-Whitney
///   fails), so insertion ran to thousands of sub-micrometre spans on
///   LinuxCNC's `LHchips4.ngc` (a 3.8 mm segment, median 0.15 mm) without
///   reducing the error.
/// * Next to a vertex that turns by `phi`, a curve within `target` of the
///   polyline turns over a length of the order of `target / sin(phi / 2)`
///   (the legs of a corner transition, seed 000). Data only at the
///   vertices leaves that turn unseen: the cubic overshoots the straight
///   moves between vertices, and no control-point count passed on a
///   raster step-over of 1 mm moves turning by 22 to 63 degrees
///   (`test_12mmflat.ngc`, 0.045 mm), which went to corner transitions
///   whose curvature ramps the machine must crawl through. Points every
///   `target / phi` put a few data points on each leg of that turn.
pub(crate) fn fill_segments(pts: &[Vec3], target: f64) -> Vec<Vec3> {
    let n = pts.len() - 1;
    let mut lens: Vec<f64> = pts.windows(2).map(|w| w[0].dist(w[1])).collect();
    let mid = n / 2;
    let median = *lens.select_nth_unstable_by(mid, f64::total_cmp).1;
    let gap = LONG_SEGMENT_PER_MEDIAN * median;
    if !(gap > 0.0 && gap.is_finite()) {
        return pts.to_vec();
    }
    // Spacing next to vertex i (infinite at the ends and where straight).
    let corner = |i: usize| -> f64 {
        if i == 0 || i == n {
            return f64::INFINITY;
        }
        let phi = (pts[i] - pts[i - 1]).angle_to(pts[i + 1] - pts[i]);
        if phi > 0.0 {
            CORNER_SPACING * target / phi
        } else {
            f64::INFINITY
        }
    };
    // Length next to a vertex of spacing h that gets points (at most half
    // the segment).
    let zone = |h: f64, len: f64| (CORNER_POINTS as f64 * h).min(0.5 * len);
    let mut out = Vec::with_capacity(pts.len());
    out.push(pts[0]);
    for (i, w) in pts.windows(2).enumerate() {
        let len = w[0].dist(w[1]);
        // Distances from w[0] of the points added: CORNER_POINTS at each
        // end's corner spacing (within half the segment), then the middle
        // evenly at the long-segment spacing.
        let mut at: Vec<f64> = Vec::new();
        let (ha, hb) = (corner(i), corner(i + 1));
        let za = zone(ha, len);
        let zb = zone(hb, len);
        let mut d = ha;
        while d < za {
            at.push(d);
            d += ha;
        }
        let from = at.last().copied().unwrap_or(0.0);
        let mut tail: Vec<f64> = Vec::new();
        let mut d = hb;
        while d < zb {
            tail.push(len - d);
            d += hb;
        }
        let to = tail.last().copied().unwrap_or(len);
        let middle = to - from;
        if middle > gap {
            let pieces = crate::math::ceil(middle / gap).min((MAX_FILL_PER_SEGMENT + 1) as f64);
            let pieces = pieces as usize;
            for k in 1..pieces {
                at.push(from + middle * k as f64 / pieces as f64);
            }
        }
        at.extend(tail.iter().rev());
        for d in at {
            out.push(w[0].lerp(w[1], d / len));
        }
        out.push(w[1]);
    }
    out
}
