//! One place that hands out the user's tolerance.
//!
//! The promise is: every point of the written feed path lies within
//! `total` mm (3D) of the original feed path. Three things spend it, one
//! after the other, and their shares add up to `total`:
//!
//! | share | who spends it | bounded by |
//! |---|---|---|
//! | [`ToleranceBudget::smoothing`] | the smoothing method: its curves stay this close to the original | the verifier, on the curves |
//! | [`ToleranceBudget::output`] | writing the curves as the output format can say them: G1 chords, G2/G3 arcs, spline blocks, and the rounding of written coordinates (the writer takes its share of rounding out of this, see `fairpath_gcode::write_decimals`) | the verifier, on the written text read back |
//! | [`ToleranceBudget::blend`] | the controller's own corner blending of what is written, when fairpath writes a blending mode for it (LinuxCNC `G64 P<blend> Q0`); 0 otherwise | the controller |
//!
//! So the curves are within `smoothing`, the written path within
//! `smoothing + output` (checked on the re-read text), and what a blending
//! controller runs within `total`.
//!
//! ## Every share, in one place
//!
//! Each consumer spends a part of the share it is handed, never more; the
//! fractions below are the only ones in the code base (the consumers import
//! them from here), and [`ToleranceBudget::shares`] lists the leaves in mm,
//! which add up to at most `total` (tested).
//!
//! ```text
//! total
//! |- smoothing = total - output - blend       -> the method (Smoother::smooth_run)
//! |    |- auto: ARC_SAMPLING_SHARE of it for the chords of sampled arcs,
//! |    |        the rest to the candidate methods
//! |    |- cleaning: CLEAN_SHARE for zero-length moves dropped; jogs absorbed
//! |    |        into their neighbours within ABSORB_SHARE per segment, which
//! |    |        the corner transitions take out of their band where spent
//! |    |- corner transitions, fits: aim at BAND_USE of their share; the rest
//! |    |        covers the cleaning of the run (CLEAN_SHARE) and f64 rounding
//! |    |- arc-fit: ARC_FIT_SHARE for its blocks (ARC_SAMPLE_SHARE of that for
//! |    |        sampling arcs); the rest covers cleaning and written centres
//! |    '- fair: its fits of runs of lines FAIR_FIT_SHARE of BAND_USE of it,
//! |             the tube of the fairing around them BAND_USE of the rest
//! |             (around curves of the input: BAND_USE of all of it); in a
//! |             run with curves the fairing cannot take (rational, degree
//! |             4 and above), FAIR_SAMPLE_SHARE of it for their chords
//! |             first, the above out of the rest
//! |- output (OUTPUT_SHARE of total by default)
//! |    |- rounding: ROUNDING_SHARE of it for the decimals written
//! |    '- render: the rest, for chords, arcs or spline blocks; arcs aim at
//! |             DEVIATION_USE of it, G1 spacing at CHORD_USE; lines up to
//! |             SHORT_LINE_SHARE of it long merged into the piece before
//! |             them within ABSORB_SHIFT_SHARE of it (out of the rest)
//! '- blend: LinuxCNC's G64 P, taken out of the output share by the writer
//!          (BLEND_SHARE_G1 of it for G1 output, BLEND_SHARE_CURVES else)
//! ```
//!
//! Run end points are compared exactly, up to ENDPOINT_ROUNDING_SHARE of
//! the tolerance (the f64 rounding of the input's own arithmetic).

/// Default share of the output approximation: a tenth of the tolerance.
pub const OUTPUT_SHARE: f64 = 0.1;

/// Default share of the output approximation for G-code formats that
/// write the smoothed B-splines exactly (G6.2 blocks): a fiftieth of the
/// tolerance. There the output share pays for the rounding of written
/// coordinates and for the few pieces the format cannot say exactly (a
/// B-spline above the controller's degree, rendered within it), not for
/// chords of every curve; the rest goes to the smoothing, whose gain grows
/// with the tube (the thesis' square of rippled corners at 0.025 mm:
/// straightened in a tube of 0.9 of the tolerance 2.0% less time in the
/// thesis' model, in 0.98 of it 3.7%; measurements: docs/tuning.md,
/// "The output share of exact formats").
pub const EXACT_OUTPUT_SHARE: f64 = 0.02;

/// Largest share of the tolerance the output approximation may be given
/// (`--chord`; the chords of a streamed motion): at least half is left
/// to the smoothing, which a method needs to round a corner at all.
pub const MAX_OUTPUT_SHARE: f64 = 0.5;

/// Share of the output share that the rounding of written coordinates may
/// take (more decimals are written until it fits): what it leaves is for
/// the chords, arcs or spline blocks themselves.
pub const ROUNDING_SHARE: f64 = 0.1;

