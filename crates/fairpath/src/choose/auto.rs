//! Method `auto` (the default): for each run, the smoothing that the feed
//! planner runs fastest, always within the tolerance and G2.
//!
//! Candidates for a run:
//!
//! * **fit**: `bspline-fit` (dense sections fitted, sparse corners blended;
//!   seeds 002 and 000) on the run with its arcs and curves sampled as
//!   chords within `arc_share * tolerance` of them, with the rest of the
//!   tolerance. Sampled arcs are dense sections like any CAM sampling, so
//!   they are fitted together with their neighbours and the joints between
//!   lines and arcs, and between arcs, become G2 as well (a tangent joint
//!   of a line and an arc, or of two arcs, still jumps in curvature, which
//!   slows the machine as much as a corner of small angle). The chords lie
//!   within `arc_share * tolerance` of the arc and the fit within the rest
//!   of the chords, so the fit is within the tolerance of the arc.
//! * **fit, wide wiggles**: the same with [`WIDE_WIGGLE_PER_TOL`], when it
//!   makes some vertex dense that the default rule does not (a zigzag whose
//!   midline lies within the tolerance).
//! * **fit, through corners**, on runs of at most [`THROUGH_MAX_PIECES`]
//!   pieces (after sampling): every vertex up to [`THROUGH_MAX_TURN`] is
//!   dense, so the fit runs through the corners (next to arcs, or between
//!   lines) instead of meeting zero-curvature corner transitions there.
//! * **fit, jerk-faired**, on the same runs: `bspline-fit` with the jerk
//!   term [`JERK_FAIRNESS`], which spreads the curvature ramps of sampled
//!   arcs between corners over more length; and through corners with a
//!   lighter jerk term, [`THROUGH_JERK_FAIRNESS`]. These are offered on
//!   runs of lines too (the survey found each chosen somewhere).
//! * the corner methods `bspline-corner` and `lotm` (not `ctm`: with its
//!   default coefficient its transitions are `bspline-corner`'s uniform
//!   cubic B-splines, at more smoothing and planning time): on the run as it is when it has only lines; on the same
//!   sampled run (with the same share of the tolerance) when it has arcs,
//!   so that they too leave no joint next to an arc that is not G2.
//! * **as is**: the run untouched, when every joint in it is already G2
//!   (one arc between two `S` words of a plasma program, say): sampled and
//!   refitted, an arc's curvature ripples and can plan slower. Last in the
//!   list, so it wins only when strictly faster.
//!
//! The candidates are a table, [`CANDIDATES`]: each row says how the
//! candidate smooths and when it is offered. The measurements that chose
//! the constants are in `docs/tuning.md`, not here.
//!
//! Each candidate is ranked by the [`Objective`] the caller injects
//! ([`Auto::new`]): the CLI's is the planned time on the user's machine
//! ([`PlannedTime`], programmed feeds overridden to the machine's maximum
//! so that the choice depends on the geometry, not on a feed the program
//! may set low). The cheapest is kept; a tie goes to the earlier candidate.
//! A candidate the objective cannot cost is kept only when none can.
//!
//! **Sections.** A run of up to [`SECTION_MAX_PIECES`] pieces is also cut
//! at the middle of every line longer than a length
//! ([`split_at_long_lines`]; each of [`AutoOptions::section_lines`], 5, 3
//! and 1 mm by default, gives one mix) and each section gets its own fastest
//! candidate (planned from rest to rest). At a cut every candidate must
//! meet the line G2 (tangent along it, zero curvature): fits keep the cut
//! halves as lines ([`BsplineFitOptions::line_at_start`]), and a candidate
//! that does not is not eligible there. A raster whose passes want fits
//! and whose step-overs want corner transitions, or a program of lines
//! and of arcs between corners, then gets the best of both. The mix is
//! planned as one run and kept only when it is faster than the best
//! candidate for the whole run (and than the mixes of the other lengths),
//! so `auto` stays no slower than any candidate.

