//! The guard against the failure the thesis reports (section 5.1: "if the
//! tool path had the shape of the letter U and the path tolerance was
//! very large, the smoothed path could take the shape of the letter V"):
//! flattening a wide tube's worth of a bend can straighten its middle and
//! push all the turning into two short corners, whose curvature rises
//! above anything the original had there.
//!
//! The rule (ours; the thesis only reports the failure): before each
//! iteration's move is kept, the peak curvature of every knot span of the
//! moved curve is sampled ([`span_peak`]) and compared with the peaks the
//! original curve had within reach of that span (the spans sharing a
//! control point with it: knot indices up to [`REACH`] apart). A span
//! whose new peak exceeds all of those is a **local rise**: the control
//! points of that span that moved are put back where they were for this
//! iteration, and the spans they touch are checked again, until no span
//! rises. The points may move again in a later iteration, once their
//! neighbours have moved (a ripple's neighbours catch up with it: the
//! rise was transient); where every move would make a V, nothing moves
//! and the fairing stops. Curvature may so move about and spread within a
//! few spans, as flattening a ripple or widening a corner does, and fall
//! anywhere, but never climb above what the original had there: a U may
//! not turn into a V. Spans whose new peak is at most a floor
//! (`accuracy` times the original curve's highest peak) are never a rise:
//! a nearly straight span may bend a little.
//!
//! The reference is the original rather than the previous iteration: a
//! guard against the previous iteration with any allowance lets a peak
//! creep up a little every iteration, and one without any stops the
//! transient rises of ordinary fairing.
//!
//! Putting some control points back leaves a polygon whose every point is
//! either the old or the new one, so the move is still within the tube's
//! bound for the full move (convex hull of the partial step); the caller
//! checks the sure bound again anyway. The work is one pass over the
//! spans plus a few spans per point put back.

use super::spans::{nonempty_spans, Basis, Span};
use crate::geom::{sampled_peak, Extrema, Vec3};
use alloc::vec;
use alloc::vec::Vec;

/// Samples per knot span of the guard's peak curvature (ours): the
/// curvature of a cubic span has few local maxima, and 16 equal steps
/// bracket each (the thesis' `precision` of 5 misses V corners that form
/// between samples); where the samples show a peak narrower than their
/// step, it is refined between them ([`sampled_peak()`],
/// [`Extrema::Narrow`]), so that a near-cusp's spike between two samples
/// counts at its height (LinuxCNC's `homer_p1.ngc`: its peak of 955 1/mm
/// samples as 73, and a fairing judged by the samples raised it to 8,021).
pub const PEAK_SAMPLES: usize = 16;

/// How far (a share of the span's parameter interval) the refinement of
/// [`span_peak`] narrows each bracket: a billionth, below any peak a
/// fairing could move.
pub const PEAK_ACCURACY: f64 = 1e-9;

/// How many knot indices apart two spans of a cubic may be and still
/// share a control point (span `s` uses control points `s-3..=s`); of a
/// curve of degree `p`, `p` ([`Basis::degree`]).
pub const REACH: usize = super::spans::DEGREE;

/// Peak curvature (1/mm) of the non-empty span `s` of the clamped
/// B-spline (`basis`, `pts`): [`PEAK_SAMPLES`] equal steps, ends included, refined
/// between them to [`PEAK_ACCURACY`] of the span where the samples show a
/// peak narrower than their step ([`sampled_peak()`], [`Extrema::Narrow`]:
/// a near-cusp). A lower bound; the guard compares like with like (the
/// peak pass measures its trials so too: refining every sampled extremum
/// made `fair` several times slower over the shared programs at 0.01 mm;
/// measurements: docs/tuning.md, `span_peak`).
pub fn span_peak(basis: &Basis, pts: &[Vec3], s: usize) -> f64 {
    let b = Span::of(basis, pts, s);
    sampled_peak(
        |tau| b.derivs12(tau),
        (0.0, 1.0),
        PEAK_SAMPLES,
        PEAK_ACCURACY,
        Extrema::Narrow,
    )
}

/// What the original curve allows each span: the highest peak it had
/// within reach, and the floor below which nothing counts.
#[derive(Clone, Debug, PartialEq)]
pub struct PeakReference {
    /// Per knot index `s` of a non-empty span: the original's highest span
    /// peak within [`REACH`] knot indices (0 for empty spans).
    pub near: Vec<f64>,
    /// `accuracy` times the original's highest peak.
    pub floor: f64,
}

impl PeakReference {
    /// The reference of the original curve (`basis`, `orig`).
    pub fn new(basis: &Basis, orig: &[Vec3], accuracy: f64) -> PeakReference {
        let spans = nonempty_spans(basis, orig.len());
        let mut own = vec![0.0f64; orig.len()];
        for &s in &spans {
            own[s] = span_peak(basis, orig, s);
        }
        let reach = basis.degree;
        let mut near = vec![0.0f64; orig.len()];
        for &s in &spans {
            let lo = s.saturating_sub(reach);
            let hi = (s + reach).min(orig.len() - 1);
            near[s] = own[lo..=hi].iter().copied().fold(0.0, f64::max);
        }
        let top = own.iter().copied().fold(0.0, f64::max);
        PeakReference {
            near,
            floor: accuracy * top,
        }
    }

    /// Whether a new peak `peak` of span `s` is a local rise.
    pub fn is_rise(&self, s: usize, peak: f64) -> bool {
        peak > self.floor && (peak > self.near[s] || peak.is_nan())
    }
}

/// Puts back (to `old`) the control points of the spans of `new` whose
/// peak is a local rise over `reference` (see the module documentation),
/// and checks the spans they touch again, until no span rises. Returns
/// how many points were put back.
pub fn undo_rises(
    basis: &Basis,
    old: &[Vec3],
    new: &mut [Vec3],
    reference: &PeakReference,
) -> usize {
    let (m, knots, reach) = (new.len(), basis.knots, basis.degree);
    let mut undone = 0;
    let mut todo = nonempty_spans(basis, m);
    while !todo.is_empty() {
        let risen: Vec<usize> = todo
            .iter()
            .copied()
            .filter(|&s| reference.is_rise(s, span_peak(basis, new, s)))
            .collect();
        todo.clear();
        for s in risen {
            for j in s - reach..=s {
                if new[j] != old[j] {
                    new[j] = old[j];
                    undone += 1;
                    // The spans control point j belongs to.
                    let hi = (j + reach).min(m - 1);
                    todo.extend((j.max(reach)..=hi).filter(|&t| knots[t] < knots[t + 1]));
                }
            }
        }
        todo.sort_unstable();
        todo.dedup();
    }
    undone
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let u = Basis::cubic(&u);
        let reference = PeakReference::new(&u, &old, 0.01);
        let mut new = old.clone();
        new[3] = Vec3::new(3.0, 3.0, 0.0); // a spike: much sharper
        assert_eq!(undo_rises(&u, &old, &mut new, &reference), 1);
        assert_eq!(new, old);
        // A flatter move is kept.
        let mut flat = old.clone();
        flat[3] = Vec3::new(3.0, 0.6, 0.0);
        assert_eq!(undo_rises(&u, &old, &mut flat, &reference), 0);
        assert_eq!(flat[3].y, 0.6);
    }
}
