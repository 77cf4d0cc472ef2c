//! `auto`'s candidates: how each smooths a run and when it is offered
//! ([`CANDIDATES`], a table), and the constants that shape them (the
//! measurements that chose them are in `docs/tuning.md`).

use crate::geom::tube_fair::PeakPass;
use crate::geom::Curve;
use crate::geom::Vec3;
use crate::geom::{classify_joint, Continuity, JointTolerances, ParamCurve};
use crate::path::{Piece, Run};
use crate::smooth::{
    outer_guide, shallow_corner_sections, BsplineCorner, BsplineFit, BsplineFitOptions,
    CornerReason, Ctm, Fair, FairOptions, LineFit, Lotm, OuterGuide, Reach, RunMemo,
    SectionOptions, SmoothError, SmoothedRun,
};
use crate::verify::{follows_in_order, Verifier, VerifyOptions};
use alloc::vec::Vec;

/// A corner method `auto` offers, with its default options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerMethod {
    /// `bspline-corner` (seed 000).
    BsplineCorner,
    /// `lotm` (seed 001).
    Lotm,
    /// `ctm` (seed 001).
    Ctm,
}

impl CornerMethod {
    /// The method's command-line name.
    pub fn name(self) -> &'static str {
        match self {
            CornerMethod::BsplineCorner => "bspline-corner",
            CornerMethod::Lotm => "lotm",
            CornerMethod::Ctm => "ctm",
        }
    }

    fn smooth_run(self, run: &Run, tol: f64) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run_reaching(run, tol, None)
    }

    /// The method on `run` with every transition's apex held to `reach`
    /// (the band's own when `None`).
    fn smooth_run_reaching(
        self,
        run: &Run,
        tol: f64,
        reach: Option<Reach>,
    ) -> Result<SmoothedRun, SmoothError> {
        match self {
            CornerMethod::BsplineCorner => {
                BsplineCorner::default().smooth_run_reaching(run, tol, reach)
            }
            CornerMethod::Lotm => Lotm::default().smooth_run_reaching(run, tol, reach),
            CornerMethod::Ctm => Ctm::default().smooth_run_reaching(run, tol, reach),
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
pub(super) fn widens_sections(run: &Run, tol: f64, wide: &SectionOptions) -> bool {
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

pub use crate::smooth::{through_corners_sections, THROUGH_MAX_TURN};

/// The sections of the [`FAIR_THROUGH_SHALLOW`] candidate's fits.
pub(super) fn shallow_sections() -> SectionOptions {
    shallow_corner_sections(&FairOptions::default().fit.sections)
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

/// The name of the corner candidate on the run's outer-edge guide
/// ([`Kind::OuterCorner`]).
pub const OUTER_CORNERS: &str = "bspline-corner, outer edges";

/// Shares of the tolerance by which [`Kind::OuterCorner`] moves the
/// moves' lines outward at a corner ([`OuterGuide::shift`]), tried in
/// turn until the result verifies within the tolerance: the whole band
/// (the transitions then cut across twice the band; it verifies where
/// the guide's moves cross from one side to the other between corners
/// that turn opposite ways, so that none runs along the band's edge),
/// nine tenths, then half that. Where none verifies, the candidate is the
/// corner method on the run itself (the same as its own row). Starting
/// at nine tenths gave up 0.5% on a zigzag of 5 mm moves turning 0.5
/// rad and 1.1% at 1 rad; at seven tenths 2.9% and 4.4% (measurements:
/// docs/tuning.md, `OUTER_CORNERS`).
pub const OUTER_SHIFT_SHARES: [f64; 3] = [1.0, 0.9, 0.45];

/// [`OuterGuide::max_turn`] of [`Kind::OuterCorner`]: 2 rad (115
/// degrees). The gain of a deeper cut falls as the turn sharpens (the
/// machine nearly stops at a sharp corner whatever its transition) while
/// the vertex moves `1 / cos(theta / 2)` times the shift: a zigzag of 5
/// mm moves gained 11% at 0.5 rad turns, 5% at 1 rad, 2% at 2 rad (and
/// left the band there at nine tenths of it) and 1% at right angles in a
/// prototype (measurements: docs/tuning.md,
/// `OUTER_CORNERS`).
pub const OUTER_MAX_TURN: f64 = 2.0;

/// Largest run (pieces after sampling) of lines on which `fair` is a
/// candidate: it fits the lines (the plain least-squares fit) and fairs
/// every fit by the thesis' iteration, work that grows with the run; the
/// evidence for the cap (where it won, what it costs, what it gives on
/// long runs) is in `docs/auto-fair.md`. 10,000 takes in the raster of
/// `surface-raster.ngc` (one run of 2,979 lines, where `fair` writes the
/// fastest program and smooths it quickly; measurements: docs/tuning.md,
/// `FAIR_MAX_PIECES`) and leaves out the 138,804 of
/// `surface-raster-large.ngc`. Runs with B-spline pieces get it whatever
/// their length: there it fairs the splines in place, which no other
/// candidate does.
pub const FAIR_MAX_PIECES: usize = 10_000;

/// The name of the `fair` candidate (`auto` also plans its section mixes
/// without it: [`super::auto::Auto`]).
pub const FAIR: &str = "fair";

/// The name of the `fair` candidate that fits through shallow corners
/// ([`LineFit::ThroughShallowCorners`], what method `fair` also tries by
/// default): on runs of at most [`THROUGH_MAX_PIECES`] pieces where it
/// makes some vertex dense that the default sections leave sparse.
/// On LinuxCNC's `default_tolerance_check.ngc` (a zigzag of 0.01 mm and
/// 0.4 um jogs between 12.7 mm moves) method `fair` wrote a faster program
/// than `auto` without this candidate (measurements: docs/tuning.md,
/// `FAIR_THROUGH_SHALLOW`).
pub const FAIR_THROUGH_SHALLOW: &str = "fair, through shallow corners";

/// The name of the `fair` candidate that straightens the run's B-splines
/// after the thesis' iterations ([`crate::smooth::Straighten::On`] in the sliding tube):
/// method `fair` judges its straightening by the planner on such runs
/// ([`crate::smooth::Straighten::Judged`], its default), so `auto` offers both smoothings
/// and stays no slower than it.
pub const FAIR_STRAIGHTENED: &str = "fair, straightened";

/// Whether the candidate named `name` is a `fair` one (they may leave the
/// joint of a cut section not G2: [`super::auto::Auto`]).
pub fn is_fair(name: &str) -> bool {
    name == FAIR || name == FAIR_THROUGH_SHALLOW || name == FAIR_STRAIGHTENED
}

/// Whether the candidate named `name` is a corner method: its row of
/// [`CANDIDATES`] runs `bspline-corner` or `lotm`, on the sampled run or on
/// the curves as written.
pub fn is_corner_method(name: &str) -> bool {
    CANDIDATES
        .iter()
        .any(|r| r.name == name && matches!(r.kind, Kind::Corner(_) | Kind::CornerInPlace(_)))
}

/// The candidates that keep the corners next to arcs as the corner
/// methods do ([`Kind::CornerInPlace`]), last in [`CANDIDATES`].
pub const CURVES_AS_WRITTEN: [&str; 2] = [
    "bspline-corner, curves as written",
    "lotm, curves as written",
];

/// The name of method `fair` on the curves as written with its arcs and
/// the curves it cannot fair kept ([`crate::smooth::FairAlternatives::kept`]),
/// which may keep corners next to them as the [`CURVES_AS_WRITTEN`]
/// candidates do: tried only in `auto`'s fallback where its best G2
/// candidate would be kept as written ([`super::Auto`]).
pub const FAIR_CURVES_AS_WRITTEN: &str = "fair, curves as written";

/// Whether `c` is (or holds a section of) a [`CURVES_AS_WRITTEN`]
/// candidate, or is [`FAIR_CURVES_AS_WRITTEN`].
pub fn keeps_arc_joints(c: &SmoothedRun) -> bool {
    c.chosen
        .iter()
        .any(|n| CURVES_AS_WRITTEN.contains(n) || *n == FAIR_CURVES_AS_WRITTEN)
}

/// How a candidate smooths a run.
#[derive(Clone, Copy, Debug)]
pub(super) enum Candidate {
    Fit(BsplineFitOptions),
    /// Method `fair` with its default options: on the run as it is when
    /// it has B-spline pieces (faired in place, with the whole tolerance)
    /// and that keeps no joint next to an arc or spline that is not G2,
    /// else on the lines the others smooth.
    Fair(FairOptions),
    /// A corner method with its default options.
    Corner(CornerMethod),
    /// A corner method on the run as it is, arcs and curves kept.
    CornerInPlace(CornerMethod),
    /// A corner method on the run's outer-edge guide ([`Kind::OuterCorner`]).
    OuterCorner(CornerMethod),
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
    /// A corner method, on the run with its arcs and curves sampled as
    /// the fits are (every joint it leaves is G2).
    Corner(CornerMethod),
    /// A corner method on the run as it is, as the method itself writes
    /// it: arcs and curves kept, the corners next to them kept
    /// ([`CornerReason::ArcJoint`]). Offered only with
    /// [`super::AutoOptions::curves_as_written`], which says why.
    CornerInPlace(CornerMethod),
    /// A corner method on the run with its sparse corners moved outward
    /// ([`crate::smooth::outer_guide`]: the moves' lines by a share of the
    /// tolerance, [`OUTER_SHIFT_SHARES`]) and the tolerance raised by the
    /// same, so that each transition starts on the band's outer edge and
    /// cuts to its inner edge at the corner; verified against the run,
    /// and the corner method on the run itself where no share verifies.
    OuterCorner(CornerMethod),
    /// Method `fair` (seed 003) with its default options, fitting runs of
    /// lines as this says.
    Fair(LineFit),
    /// Method `fair` with its straightening forced on in the sliding tube
    /// ([`FairOptions::straightened`]).
    FairStraightened,
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
    /// When the run has an arc or curve (else it is the corner method on
    /// the sampled run again).
    OnCurves,
    /// On runs with a B-spline piece, and on runs of at most
    /// [`FAIR_MAX_PIECES`] pieces (after sampling).
    OnSplinesOrShortRuns,
    /// On runs with a B-spline piece.
    OnSplines,
    /// On runs of at most [`THROUGH_MAX_PIECES`] pieces (after sampling)
    /// where [`shallow_corner_sections`] makes some vertex dense that the
    /// default sections do not (else it is the `fair` candidate again).
    WhenShallowCornersWiden,
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
        name: FAIR,
        kind: Kind::Fair(LineFit::Sections),
        offered: Offered::OnSplinesOrShortRuns,
    },
    CandidateRow {
        name: FAIR_THROUGH_SHALLOW,
        kind: Kind::Fair(LineFit::ThroughShallowCorners),
        offered: Offered::WhenShallowCornersWiden,
    },
    CandidateRow {
        name: FAIR_STRAIGHTENED,
        kind: Kind::FairStraightened,
        offered: Offered::OnSplines,
    },
    CandidateRow {
        name: "as is",
        kind: Kind::AsIs,
        offered: Offered::AlreadyG2,
    },
    CandidateRow {
        name: CURVES_AS_WRITTEN[0],
        kind: Kind::CornerInPlace(CornerMethod::BsplineCorner),
        offered: Offered::OnCurves,
    },
    CandidateRow {
        name: CURVES_AS_WRITTEN[1],
        kind: Kind::CornerInPlace(CornerMethod::Lotm),
        offered: Offered::OnCurves,
    },
    CandidateRow {
        name: "ctm",
        kind: Kind::Corner(CornerMethod::Ctm),
        offered: Offered::Always,
    },
    CandidateRow {
        name: OUTER_CORNERS,
        kind: Kind::OuterCorner(CornerMethod::BsplineCorner),
        offered: Offered::OnShortRuns,
    },
];

impl SectionRule {
    pub(super) fn options(self) -> SectionOptions {
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
    pub(super) fn candidate(self) -> Candidate {
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
            Kind::CornerInPlace(m) => Candidate::CornerInPlace(m),
            Kind::OuterCorner(m) => Candidate::OuterCorner(m),
            // With `bspline-fit`'s sections only: the fits through the
            // corners are candidates of their own here, and faired again
            // they made `auto` far slower on `makerblock_tinycnc.gcode`
            // for the same written program (measurements: docs/tuning.md,
            // `Kind::Fair`).
            Kind::Fair(lines) => Candidate::Fair(FairOptions {
                lines,
                ..FairOptions::default()
            }),
            Kind::FairStraightened => Candidate::Fair(FairOptions::default().straightened()),
            Kind::AsIs => Candidate::AsIs,
        }
    }
}

/// Whether every joint of `run` is G2 (a run of one piece has none) at the
/// joint tolerances of `tolerance`.
pub(super) fn is_g2(run: &Run, tolerance: f64) -> bool {
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
    /// `original`: the run before its arcs were sampled into `input`,
    /// whose tolerance is `tolerance` (`input`'s is `tol`).
    /// `memo`: the fits and tube fairings made for this run so far (by
    /// any candidate).
    pub(super) fn smooth(
        &self,
        (original, tolerance): (&Run, f64),
        input: &Run,
        tol: f64,
        cut_ends: (bool, bool),
        memo: &RunMemo,
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
            .smooth_run_with(input, tol, memo),
            Candidate::Corner(m) => m.smooth_run(input, tol),
            Candidate::CornerInPlace(m) => m.smooth_run(original, tolerance),
            Candidate::OuterCorner(m) => outer_corners(*m, input, tol),
            Candidate::Fair(o) => {
                let fit = BsplineFitOptions {
                    line_at_start: cut_ends.0,
                    line_at_end: cut_ends.1,
                    ..o.fit
                };
                let fair = Fair {
                    options: FairOptions { fit, ..*o },
                };
                // In place, unless that keeps a joint next to an arc or a
                // spline that is not G2 (only the corner methods on the
                // curves as written leave one): then on the sampled run,
                // as the others.
                if has_splines(original) {
                    let out = fair.smooth_run_with(original, tolerance, memo)?;
                    if out
                        .kept_corners
                        .iter()
                        .all(|k| k.reason != CornerReason::ArcJoint)
                    {
                        return Ok(out);
                    }
                }
                // On lines (a run of them, or a run sampled) without the
                // peak pass: it cost `auto` CPU time on the dense
                // reference programs and changed no written time there
                // (`docs/auto-fair.md`; measurements: docs/tuning.md,
                // `Candidate::Fair`); the jerk-faired fits already weigh
                // what it lowers. Those near the best are made again with
                // it (`Auto::fair_with_peak_pass`).
                let lines = Fair {
                    options: FairOptions {
                        peak_pass: PeakPass::Off,
                        ..fair.options
                    },
                };
                lines.smooth_run_with(input, tol, memo)
            }
        }
    }
}

/// [`Candidate::OuterCorner`]: `m` on the outer-edge guide of `input`
/// with the tolerance `tol` raised by the guide's shift, at the first of
/// [`OUTER_SHIFT_SHARES`] whose result verifies within `tol` of `input`
/// (its deviation bound); else `m` on `input` itself. Where a result
/// leaves the band by a little (a transition is not a circle, so its
/// farthest point from the original need not lie on the bisector where
/// the argument places it), the raised tolerance is lowered by what it
/// left by, [`OUTER_TRIES`] times at most.
fn outer_corners(m: CornerMethod, input: &Run, tol: f64) -> Result<SmoothedRun, SmoothError> {
    let verifier = Verifier::new(&input.pieces, &VerifyOptions::new(tol));
    // Every corner of the input passed within the reach, in order: what
    // the reach in the smoothing aims at (`Reach`), checked.
    let corners = corner_gates(input, tol);
    for share in OUTER_SHIFT_SHARES {
        let g = OuterGuide {
            shift: share * tol,
            max_turn: OUTER_MAX_TURN,
            depth: tol + share * tol,
            straight: OUTER_STRAIGHT_SHARE * tol,
        };
        let Some(guide) = outer_guide(input, &g) else {
            break;
        };
        // Every apex within the reach of the band `tol` has of its
        // original corner, moved or not.
        let mut reach = Reach {
            radius: crate::budget::CORNER_REACH_SHARE * crate::budget::BAND_USE * tol,
            shift: g.shift,
            moved_from: 0.5 * (core::f64::consts::PI - g.max_turn),
        };
        let mut raised = tol + g.shift;
        for _ in 0..OUTER_TRIES {
            let out = m.smooth_run_reaching(&guide, raised, Some(reach))?;
            let over = verifier.deviation(&out.pieces).bound - tol;
            if over <= 0.0 {
                if reaches_corners(&out.pieces, &corners, tol) {
                    return Ok(out);
                }
                // A corner next to a move the guide tilted (one end moved,
                // the other not) is passed a little beyond the reach,
                // which places the original corner as if both moves were
                // moved: narrowed, the apex comes back inside it.
                reach.radius *= OUTER_REACH_RETRY;
                continue;
            }
            // Lowered by twice the excess (the apex moves with the
            // tolerance one to one; twice leaves room for the bound).
            raised -= 2.0 * over;
            if raised <= tol {
                break;
            }
        }
    }
    m.smooth_run(input, tol)
}

/// How closely, as a share of the tolerance, the check that
/// [`Kind::OuterCorner`]'s result passes every corner within the reach
/// ([`reaches_corners`]) flattens its curves: a thousandth, under the 0.2% the corner transitions leave
/// of the reach ([`crate::budget::BAND_USE`]).
const REACH_ACCURACY: f64 = 1e-3;

/// A gate at every inner vertex of `run` (each piece's end but the
/// last's), of the corner reach of the tolerance `tol`
/// ([`crate::budget::CORNER_REACH_SHARE`]).
fn corner_gates(run: &Run, tol: f64) -> Vec<(Vec3, f64)> {
    let radius = crate::budget::CORNER_REACH_SHARE * tol;
    run.pieces[..run.pieces.len().saturating_sub(1)]
        .iter()
        .map(|p| (p.end(), radius))
        .collect()
}

/// Whether `path` passes every gate of [`corner_gates`] (of `tol`) in
/// order, its curves flattened within [`REACH_ACCURACY`] of `tol`: the
/// smoothing turns back short of no corner.
fn reaches_corners(path: &[Piece], gates: &[(Vec3, f64)], tol: f64) -> bool {
    follows_in_order(path, gates, REACH_ACCURACY * tol)
}

/// [`OuterGuide::straight`] of [`Kind::OuterCorner`], as a share of the
/// tolerance: moves that go straight on within 5% of it are one move for
/// the guide (an engraving's straight edges, written as moves of a few
/// tenths of a millimetre with 3 decimals, wobble by half a micrometre;
/// as separate moves they leave each corner the room of one of them).
pub const OUTER_STRAIGHT_SHARE: f64 = 0.05;

/// The reach [`Kind::OuterCorner`] tries again with where its result
/// passes a corner beyond it, as a share of the one before: 5% narrower.
/// The guide tilts a move whose one end it moves and the other not (next to
/// a run's ends and to corners it keeps), and the original corner at such a
/// move's moved end lies off where the reach places it; a right angle's
/// apex sits at the reach itself (`BAND_USE` of it, 0.2% inside the check),
/// so any tilt shows there (LinuxCNC's `simple_blend.ngc`).
pub const OUTER_REACH_RETRY: f64 = 0.95;

/// Most smoothings [`Kind::OuterCorner`] makes at each share of
/// [`OUTER_SHIFT_SHARES`]: the first, and two with the raised tolerance
/// lowered by what the one before left the band by.
pub const OUTER_TRIES: usize = 3;

/// Whether `run` has a B-spline (NURBS) piece.
pub(super) fn has_splines(run: &Run) -> bool {
    run.pieces
        .iter()
        .any(|p| matches!(p.curve, Curve::Nurbs(_)))
}

/// The run the candidates work on: `run` itself, or `run` with its arcs
/// and curves sampled; and the tolerance left to them.
pub(super) enum Input<'a> {
    Lines(&'a Run),
    Sampled(Run),
}

impl Input<'_> {
    pub(super) fn run(&self) -> &Run {
        match self {
            Input::Lines(r) => r,
            Input::Sampled(r) => r,
        }
    }
}

/// The run the candidates smooth, its tolerance, and the named candidates.
pub(super) type CandidateList<'a> = (Input<'a>, f64, Vec<(&'static str, Candidate)>);