use super::objective::{Objective, PlannedTime};
use super::sections::{split_at_long_lines, SectionCache};
use crate::geom::{
    classify_joint, flatten_params, Continuity, Curve, JointTolerances, Line, ParamCurve,
};
use crate::path::{Piece, Run};
use crate::smooth::{
    check_tolerance, require, BsplineCorner, BsplineFit, BsplineFitOptions, Lotm, OptionError,
    SectionOptions, SmoothError, SmoothedRun, Smoother,
};
use alloc::sync::Arc;
use alloc::vec::Vec;

/// A corner method `auto` offers, with its default options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerMethod {
    /// `bspline-corner` (seed 000).
    BsplineCorner,
    /// `lotm` (seed 001).
    Lotm,
}

impl CornerMethod {
    /// The method's command-line name.
    pub fn name(self) -> &'static str {
        match self {
            CornerMethod::BsplineCorner => "bspline-corner",
            CornerMethod::Lotm => "lotm",
        }
    }

    fn smooth_run(self, run: &Run, tol: f64) -> Result<SmoothedRun, SmoothError> {
        match self {
            CornerMethod::BsplineCorner => BsplineCorner::default().smooth_run(run, tol),
            CornerMethod::Lotm => Lotm::default().smooth_run(run, tol),
        }
    }
}

/// Wiggle factor ([`SectionOptions::wiggle_per_tol`]) of the second fit
/// candidate: a vertex up to twice the tolerance above the chord of its
/// neighbours is dense, so a zigzag whose midline lies within the
/// tolerance of every vertex may be fitted by that midline (LinuxCNC's
/// `zigzag_0.002_0.001.ngc`: 0.0254 mm each side of the line at 0.05 mm).
/// Not the default of `bspline-fit`: on paths whose sharp vertices are real
/// (raster step-overs, V-carving) a fit across them is slower than corner
/// transitions, so `auto` plans both and keeps the faster.
pub const WIDE_WIGGLE_PER_TOL: f64 = 2.0;

/// Whether `wide` makes some vertex of the lines of `run` dense that the
/// default rule does not (the wide candidate would differ).
fn widens_sections(run: &Run, tol: f64, wide: &SectionOptions) -> bool {
    let Some(first) = run.pieces.first() else {
        return false;
    };
    let mut pts = Vec::with_capacity(run.pieces.len() + 1);
    pts.push(first.curve.start());
    pts.extend(run.pieces.iter().map(|p| p.curve.end()));
    let narrow = SectionOptions::default();
    (1..pts.len().saturating_sub(1))
        .any(|i| wide.is_dense(&pts, i, tol) && !narrow.is_dense(&pts, i, tol))
}

/// Sharpest turn (rad, about 143 degrees) that the through-corners
/// candidate fits across; sharper vertices (reversals) stay corners.
///
/// A corner transition (seed 000) ends with zero curvature on its lines.
/// Next to a sampled arc, the fit of the arc must then ramp its curvature
/// from zero to `1/R` after the corner and back before the next one: on
/// short arcs between corners (LinuxCNC's `line-arc-burnin.ngc`,
/// `linearc.ngc`) the ramps slowed `auto` below the program as it is. The
/// through-corners candidate makes every vertex of the sampled run up to
/// this turn dense, whatever its segment lengths, so one fit runs through
/// the corner (knots are added where it misses the band) and each arc's
/// curvature runs into the next piece's. Where such a fit fails, the
/// section is split around its sharpest vertex as usual.
pub const THROUGH_MAX_TURN: f64 = 2.5;

/// The run detection of the through-corners candidates: every vertex up
/// to [`THROUGH_MAX_TURN`] is dense, whatever its segment lengths.
pub fn through_corners_sections() -> SectionOptions {
    SectionOptions {
        max_segment: 1e6,
        max_turn: THROUGH_MAX_TURN,
        chord_error_per_tol: 1e6,
        ..SectionOptions::default()
    }
}

/// Largest run (pieces after sampling) for which the through-corners and
/// jerk-faired candidates are tried: fits across many sharp corners fail
/// and are split again and again, which costs more smoothing time on long
/// runs than it saves machining time.
pub const THROUGH_MAX_PIECES: usize = 2000;

