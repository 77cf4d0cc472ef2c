//! Tests of [`super::Auto`].

use super::super::candidate_set::CandidateSet;
use super::super::candidates::CURVES_AS_WRITTEN;
use super::super::same_pieces::same_pieces;
use super::*;
use crate::geom::{Line, Vec3};
use crate::path::Piece;
use core::sync::atomic::{AtomicUsize, Ordering};

/// [`PlannedTime`], counting its calls.
#[derive(Debug, Default)]
struct Counted {
    calls: AtomicUsize,
    time: PlannedTime,
}

impl Objective for Counted {
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.time.cost(pieces)
    }
}

/// A zigzag of long lines: no dense section, so every fit candidate
/// smooths it as `bspline-corner` does.
fn zigzag() -> Run {
    let p = |i: usize| Vec3::new(10.0 * i as f64, if i % 2 == 0 { 0.0 } else { 8.0 }, 0.0);
    let pieces = (1..8)
        .map(|i| Piece {
            curve: Curve::Line(Line::new(p(i - 1), p(i))),
            rapid: false,
            source_lines: (i, i),
            feed: Some(3000.0),
        })
        .collect();
    Run::new(pieces)
}

/// Every candidate gets the cost of its own pieces, while the
/// objective runs once per distinct result.
#[test]
fn candidates_with_the_same_pieces_share_one_cost() {
    let counted = Arc::new(Counted::default());
    let auto = Auto::new(AutoOptions::default(), counted.clone());
    let run = zigzag();
    let memo = RunMemo::default();
    let mut ranking = auto
        .ranked_candidates(&run, 0.05, (false, false), &memo)
        .map(|(ranking, _)| ranking)
        .unwrap();
    ranking.fastest(|_| true).unwrap();
    let plain = PlannedTime::default();
    let mut distinct: Vec<&[Piece]> = Vec::new();
    for (i, cand) in ranking.cands.iter().enumerate() {
        assert_eq!(
            ranking.cost_of(i).flatten().map(f64::to_bits),
            plain.cost(&cand.pieces).map(f64::to_bits)
        );
        if !distinct.iter().any(|d| same_pieces(d, &cand.pieces)) {
            distinct.push(&cand.pieces);
        }
    }
    assert!(distinct.len() < ranking.cands.len(), "no candidates alike");
    assert_eq!(counted.calls.load(Ordering::Relaxed), distinct.len());
}

/// [`PlannedTime`] as the cost, and as its own bound plus the
/// candidate's place in the table (seconds): only the candidates whose
/// bound is at most the least cost found before them are costed.
#[derive(Debug, Default)]
struct Bounded {
    calls: AtomicUsize,
    time: PlannedTime,
}

impl Objective for Bounded {
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.time.cost(pieces)
    }
    fn bound(&self, pieces: &[Piece]) -> Option<f64> {
        // Corner transitions have more pieces than fits: a bound far
        // above any cost for all but the fewest pieces.
        self.time
            .cost(pieces)
            .map(|t| t + if pieces.len() > 20 { 1e3 } else { 0.0 })
    }
}

#[test]
fn a_candidate_whose_bound_exceeds_a_cost_found_is_not_costed() {
    let bounded = Arc::new(Bounded::default());
    let auto = Auto::new(AutoOptions::default(), bounded.clone());
    let run = Run::new(
        (0..40)
            .map(|i| {
                let p = |k: usize| {
                    let a = 0.05 * k as f64;
                    Vec3::new(20.0 * a.cos(), 20.0 * a.sin(), 0.0)
                };
                Piece {
                    curve: Curve::Line(Line::new(p(i), p(i + 1))),
                    rapid: false,
                    source_lines: (i + 1, i + 1),
                    feed: Some(3000.0),
                }
            })
            .collect(),
    );
    let memo = RunMemo::default();
    let mut ranking = auto
        .ranked_candidates(&run, 0.05, (false, false), &memo)
        .map(|(ranking, _)| ranking)
        .unwrap();
    let (_, i) = ranking.fastest(|_| true).unwrap();
    assert!(ranking.cands[i].pieces.len() <= 20);
    let costed = (0..ranking.cands.len())
        .filter(|&k| ranking.cost_of(k).is_some())
        .count();
    assert!(costed < ranking.cands.len(), "every candidate costed");
    // The corner methods' many pieces: bounded, never costed.
    for (k, c) in ranking.cands.iter().enumerate() {
        if c.pieces.len() > 20 {
            assert_eq!(ranking.cost_of(k), None, "{:?}", c.chosen);
        }
    }
    assert_eq!(bounded.calls.load(Ordering::Relaxed), {
        let mut d: Vec<&[Piece]> = Vec::new();
        for k in 0..ranking.cands.len() {
            let p = &ranking.cands[k].pieces;
            if ranking.cost_of(k).is_some() && !d.iter().any(|x| same_pieces(x, p)) {
                d.push(p);
            }
        }
        d.len()
    });
}