/// Share of the render share the sampled deviation of written arcs may use:
/// sampling at a fixed number of points per biarc sees the error of an
/// O(h^3) fit to within a few percent; the written text is verified exactly
/// afterwards.
pub const DEVIATION_USE: f64 = 0.9;

/// Share of the render share the spacing rule of G1 output aims at (the
/// chord error is checked at each move's middle afterwards).
pub const CHORD_USE: f64 = 0.9;

/// Lines of a rendered run no longer than this share of the render share
/// are merged into the piece before them (`render::absorb`): written, the
/// rounding of their ends turns their direction into corners with no room
/// to blend.
pub const SHORT_LINE_SHARE: f64 = 0.25;

/// Share of the render share a merged short line may move the path by:
/// out of what [`DEVIATION_USE`] and [`CHORD_USE`] leave.
pub const ABSORB_SHIFT_SHARE: f64 = 1e-3;

/// Largest turn (rad) of an arc's start tangent that extending it over a
/// merged short line may make (`render::absorb`): extended to a new end
/// about the same centre, a spiral's radius law changes and its start
/// tangent swings (by `(r1' - r1) / (r sweep)` about), which turns the
/// joint before it. Kept, the short line would turn its own joints by
/// about `2 sqrt(3) eps / L` once its ends are rounded to `eps` (1.6e-4
/// rad for a 1.1 um line, the longest absorbed at 0.05 mm, at 5e-8 mm):
/// a swing below 1e-4 rad costs less than the line it removes (on
/// `LHchips4.ngc` the largest is 1.1e-6), and a short arc's swing of
/// 6e-3 rad, which the renderer's proptest found, is refused.
pub const ABSORB_TURN: f64 = 1e-4;

/// Share of the output share LinuxCNC's blending (`G64 P`) gets for G1
/// output, where every vertex is blended.
pub const BLEND_SHARE_G1: f64 = 0.5;

/// Share of the output share LinuxCNC's blending gets for the other G-code
/// formats (only corners that were kept are blended).
pub const BLEND_SHARE_CURVES: f64 = 0.1;

/// Share of the smoothing share that `auto` gives the chords of sampled
/// arcs (its candidates work on the chords with the rest).
pub const ARC_SAMPLING_SHARE: f64 = 0.05;

/// Share of the tolerance the cleaning of a run may move it: zero-length
/// moves dropped and vertices merged within this share (below any written
/// decimal), by every method (`smooth/chains.rs`, `none`).
pub const CLEAN_SHARE: f64 = 1e-3;

/// Share of the tolerance within which a vertex counts as straight on:
/// cleaning merges it where it lies within this distance of the merged
/// segment (`smooth/chains.rs`, `merge_collinear`), which moves the path
/// by no more than that.
pub const COLLINEAR_SHARE: f64 = 1e-6;

/// Share of the tolerance that absorbing moves far inside it (jogs, moves
/// up to twice this long) into their neighbours may move one segment of a
/// chain of lines before corner transitions are built (`smooth/absorb.rs`).
/// It is no extra share: the corner engine builds a transition within its
/// band *less* what absorbing spent on its two segments
/// (`LineChain::absorbed`), so by the triangle inequality the result stays
/// within the band of the original program and the shares below add up as
/// before. Where nothing is absorbed, the
/// bands are unchanged. A tenth: CAM programs step over with moves of a
/// few micrometres (LinuxCNC's `line-contouring-xz.ngc` goes down an arch,
/// 1.2 mm across and 4 um down, then up the next arch; `LHchips4.ngc` has
/// moves of 5 to 7 um in Z between long ones), which at 5% of 0.05 mm
/// were no jogs, and their corners' transitions were squeezed into them
/// (942 1/mm in `auto`'s and `bspline-corner`'s output). Not more: at a
/// quarter, the 10 um chords of a spiral (`spiral_tangent_test.ngc`) were
/// all jogs, collapsed in turn into segments of uneven length whose
/// transitions peaked at 198,000 1/mm (measurements: docs/tuning.md,
/// `ABSORB_SHARE`).
pub const ABSORB_SHARE: f64 = 0.1;

/// Longest move, in tolerances, that absorbing may skip next to a sharp
/// corner it hides (`smooth/absorb.rs`: within [`ABSORB_SHARE`] all the
/// same): a corner transition at 0.05 mm reaches about a tolerance or two
/// along its segments, so a shorter move squeezes it.
pub const SHORT_MOVE_SHARE: f64 = 2.0;

/// Share of the tolerance corner transitions and fits aim at. The rest
/// (0.2%) covers the dropping of zero-length moves (up to 0.1% of the
/// tolerance, see `smooth/chains.rs`), rounding, and the accuracy of the
/// verifier (`VerifyOptions::new` measures to 0.01% of the tolerance), so
/// a full-band result always verifies.
pub const BAND_USE: f64 = 0.998;