/// [`BsplineFitOptions::jerk_fairness`] of the jerk-faired candidate (the
/// one that keeps the default run detection), tried on the same runs as
/// the through-corners candidates (up to [`THROUGH_MAX_PIECES`] pieces;
/// those use [`THROUGH_JERK_FAIRNESS`]). It spreads the curvature ramps of
/// sampled arcs between sharp corners over more length; as the default of
/// every fit it costs time elsewhere, so `auto` plans it beside the others.
pub const JERK_FAIRNESS: f64 = 3e4;

/// [`BsplineFitOptions::jerk_fairness`] of the jerk-faired through-corners
/// candidate. The jerk term's weight against the bending term's is
/// `mu / lambda = jerk_fairness * s^2` (mean segment `s`); it balances the
/// two where the curvature `kappa` changes over a length `sqrt(mu /
/// lambda)`. At a corner the machine brakes for, `kappa^2 v^3 <= J` and
/// `|dkappa/ds| v^3 <= J` bind together when the curvature ramps over
/// about the corner's radius `1 / kappa`, a few segments at most, so a
/// jerk fairness of order 1 suits fits through corners (the fits are also
/// relaxed inside the band, [`BsplineFitOptions::relax`], so a larger one
/// spreads the curvature of the corners too far).
pub const THROUGH_JERK_FAIRNESS: f64 = 3.0;

/// Share of the tolerance that the chords of sampled arcs may take (see
/// [`crate::budget`]).
pub use crate::budget::ARC_SAMPLING_SHARE as ARC_SHARE;

/// Default [`AutoOptions::section_lines`] (mm): a run is cut at the lines
/// longer than 5 mm, then at those longer than 3 mm, then 1 mm, and the
/// fastest of the three mixes (or the whole run) is kept. Long lines cut
/// sections whose best candidates differ (a raster's passes and its
/// step-overs); shorter cuts give short features their own choices. The
/// sections the lengths share are smoothed once.
pub const SECTION_LINES: [f64; 3] = [5.0, 3.0, 1.0];

/// Largest run (pieces) that is also smoothed section by section: the
/// sections are smoothed and planned besides the whole run (the mix is kept
/// only when the whole run plans faster with it), which doubles the work.
pub const SECTION_MAX_PIECES: usize = 20_000;

/// Options of [`Auto`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct AutoOptions {
    /// Share of the tolerance for the chords of sampled arcs, in `(0, 0.5]`.
    pub arc_share: f64,
    /// For each of these lengths (mm), the lines longer than it cut the
    /// run into sections, each smoothed by its own fastest candidate; the
    /// fastest of these mixes and the best candidate for the whole run is
    /// kept ([`SECTION_LINES`]; an infinite length cuts nothing, all
    /// infinite: one choice per run).
    pub section_lines: [f64; 3],
}

impl AutoOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        let s = self.arc_share;
        require(
            s > 0.0 && s <= 0.5,
            "auto",
            "arc_share",
            s,
            "must be in (0, 0.5]",
        )?;
        let l = self.section_lines;
        require(
            l.iter().all(|&x| x > 0.0),
            "auto",
            "section_lines",
            l,
            "must be positive lengths (mm) or infinite",
        )
    }
}

impl Default for AutoOptions {
    fn default() -> Self {
        AutoOptions {
            arc_share: ARC_SHARE,
            section_lines: SECTION_LINES,
        }
    }
}

/// The `auto` method (see the module documentation).
#[derive(Clone, Debug)]
pub struct Auto {
    pub options: AutoOptions,
    /// What the candidates are ranked by.
    pub objective: Arc<dyn Objective>,
}

impl Auto {
    /// `auto` with `options`, ranking its candidates by `objective`.
    pub fn new(options: AutoOptions, objective: Arc<dyn Objective>) -> Self {
        Auto { options, objective }
    }
}

impl Default for Auto {
    /// Default options, ranked by [`PlannedTime::default`] (the reference
    /// machine of seed 003: pass your own with [`Auto::new`]).
    fn default() -> Self {
        Auto::new(AutoOptions::default(), Arc::new(PlannedTime::default()))
    }
}