/// [`PlannedTime`] as the cost, with a bound (`tight`: the cost itself;
/// else `f64::MAX`, which no cost found lies above).
#[derive(Debug, Default)]
struct BoundedBy {
    tight: bool,
    time: PlannedTime,
}

impl Objective for BoundedBy {
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        self.time.cost(pieces)
    }
    fn bound(&self, pieces: &[Piece]) -> Option<f64> {
        if self.tight {
            self.cost(pieces)
        } else {
            Some(f64::MAX)
        }
    }
}

/// A raster of wavy passes joined by short step-overs between long
/// lines: its sections want fits and corner transitions (waves of
/// 0.4 mm: with 0.3 mm one fit of the whole run has won since the
/// planner flattens splines span by span).
fn wavy_raster() -> Run {
    let mut pts = Vec::new();
    for pass in 0..4 {
        let y = 2.0 * pass as f64;
        let xs: Vec<f64> = (0..=60).map(|k| 0.5 * k as f64).collect();
        let row: Vec<Vec3> = xs
            .iter()
            .map(|&x| Vec3::new(x, y + 0.4 * (0.8 * x).sin(), 0.0))
            .collect();
        if pass % 2 == 0 {
            pts.extend(row);
        } else {
            pts.extend(row.into_iter().rev());
        }
    }
    Run::polyline(&pts, Some(3000.0))
}

/// A window of a longer run (its first and last lines the halves of
/// cut lines) is smoothed so that it goes on straight across each cut
/// (G2 with the cut line), its ends exact: by `auto` and by
/// `bspline-fit` alone.
#[test]
fn a_window_goes_on_straight_across_its_cuts() {
    let wavy = wavy_raster();
    let first = wavy.pieces.first().unwrap().curve.start();
    let last = wavy.pieces.last().unwrap().curve.end();
    let mut pts = vec![first - Vec3::new(1.5, 0.0, 0.0)];
    pts.extend(wavy.pieces.iter().map(|p| p.curve.start()));
    pts.push(last);
    pts.push(last - Vec3::new(1.5, 0.0, 0.0));
    let run = Run::polyline(&pts, Some(3000.0));
    let direction = |p: &Piece| p.curve.end() - p.curve.start();
    let cuts = (
        Some(direction(&run.pieces[0])),
        Some(direction(run.pieces.last().unwrap())),
    );
    let jt = JointTolerances::from_tolerance(0.05);
    let fit = crate::smooth::BsplineFit::default();
    let methods: [&dyn Smoother; 2] = [&Auto::default(), &fit];
    for method in methods {
        let name = method.name();
        let window = method.smooth_window(&run, 0.05, (true, true)).unwrap();
        assert!(
            meets_cut_lines(&window, cuts, jt),
            "{name}: {:?}",
            window.chosen
        );
        let (a, b) = (
            window.pieces.first().unwrap(),
            window.pieces.last().unwrap(),
        );
        assert_eq!(a.curve.start(), pts[0], "{name}");
        assert_eq!(b.curve.end(), *pts.last().unwrap(), "{name}");
        // As a run of its own, its ends are not kept straight.
        let whole = method.smooth_run(&run, 0.05).unwrap();
        assert!(
            !meets_cut_lines(&whole, cuts, jt),
            "{name}: {:?}",
            whole.chosen
        );
    }
}