/// How far from its corner point a corner transition's apex may lie, in
/// the transition's band (`BAND_USE` of its share of the tolerance): the
/// band's own corner at a right angle, `sqrt(2)`. A transition within
/// `delta` of its two moves has its apex within `delta / sin(theta)` of
/// the corner (`theta` the half corner angle: the point where the curve
/// crosses the bisector is within `delta` of both moves), which grows
/// without bound at a sharp corner: at a turn of 160 degrees 5.8 `delta`,
/// at 179.5 degrees the whole move (the tip of a spike or of a V-carve's
/// stroke, inside the band one-sidedly, would not be cut). Sharper than a
/// right angle the band is narrowed so the apex stays within this reach;
/// up to a right angle nothing changes (`smooth/corner_engine.rs`,
/// `Reach`).
pub const CORNER_REACH_SHARE: f64 = core::f64::consts::SQRT_2;

/// Share of the tolerance `arc-fit`'s blocks use: the rest covers the
/// cleaning of the run and the rounding of written centres.
pub const ARC_FIT_SHARE: f64 = 0.9;

/// Share of the band (`BAND_USE` of the smoothing share) that method
/// `fair` gives the least-squares fits (`bspline-fit`) of runs of lines;
/// the thesis' fairing then moves the fitted curves inside a tube of the
/// rest of the band around them, so the result stays within the band of
/// the original (triangle inequality). A quarter: the fit only needs to follow the lines closely
/// (a CAM-like spline, ripples and all); flattening is the fairing's job,
/// and the wider its tube the more it flattens.
pub const FAIR_FIT_SHARE: f64 = 0.25;

/// Share of the smoothing share that method `fair` gives the chords of the
/// curves the thesis' fairing cannot take (rational, degree 4 and above)
/// in a run, which are then fitted and faired as lines with the rest: as
/// `auto`'s chords of arcs ([`ARC_SAMPLING_SHARE`]), a twentieth, far
/// below the tube the fairing flattens in.
pub const FAIR_SAMPLE_SHARE: f64 = 0.05;

/// Share of `arc-fit`'s block tolerance that the sampled chords of an arc
/// may deviate from it.
pub const ARC_SAMPLE_SHARE: f64 = 0.05;

/// Run end points count as equal within this share of the tolerance: the
/// rounding of the input's own reading (1,000 G91 moves of 0.0005 in sum
/// to 12.700000000000152 mm in f64; the written `X0.5` reads as 12.7:
/// `straight_segments.ngc`), far below any machine's resolution.
pub const ENDPOINT_ROUNDING_SHARE: f64 = 1e-9;

/// Smallest tolerance or share accepted (mm): 1 nm, below any machine's
/// resolution and the f64 rounding of metre-sized parts.
pub const MIN_SHARE_MM: f64 = 1e-6;

/// Largest tolerance accepted (mm).
pub const MAX_TOLERANCE_MM: f64 = 1000.0;

/// How the tolerance is shared (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToleranceBudget {
    /// The user's tolerance.
    pub total: f64,
    /// Writing the curves in the output format, rounding included.
    pub output: f64,
    /// The controller's blending of corners of what is written.
    pub blend: f64,
}

/// A budget that cannot be made.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum BudgetError {
    #[error("the tolerance must be a number of mm from 1e-6 to 1000, got {0}")]
    Tolerance(f64),
    #[error(
        "the output share ({output} mm) must be positive and at most half the tolerance ({half} mm)"
    )]
    Output { output: f64, half: f64 },
    #[error("the blending share must be a number of mm >= 0, got {0}")]
    Blend(f64),
    #[error(
        "the tolerance {total} mm leaves {left:e} mm for smoothing after the output ({output} mm) \
         and blending ({blend} mm) shares; at least 1e-6 mm is needed"
    )]
    NothingLeft {
        total: f64,
        output: f64,
        blend: f64,
        left: f64,
    },
}

impl ToleranceBudget {
    /// The budget for `total` mm: `output` mm for writing the curves
    /// (default [`OUTPUT_SHARE`] of the tolerance) and `blend` mm for the
    /// controller's blending (0 when fairpath writes no blending mode).
    pub fn new(total: f64, output: Option<f64>, blend: f64) -> Result<Self, BudgetError> {
        if !(total.is_finite() && (MIN_SHARE_MM..=MAX_TOLERANCE_MM).contains(&total)) {
            return Err(BudgetError::Tolerance(total));
        }
        let output = output.unwrap_or(OUTPUT_SHARE * total);
        let half = 0.5 * total;
        if !(output.is_finite() && output > 0.0 && output <= half) {
            return Err(BudgetError::Output { output, half });
        }
        if !(blend.is_finite() && blend >= 0.0) {
            return Err(BudgetError::Blend(blend));
        }
        let b = ToleranceBudget {
            total,
            output,
            blend,
        };
        let left = b.smoothing();
        if left.is_nan() || left < MIN_SHARE_MM {
            return Err(BudgetError::NothingLeft {
                total,
                output,
                blend,
                left,
            });
        }
        Ok(b)
    }