/// `run` with every piece that is not a line replaced by chords within
/// `chord` mm of it (exact end points; each chord keeps the piece's input
/// lines and feed).
pub fn sample_curves(run: &Run, chord: f64) -> Run {
    let mut out = Vec::with_capacity(run.pieces.len());
    for p in &run.pieces {
        if matches!(p.curve, Curve::Line(_)) {
            out.push(p.clone());
            continue;
        }
        let c = &p.curve;
        let ts = flatten_params(c, chord);
        let n = ts.len();
        let mut prev = c.start();
        for (i, &t) in ts.iter().enumerate().skip(1) {
            let q = if i + 1 == n { c.end() } else { c.eval(t) };
            out.push(Piece {
                curve: Curve::Line(Line::new(prev, q)),
                rapid: p.rapid,
                source_lines: p.source_lines,
                feed: p.feed,
            });
            prev = q;
        }
    }
    Run::new(out)
}

/// How a candidate smooths a run.
#[derive(Clone, Copy, Debug)]
enum Candidate {
    Fit(BsplineFitOptions),
    /// A corner method with its default options.
    Corner(CornerMethod),
    /// The run as it is ([`Offered::AlreadyG2`]).
    AsIs,
}

/// Which dense-section rule a fit candidate uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionRule {
    /// `bspline-fit`'s default.
    Default,
    /// [`WIDE_WIGGLE_PER_TOL`]: a zigzag within the tolerance of its midline
    /// is dense.
    WideWiggles,
    /// [`through_corners_sections`]: every vertex up to [`THROUGH_MAX_TURN`].
    ThroughCorners,
}

/// What a candidate is, in [`CANDIDATES`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// `bspline-fit` with a section rule and a jerk fairness.
    Fit {
        sections: SectionRule,
        jerk_fairness: f64,
    },
    /// A corner method.
    Corner(CornerMethod),
    /// The run untouched.
    AsIs,
}

/// When a candidate is offered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Offered {
    /// On every run.
    Always,
    /// When its section rule makes some vertex dense that the default does
    /// not (else it is the default fit again).
    WhenItWidens,
    /// On runs of at most [`THROUGH_MAX_PIECES`] pieces (after sampling).
    OnShortRuns,
    /// When every joint of the run is already G2.
    AlreadyG2,
}

/// One row of `auto`'s candidate table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CandidateRow {
    /// The name reported in the summary (`auto_chose`).
    pub name: &'static str,
    pub kind: Kind,
    pub offered: Offered,
}

/// `auto`'s candidates, in order (a tie goes to the earlier). See the
/// module documentation for why each is there.
pub const CANDIDATES: &[CandidateRow] = &[
    CandidateRow {
        name: "bspline-fit",
        kind: Kind::Fit {
            sections: SectionRule::Default,
            jerk_fairness: 0.0,
        },
        offered: Offered::Always,
    },
    CandidateRow {
        name: "bspline-corner",
        kind: Kind::Corner(CornerMethod::BsplineCorner),
        offered: Offered::Always,
    },
    CandidateRow {
        name: "bspline-fit, wide wiggles",
        kind: Kind::Fit {
            sections: SectionRule::WideWiggles,
            jerk_fairness: 0.0,
        },
        offered: Offered::WhenItWidens,
    },
    CandidateRow {
        name: "bspline-fit, through corners",
        kind: Kind::Fit {
            sections: SectionRule::ThroughCorners,
            jerk_fairness: 0.0,
        },
        offered: Offered::OnShortRuns,
    },
    CandidateRow {
        name: "bspline-fit, through corners, jerk-faired",
        kind: Kind::Fit {
            sections: SectionRule::ThroughCorners,
            jerk_fairness: THROUGH_JERK_FAIRNESS,
        },
        offered: Offered::OnShortRuns,
    },
    CandidateRow {
        name: "bspline-fit, jerk-faired",
        kind: Kind::Fit {
            sections: SectionRule::Default,
            jerk_fairness: JERK_FAIRNESS,
        },
        offered: Offered::OnShortRuns,
    },
    CandidateRow {
        name: "lotm",
        kind: Kind::Corner(CornerMethod::Lotm),
        offered: Offered::Always,
    },
    CandidateRow {
        name: "as is",
        kind: Kind::AsIs,
        offered: Offered::AlreadyG2,
    },
];