#[test]
fn a_mix_whose_bound_is_above_the_best_time_is_not_kept_nor_changes_the_choice() {
    let run = wavy_raster();
    let plain = Auto::default().smooth_run(&run, 0.05).unwrap();
    assert!(plain.chosen.len() > 1, "no mix chosen: {:?}", plain.chosen);
    // A tight bound prunes only what cannot win: the same choice.
    let tight = Auto::new(
        AutoOptions::default(),
        Arc::new(BoundedBy {
            tight: true,
            ..Default::default()
        }),
    );
    let t = tight.smooth_run(&run, 0.05).unwrap();
    assert_eq!(t.chosen, plain.chosen);
    assert!(same_pieces(&t.pieces, &plain.pieces));
    // A bound above every cost: no mix is costed, so none is kept.
    let high = Auto::new(AutoOptions::default(), Arc::new(BoundedBy::default()));
    let h = high.smooth_run(&run, 0.05).unwrap();
    assert_eq!(h.chosen.len(), 1, "{:?}", h.chosen);
}

/// An objective that prices a run with an arc at `with_arcs`, else at
/// `lines`, and says `as_written` of the pieces it is asked about:
/// `own` for pieces with an arc (the run as the program wrote it),
/// `curves` for others (a G2 candidate's curves).
#[derive(Debug)]
struct Priced {
    with_arcs: f64,
    lines: f64,
    own: Option<f64>,
    curves: f64,
}

fn has_arc(pieces: &[Piece]) -> bool {
    pieces.iter().any(|p| matches!(p.curve, Curve::Arc(_)))
}

impl Objective for Priced {
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        Some(if has_arc(pieces) {
            self.with_arcs
        } else {
            self.lines
        })
    }
    fn as_written(&self, pieces: &[Piece]) -> Option<f64> {
        if has_arc(pieces) {
            self.own
        } else {
            Some(self.curves)
        }
    }
}

/// A quarter arc of radius 8 between two lines that meet it at
/// corners, and a corner between two lines after it.
fn arc_between_corners() -> Run {
    let piece = |curve| Piece {
        curve,
        rapid: false,
        source_lines: (1, 1),
        feed: Some(3000.0),
    };
    let (a, b) = (Vec3::new(8.0, 0.0, 0.0), Vec3::new(0.0, 8.0, 0.0));
    let arc = crate::geom::Arc::from_center(a, b, Vec3::ZERO, Vec3::Z, false, 1, 1e-9).unwrap();
    Run::new(alloc::vec![
        piece(Curve::Line(Line::new(
            Vec3::new(8.0, -10.0, 0.0),
            Vec3::new(4.0, -6.0, 0.0)
        ))),
        piece(Curve::Line(Line::new(Vec3::new(4.0, -6.0, 0.0), a))),
        piece(Curve::from(arc)),
        piece(Curve::Line(Line::new(b, Vec3::new(-5.0, 12.0, 0.0)))),
        piece(Curve::Line(Line::new(
            Vec3::new(-5.0, 12.0, 0.0),
            Vec3::new(-15.0, 12.0, 0.0)
        ))),
    ])
}

fn chosen_with(objective: Priced) -> Vec<&'static str> {
    let auto = Auto::new(AutoOptions::default(), Arc::new(objective));
    auto.smooth_run(&arc_between_corners(), 0.05)
        .unwrap()
        .chosen
}

#[test]
fn curves_as_written_are_the_fallback_where_the_run_would_be_kept() {
    // The G2 candidates (no arc left) cost more than the run as written:
    // the corner methods on the curves as written, cheaper, are kept.
    let chosen = chosen_with(Priced {
        with_arcs: 1.0,
        lines: 2.0,
        own: Some(1.5),
        curves: 1.0,
    });
    assert!(
        chosen.iter().all(|c| CURVES_AS_WRITTEN.contains(c)),
        "{chosen:?}"
    );
    // Rendered cheaper than the run, but curves that are not: the
    // rendering's gain is not sure to survive the writing.
    let chosen = chosen_with(Priced {
        with_arcs: 1.0,
        lines: 1.2,
        own: Some(1.5),
        curves: 1.6,
    });
    assert!(
        chosen.iter().all(|c| CURVES_AS_WRITTEN.contains(c)),
        "{chosen:?}"
    );
}

