//! The guard against the failure the thesis reports (section 5.1: "if the
//! tool path had the shape of the letter U and the path tolerance was
//! very large, the smoothed path could take the shape of the letter V"):
//! flattening a wide tube's worth of a bend can straighten its middle and
//! push all the turning into two short corners, whose curvature rises
//! above anything the original had there.
//!
//! The rule (ours; the thesis only reports the failure): before each
//! iteration's move is kept, the peak curvature of every knot span of the
//! moved curve is sampled ([`span_peaks`]) and compared with the peaks
//! the original curve had within reach of that span (the spans sharing a
//! control point with it: knot indices up to [`REACH`] apart). A span
//! whose new peak exceeds all of those is a **local rise**: the control
//! points of that span that moved are put back where they were for this
//! iteration, and the check is repeated until no span rises. They may
//! move again in a later iteration, once their neighbours have moved (a
//! ripple's neighbours catch up with it: the rise was transient); where
//! every move would make a V, nothing moves and the fairing stops. Curvature may so move about and spread within a
//! few spans, as flattening a ripple or widening a corner does, and fall
//! anywhere, but never climb above what the original had there: a U may
//! not turn into a V. Spans whose new peak is at most `floor` (the caller
//! passes `accuracy` times the original curve's highest peak) are never a
//! rise: a nearly straight span may bend a little.
//!
//! The reference is the original rather than the previous iteration: a
//! guard against the previous iteration with any allowance lets a peak
//! creep up a little every iteration, and one without any stops the
//! transient rises of ordinary fairing.
//!
//! Putting some control points back leaves a polygon whose every point is
//! either the old or the new one, so the move is still within the tube's
//! bound for the full move (convex hull of the partial step); the caller
//! checks the sure bound again anyway.

use super::spans::{bezier_derivatives, bezier_of_span, nonempty_spans};
use crate::geom::{curvature_from, Vec3};
use alloc::vec::Vec;

/// Samples per knot span of the guard's peak curvature (ours): the
/// curvature of a cubic span has few local maxima, and 16 equal steps
/// find its peak to within a few percent on the curves faired here (the
/// thesis' `precision` of 5 misses V corners that form between samples).
pub const PEAK_SAMPLES: usize = 16;

/// How many knot indices apart two spans of a cubic may be and still
/// share a control point (span `s` uses control points `s-3..=s`).
pub const REACH: usize = 3;

/// Knot index and sampled peak curvature (1/mm) of every non-empty span of
/// the clamped cubic (`knots`, `pts`), at `samples` equal steps, ends
/// included. A sample, not a bound: the guard compares like with like.
pub fn span_peaks(knots: &[f64], pts: &[Vec3], samples: usize) -> Vec<(usize, f64)> {
    nonempty_spans(knots, pts.len())
        .into_iter()
        .map(|s| {
            let b = bezier_of_span(knots, pts, s);
            let peak = (0..=samples)
                .map(|j| {
                    let (d1, d2) = bezier_derivatives(&b, j as f64 / samples as f64);
                    curvature_from(d1, d2)
                })
                .fold(0.0, f64::max);
            (s, peak)
        })
        .collect()
}

/// The spans (knot indices) of `new` whose peak is a local rise over
/// `reference` (the same spans), ignoring peaks at or below `floor`.
pub fn risen_spans(reference: &[(usize, f64)], new: &[(usize, f64)], floor: f64) -> Vec<usize> {
    let mut out = Vec::new();
    for &(s, peak) in new {
        if peak <= floor {
            continue; // (a NaN or infinite peak is a rise)
        }
        let before = reference
            .iter()
            .filter(|(t, _)| t.abs_diff(s) <= REACH)
            .map(|&(_, k)| k)
            .fold(0.0, f64::max);
        if peak > before || peak.is_nan() {
            out.push(s);
        }
    }
    out
}

/// Puts back (to `old`) the control points of the risen spans of `new`
/// (see the module documentation) until no
/// span rises above the `reference` peaks (the original curve's). Returns
/// how many points were put back.
pub fn undo_rises(
    knots: &[f64],
    old: &[Vec3],
    new: &mut [Vec3],
    reference: &[(usize, f64)],
    samples: usize,
    floor: f64,
) -> usize {
    let mut undone = 0;
    loop {
        let peaks = span_peaks(knots, new, samples);
        let risen = risen_spans(reference, &peaks, floor);
        let mut changed = false;
        for s in risen {
            for j in s - REACH..=s {
                if new[j] != old[j] {
                    new[j] = old[j];
                    undone += 1;
                    changed = true;
                }
            }
        }
        if !changed {
            return undone;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    #[test]
    fn a_sharper_corner_is_put_back() {
        let u = vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0];
        let old: Vec<Vec3> = [
            (0., 0.),
            (1., 0.),
            (2., 0.5),
            (3., 1.0),
            (4., 0.5),
            (5., 0.),
            (6., 0.),
        ]
        .iter()
        .map(|&(x, y)| Vec3::new(x, y, 0.0))
        .collect();
        let mut new = old.clone();
        new[3] = Vec3::new(3.0, 3.0, 0.0); // a spike: much sharper
        let peaks = span_peaks(&u, &old, 5);
        let n = undo_rises(&u, &old, &mut new, &peaks, 5, 0.0);
        assert_eq!(n, 1);
        assert_eq!(new, old);
        // A flatter move is kept.
        let mut flat = old.clone();
        flat[3] = Vec3::new(3.0, 0.6, 0.0);
        assert_eq!(undo_rises(&u, &old, &mut flat, &peaks, 5, 0.0), 0);
        assert_eq!(flat[3].y, 0.6);
    }
}