impl SectionRule {
    fn options(self) -> SectionOptions {
        match self {
            SectionRule::Default => SectionOptions::default(),
            SectionRule::WideWiggles => SectionOptions {
                wiggle_per_tol: WIDE_WIGGLE_PER_TOL,
                ..SectionOptions::default()
            },
            SectionRule::ThroughCorners => through_corners_sections(),
        }
    }
}

impl Kind {
    fn candidate(self) -> Candidate {
        match self {
            Kind::Fit {
                sections,
                jerk_fairness,
            } => Candidate::Fit(BsplineFitOptions {
                sections: sections.options(),
                jerk_fairness,
                ..BsplineFitOptions::default()
            }),
            Kind::Corner(m) => Candidate::Corner(m),
            Kind::AsIs => Candidate::AsIs,
        }
    }
}

/// Whether every joint of `run` is G2 (a run of one piece has none) at the
/// joint tolerances of `tolerance`.
fn is_g2(run: &Run, tolerance: f64) -> bool {
    let jt = JointTolerances::from_tolerance(tolerance);
    !run.pieces.is_empty()
        && run
            .pieces
            .windows(2)
            .all(|w| classify_joint(&w[0].curve, &w[1].curve, &jt) == Continuity::G2)
}

impl Candidate {
    /// `cut_ends`: whether the run starts (ends) in the middle of a line
    /// where `auto` cut it into sections, so fits must keep that line.
    /// `original`: the run before its arcs were sampled into `input`.
    fn smooth(
        &self,
        original: &Run,
        input: &Run,
        tol: f64,
        cut_ends: (bool, bool),
    ) -> Result<SmoothedRun, SmoothError> {
        match self {
            Candidate::AsIs => Ok(SmoothedRun {
                pieces: original.pieces.clone(),
                ..SmoothedRun::default()
            }),
            Candidate::Fit(o) => BsplineFit {
                options: BsplineFitOptions {
                    line_at_start: cut_ends.0,
                    line_at_end: cut_ends.1,
                    ..*o
                },
            }
            .smooth_run(input, tol),
            Candidate::Corner(m) => m.smooth_run(input, tol),
        }
    }
}

/// The run the candidates work on: `run` itself, or `run` with its arcs
/// and curves sampled; and the tolerance left to them.
enum Input<'a> {
    Lines(&'a Run),
    Sampled(Run),
}

impl Input<'_> {
    fn run(&self) -> &Run {
        match self {
            Input::Lines(r) => r,
            Input::Sampled(r) => r,
        }
    }
}

/// The run the candidates smooth, its tolerance, and the named candidates.
type CandidateList<'a> = (Input<'a>, f64, Vec<(&'static str, Candidate)>);

impl Auto {
    /// The candidates for `run` with the run they smooth and its tolerance
    /// (see the module documentation).
    fn plan_candidates<'a>(
        &self,
        run: &'a Run,
        tolerance: f64,
    ) -> Result<CandidateList<'a>, SmoothError> {
        self.options.validate()?;
        let share = self.options.arc_share;
        // The candidates of a run with arcs get the rest of the tolerance.
        check_tolerance(tolerance * (1.0 - share))?;
        let has_curves = run
            .pieces
            .iter()
            .any(|p| !matches!(p.curve, Curve::Line(_)));
        // With arcs or curves, every candidate works on the run sampled as
        // chords, with what the chords leave of the tolerance.
        let (input, tol) = if has_curves {
            let chord = share * tolerance;
            (Input::Sampled(sample_curves(run, chord)), tolerance - chord)
        } else {
            (Input::Lines(run), tolerance)
        };
        let wide = SectionRule::WideWiggles.options();
        let mut out = Vec::new();
        for row in CANDIDATES {
            let offered = match row.offered {
                Offered::Always => true,
                Offered::WhenItWidens => widens_sections(input.run(), tol, &wide),
                Offered::OnShortRuns => input.run().pieces.len() <= THROUGH_MAX_PIECES,
                Offered::AlreadyG2 => is_g2(run, tolerance),
            };
            if offered {
                out.push((row.name, row.kind.candidate()));
            }
        }
        Ok((input, tol, out))
    }

    /// The candidates for `run` (see the module documentation), each with
    /// its name, smoothed one after the other.
    pub fn candidates(
        &self,
        run: &Run,
        tolerance: f64,
    ) -> Result<Vec<(&'static str, SmoothedRun)>, SmoothError> {
        let (input, tol, list) = self.plan_candidates(run, tolerance)?;
        list.iter()
            .map(|(name, c)| Ok((*name, c.smooth(run, input.run(), tol, (false, false))?)))
            .collect()
    }
}