#[test]
fn curves_as_written_are_no_fallback_where_a_g2_candidate_gains() {
    let cases = [
        // Rendering and curves both cheaper than the run as written.
        Priced {
            with_arcs: 1.0,
            lines: 1.2,
            own: Some(1.5),
            curves: 1.2,
        },
        // The objective does not say what the run as written costs.
        Priced {
            with_arcs: 1.0,
            lines: 2.0,
            own: None,
            curves: 1.0,
        },
    ];
    for objective in cases {
        let chosen = chosen_with(objective);
        assert!(
            !chosen.is_empty() && chosen.iter().all(|c| !CURVES_AS_WRITTEN.contains(c)),
            "{chosen:?}"
        );
    }
    // Where the run would be kept but the curves as written cost more
    // than the best G2 candidate, or would be kept as well (not the
    // writer's margin cheaper than the run), that candidate stays.
    for with_arcs in [3.0, 1.5 * (1.0 - 0.5 * KEEP_MARGIN)] {
        let chosen = chosen_with(Priced {
            with_arcs,
            lines: 2.0,
            own: Some(1.5),
            curves: 1.0,
        });
        assert!(
            chosen.iter().all(|c| !CURVES_AS_WRITTEN.contains(c)),
            "{with_arcs}: {chosen:?}"
        );
    }
}

/// [`Priced`], with a writer that also judges the runs at a feed the
/// costs are not planned at, where the G2 candidates (no arc) plan
/// slower than the run as written.
#[derive(Debug)]
struct LosingAtTheMaximumFeed(Priced);

impl Objective for LosingAtTheMaximumFeed {
    fn cost(&self, pieces: &[Piece]) -> Option<f64> {
        self.0.cost(pieces)
    }
    fn as_written(&self, pieces: &[Piece]) -> Option<f64> {
        self.0.as_written(pieces)
    }
    fn written_instead(&self, candidate: &[Piece], cost: f64, _: &[Piece], own: f64) -> bool {
        has_arc(candidate) && cost * (1.0 + KEEP_MARGIN) <= own
    }
}

/// Regression (`arc_splitting_0.90.ngc`): the best G2 candidate gains
/// at the feeds it is costed at, rendering and curves, but the writer
/// would keep the run as written at its other feed; the corner methods
/// on the curves as written, which it would write, are kept, though
/// they cost more than that G2 candidate where it is costed.
#[test]
fn curves_as_written_are_the_fallback_where_the_writer_keeps_the_run_at_another_feed() {
    let priced = || Priced {
        with_arcs: 1.3,
        lines: 1.2,
        own: Some(1.5),
        curves: 1.2,
    };
    let auto = Auto::new(
        AutoOptions::default(),
        Arc::new(LosingAtTheMaximumFeed(priced())),
    );
    let chosen = auto
        .smooth_run(&arc_between_corners(), 0.05)
        .unwrap()
        .chosen;
    assert!(
        chosen.iter().all(|c| CURVES_AS_WRITTEN.contains(c)),
        "{chosen:?}"
    );
    // Judged at the costed feeds alone, the G2 candidate stays.
    let chosen = chosen_with(priced());
    assert!(
        !chosen.is_empty() && chosen.iter().all(|c| !CURVES_AS_WRITTEN.contains(c)),
        "{chosen:?}"
    );
}

/// Every candidate but those named, the names as the summary gives them.
fn all_but(keep: &[&str]) -> CandidateSet {
    CandidateSet::of_names(
        CANDIDATES
            .iter()
            .map(|r| r.name)
            .filter(|n| !keep.contains(n)),
    )
    .unwrap()
}