    /// What the smoothing method may use: the rest.
    pub fn smoothing(&self) -> f64 {
        self.total - self.output - self.blend
    }

    /// What the written path may deviate from the original, as read back
    /// (the controller's blending comes on top, within `blend`).
    pub fn written(&self) -> f64 {
        self.total - self.blend
    }

    /// What the rounding of written coordinates may take (mm).
    pub fn rounding(&self) -> f64 {
        ROUNDING_SHARE * self.output
    }

    /// What the chords, arcs or spline blocks of the output may deviate
    /// from the curves (mm): the output share less the rounding.
    pub fn render(&self) -> f64 {
        self.output - self.rounding()
    }

    /// The output share G1 lines are rendered within where a blending
    /// share is kept (`blend > 0`): the one G1 output gets, output and
    /// blending split [`BLEND_SHARE_G1`] to blending (where a curve
    /// format keeps [`BLEND_SHARE_CURVES`]), which is at most `output`;
    /// `None` without a blending share (then G1 output and the curve
    /// formats both render within the whole output share). The all-G1
    /// alternative to arcs is rendered so where the arcs hold no arc:
    /// lines cut finer turn less at each vertex the controller blends,
    /// and plan faster.
    pub fn finer_lines_output(&self) -> Option<f64> {
        (self.blend > 0.0)
            .then(|| ((self.output + self.blend) * (1.0 - BLEND_SHARE_G1)).min(self.output))
    }

    /// How far run end points may differ and still count as equal (mm).
    pub fn endpoint_rounding(&self) -> f64 {
        ENDPOINT_ROUNDING_SHARE * self.total
    }

    /// The leaves of the budget, in mm: they add up to at most `total`.
    pub fn shares(&self) -> Shares {
        Shares {
            smoothing: self.smoothing(),
            render: self.render(),
            rounding: self.rounding(),
            blend: self.blend,
        }
    }
}

/// What each consumer may spend (mm), from [`ToleranceBudget::shares`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shares {
    /// The smoothing method.
    pub smoothing: f64,
    /// The chords, arcs or spline blocks of the output.
    pub render: f64,
    /// The rounding of written coordinates.
    pub rounding: f64,
    /// The controller's blending.
    pub blend: f64,
}

impl Shares {
    /// Their sum (at most the tolerance).
    pub fn sum(&self) -> f64 {
        self.smoothing + self.render + self.rounding + self.blend
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shares_add_up_to_the_tolerance() {
        let b = ToleranceBudget::new(0.05, None, 0.0025).unwrap();
        assert!((b.output - 0.005).abs() < 1e-15);
        assert_eq!(b.smoothing() + b.output + b.blend, 0.05);
        assert_eq!(b.written(), 0.05 - 0.0025);
    }

    /// Seeded random budgets: the leaves never add up to more than the
    /// tolerance (f64 rounding of the subtractions aside: 4 ulps).
    #[test]
    fn the_leaves_never_exceed_the_tolerance() {
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..10_000 {
            let total = 10f64.powf(-5.0 + 8.0 * next());
            let output = (next() * 0.5 * total).max(MIN_SHARE_MM);
            let blend = [0.0, BLEND_SHARE_G1 * output, BLEND_SHARE_CURVES * output]
                [(next() * 3.0) as usize % 3];
            let Ok(b) = ToleranceBudget::new(total, Some(output), blend) else {
                continue;
            };
            let s = b.shares();
            assert!(s.smoothing > 0.0 && s.render > 0.0 && s.rounding > 0.0 && s.blend >= 0.0);
            assert!(
                s.sum() <= total * (1.0 + 4.0 * f64::EPSILON),
                "{b:?}: {s:?}"
            );
        }
    }

    #[test]
    fn bad_budgets_are_errors() {
        for t in [0.0, -1.0, f64::NAN, 2000.0, 1e-7] {
            assert!(matches!(
                ToleranceBudget::new(t, None, 0.0),
                Err(BudgetError::Tolerance(_))
            ));
        }
        assert!(matches!(
            ToleranceBudget::new(0.05, Some(0.03), 0.0),
            Err(BudgetError::Output { .. })
        ));
        assert!(matches!(
            ToleranceBudget::new(0.05, None, -1.0),
            Err(BudgetError::Blend(_))
        ));
        assert!(matches!(
            ToleranceBudget::new(0.05, Some(0.025), 0.025),
            Err(BudgetError::NothingLeft { .. })
        ));
    }
}