/// `f(i)` for `i in 0..n`, in order: on scoped threads with `std` (the
/// candidates are independent, and a workstation has the cores), one
/// after the other without.
fn map_candidates<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    #[cfg(feature = "std")]
    {
        if n > 1 {
            let f = &f;
            return std::thread::scope(|s| {
                let handles: Vec<_> = (0..n).map(|i| s.spawn(move || f(i))).collect();
                handles
                    .into_iter()
                    .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                    .collect()
            });
        }
    }
    (0..n).map(f).collect()
}

/// A candidate smoothed and its cost (`None`: the objective could not
/// cost it).
pub(super) type Planned = (Option<f64>, SmoothedRun);

impl Auto {
    /// Every candidate for `run`, smoothed and planned.
    pub(super) fn planned_candidates(
        &self,
        run: &Run,
        tolerance: f64,
        cut_ends: (bool, bool),
    ) -> Result<Vec<Planned>, SmoothError> {
        let (input, tol, list) = self.plan_candidates(run, tolerance)?;
        map_candidates(list.len(), |i| {
            let mut cand = list[i].1.smooth(run, input.run(), tol, cut_ends)?;
            cand.chosen = alloc::vec![list[i].0];
            let time = self.objective.cost(&cand.pieces);
            Ok((time, cand))
        })
        .into_iter()
        .collect()
    }

    /// The fastest of `cands` that `eligible` accepts, with its planned
    /// time (a tie goes to the earlier); failing any that planned, the
    /// first accepted that the planner rejected (time `None`).
    pub(super) fn fastest(
        cands: Vec<Planned>,
        eligible: impl Fn(&SmoothedRun) -> bool,
    ) -> Option<Planned> {
        let mut best: Option<(f64, SmoothedRun)> = None;
        let mut fallback = None;
        for (time, cand) in cands {
            if !eligible(&cand) {
                continue;
            }
            match time {
                Some(t) if best.as_ref().is_none_or(|(b, _)| t < *b) => best = Some((t, cand)),
                Some(_) => {}
                None => {
                    if fallback.is_none() {
                        fallback = Some(cand);
                    }
                }
            }
        }
        best.map(|(t, c)| (Some(t), c))
            .or(fallback.map(|c| (None, c)))
    }
}

impl Smoother for Auto {
    fn name(&self) -> &'static str {
        "auto"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        check_tolerance(tolerance)?;
        self.options.validate()?;
        let lines = self.options.section_lines;
        let cands = self.planned_candidates(run, tolerance, (false, false))?;
        let (mut time, mut best) =
            Self::fastest(cands, |_| true).ok_or(SmoothError::NoCandidate)?;
        if run.pieces.len() > SECTION_MAX_PIECES {
            return Ok(best);
        }
        let mut cache = SectionCache::default();
        let mut tried: Vec<usize> = Vec::new();
        for line in lines {
            let sections = split_at_long_lines(run, line);
            // A length that cuts where a longer one did gives the same mix.
            if sections.len() < 2 || tried.contains(&sections.len()) {
                continue;
            }
            tried.push(sections.len());
            let Some(mixed) = self.smooth_sections(&sections, tolerance, &mut cache)? else {
                continue;
            };
            let t = self.objective.cost(&mixed.pieces);
            if let (Some(t), Some(tw)) = (t, time) {
                if t < tw {
                    (time, best) = (Some(t), mixed);
                }
            }
        }
        Ok(best)
    }
}