/// A left-out candidate is never chosen, for the whole run or for a
/// section (the zigzag is cut into sections by default).
#[test]
fn left_out_candidates_are_never_chosen() {
    let run = zigzag();
    let plain = Auto::default().smooth_run(&run, 0.05).unwrap();
    assert!(!plain.chosen.is_empty());
    // Each candidate the default choice made, left out in turn.
    for name in plain.chosen.clone() {
        let leave_out = CandidateSet::of_names([name]).unwrap();
        if leave_out.holds_every_one_always_offered() {
            continue;
        }
        let auto = Auto::new(
            AutoOptions {
                leave_out,
                ..AutoOptions::default()
            },
            Arc::new(PlannedTime::default()),
        );
        let out = auto.smooth_run(&run, 0.05).unwrap();
        assert!(
            !out.chosen.contains(&name),
            "{name} left out, yet chosen: {:?}",
            out.chosen
        );
    }
}

/// Leaving out every candidate offered on every run is refused, naming
/// the option; keeping one of them is accepted.
#[test]
fn leave_out_keeps_a_candidate_for_every_run() {
    let always: Vec<&str> = CandidateSet::always_offered().names().collect();
    // The names `AutoOptions::validate`'s message lists.
    assert_eq!(always, ["bspline-fit", "bspline-corner", "lotm", "ctm"]);
    let opts = |names: &[&str]| AutoOptions {
        leave_out: CandidateSet::of_names(names.iter().copied()).unwrap(),
        ..AutoOptions::default()
    };
    let e = opts(&always).validate().unwrap_err();
    assert_eq!(e.option, "leave_out");
    assert!(e.value.contains(always[0]), "{}", e.value);
    assert!(opts(&always[1..]).validate().is_ok());
    let auto = Auto::new(opts(&always), Arc::new(PlannedTime::default()));
    assert!(auto.smooth_run(&zigzag(), 0.05).is_err());
}

proptest::proptest! {
    /// With every candidate left out but one corner method, no
    /// sections and no cuts at near-reversals, `auto` writes what that
    /// method writes, bit for bit (random runs of lines).
    #[test]
    fn auto_with_one_candidate_is_that_method(
        pts in proptest::collection::vec((0.0f64..40.0, 0.0f64..40.0, 0.0f64..2.0), 3..12),
        tol in 0.005f64..0.2,
        which in 0usize..3,
    ) {
        let pieces: Vec<Piece> = pts
            .windows(2)
            .enumerate()
            .map(|(i, w)| Piece {
                curve: Curve::Line(Line::new(
                    Vec3::new(w[0].0, w[0].1, w[0].2),
                    Vec3::new(w[1].0, w[1].1, w[1].2),
                )),
                rapid: false,
                source_lines: (i + 1, i + 1),
                feed: Some(3000.0),
            })
            .collect();
        let run = Run::new(pieces);
        let (name, method): (&str, &dyn Smoother) = match which {
            0 => ("lotm", &crate::smooth::Lotm::default()),
            1 => ("ctm", &crate::smooth::Ctm::default()),
            _ => ("bspline-corner", &crate::smooth::BsplineCorner::default()),
        };
        let auto = Auto::new(
            AutoOptions {
                leave_out: all_but(&[name]),
                section_lines: [f64::INFINITY; 3],
                reversal_turn: f64::INFINITY,
                ..AutoOptions::default()
            },
            Arc::new(PlannedTime::default()),
        );
        let own = method.smooth_run(&run, tol);
        let chosen = auto.smooth_run(&run, tol);
        match (own, chosen) {
            (Ok(own), Ok(chosen)) => {
                proptest::prop_assert!(same_pieces(&own.pieces, &chosen.pieces));
                proptest::prop_assert_eq!(chosen.chosen, alloc::vec![name]);
            }
            (Err(_), Err(_)) => {}
            (own, chosen) => proptest::prop_assert!(
                false,
                "{name}: {:?} against auto's {:?}",
                own.map(|r| r.pieces.len()),
                chosen.map(|r| r.pieces.len())
            ),
        }
    }
}
