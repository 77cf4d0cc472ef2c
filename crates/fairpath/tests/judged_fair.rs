//! `fair` as the registry builds it ([`JudgedFair`]): its two smoothings
//! of a run with arcs judged by the objective, and [`PlannedTime`]'s
//! judgement at every feed a G-code writer judges a run at.

use fairpath::choose::{JudgedFair, Method, Objective, PlannedTime};
use fairpath::feed::limits::MachineLimits;
use fairpath::geom::{Arc, Curve, Line, Vec3};
use fairpath::path::{Piece, Run};
use fairpath::smooth::{Fair, FairOptions, Smoother};
use fairpath::verify::{verify_run, VerifyOptions};
use std::sync::Arc as Shared;

fn piece(curve: Curve, line: usize, feed: f64) -> Piece {
    Piece {
        curve,
        rapid: false,
        source_lines: (line, line),
        feed: Some(feed),
    }
}

fn line(a: Vec3, b: Vec3, n: usize, feed: f64) -> Piece {
    piece(Curve::Line(Line::new(a, b)), n, feed)
}

/// A run of lines with a short arc between each two (alternating sides),
/// which `fair` cannot move: it smooths the run with the arcs kept and
/// with them sampled, fitted and faired.
fn lines_and_arcs() -> Run {
    let (c, r): (f64, f64) = (2.0, 1.6);
    let h = (r * r - 0.25 * c * c).sqrt();
    let p = |x: f64| Vec3::new(x, 0.0, 0.0);
    let mut pieces = Vec::new();
    let mut x = 0.0;
    for i in 0..6 {
        pieces.push(line(p(x), p(x + c), 2 * i + 1, 3000.0));
        x += c;
        let cw = i % 2 == 0;
        let centre = Vec3::new(x + 0.5 * c, if cw { -h } else { h }, 0.0);
        let arc = Arc::from_center(p(x), p(x + c), centre, Vec3::Z, cw, 0, 1e-9).unwrap();
        pieces.push(piece(Curve::from(arc), 2 * i + 2, 3000.0));
        x += c;
    }
    Run::new(pieces)
}

/// A run of one uniform cubic B-spline through `pts`' control points.
fn spline(pts: Vec<Vec3>) -> Run {
    use fairpath::geom::Nurbs;
    let m = pts.len();
    let mut k = vec![0.0; 4];
    k.extend((1..m - 3).map(|i| i as f64));
    k.extend([(m - 3) as f64; 4]);
    Run::new(vec![piece(
        Curve::from(Nurbs::new(3, k, pts, None).unwrap()),
        1,
        24000.0,
    )])
}

/// A spline of rippled corners: its control points a saw-tooth.
fn saw_tooth() -> Run {
    spline(
        (0..24)
            .map(|i| Vec3::new(2.0 * i as f64, if i % 2 == 0 { 0.0 } else { 0.3 }, 0.0))
            .collect(),
    )
}

/// Says whether the sampled smoothing is better, whatever it is.
#[derive(Debug)]
struct Fixed(bool);

impl Objective for Fixed {
    fn cost(&self, _: &[Piece]) -> Option<f64> {
        Some(0.0)
    }
    fn prefers(&self, _: &[Piece], _: &[Piece]) -> bool {
        self.0
    }
}

#[test]
fn judged_fair_writes_the_smoothing_the_objective_prefers() {
    let run = lines_and_arcs();
    let tol = 0.05;
    let fair = Fair::default();
    let alt = fair.alternatives(&run, tol).unwrap();
    let sampled = alt.sampled.clone().expect("the arcs sampled and faired");
    assert_ne!(sampled.pieces, alt.kept.pieces);
    for (prefers, want) in [(true, &sampled), (false, &alt.kept)] {
        let judged = JudgedFair {
            fair,
            objective: Shared::new(Fixed(prefers)),
        };
        let out = judged.smooth_run(&run, tol).unwrap();
        assert_eq!(&out.pieces, &want.pieces, "prefers sampled: {prefers}");
        let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(tol));
        assert!(rep.deviation_bound <= tol, "{}", rep.deviation_bound);
    }
}

#[test]
fn the_registrys_fair_is_judged_by_its_objective() {
    let run = lines_and_arcs();
    let tol = 0.05;
    let alt = Fair::default().alternatives(&run, tol).unwrap();
    let sampled = alt.sampled.expect("the arcs sampled and faired");
    for (prefers, want) in [(true, &sampled), (false, &alt.kept)] {
        let fair = Method::Fair(FairOptions::default()).smoother(Shared::new(Fixed(prefers)));
        let out = fair.smooth_run(&run, tol).unwrap();
        assert_eq!(&out.pieces, &want.pieces, "prefers sampled: {prefers}");
    }
    // With the planner on a machine: the smoothing it prefers.
    let objective = PlannedTime::new(MachineLimits::thesis(), false);
    let want = if objective.prefers(&sampled.pieces, &alt.kept.pieces) {
        &sampled
    } else {
        &alt.kept
    };
    let fair = Method::Fair(FairOptions::default()).smoother(Shared::new(objective));
    assert_eq!(fair.smooth_run(&run, tol).unwrap().pieces, want.pieces);
}

#[test]
fn planned_time_prefers_only_what_is_faster_at_every_feed() {
    let o = Vec3::ZERO;
    // 100 mm at 400 mm/s against 20 mm at 20 mm/s: the first is faster at
    // the programmed feeds, the second at the maximum feed.
    let long_fast = [line(o, Vec3::new(100.0, 0.0, 0.0), 1, 24000.0)];
    let short_slow = [line(o, Vec3::new(20.0, 0.0, 0.0), 1, 1200.0)];
    let m = MachineLimits::thesis();
    let (programmed, overridden) = (PlannedTime::new(m, false), PlannedTime::new(m, true));
    let cost = |o: &PlannedTime, p: &[Piece]| o.cost(p).unwrap();
    assert!(cost(&programmed, &long_fast) < cost(&programmed, &short_slow));
    assert!(cost(&overridden, &short_slow) < cost(&overridden, &long_fast));
    // At the programmed feeds, also at the maximum: neither is better.
    assert!(!programmed.prefers(&long_fast, &short_slow));
    assert!(!programmed.prefers(&short_slow, &long_fast));
    // At the maximum feed alone, the shorter.
    assert!(overridden.prefers(&short_slow, &long_fast));
    assert!(!overridden.prefers(&long_fast, &short_slow));
    // Faster at both: preferred.
    let short_fast = [line(o, Vec3::new(20.0, 0.0, 0.0), 1, 24000.0)];
    assert!(programmed.prefers(&short_fast, &long_fast));
}

/// With `straighten = "judged"` `fair` smooths a run with
/// and without the straightening and keeps the faster by the objective:
/// on a spline of rippled corners (a saw-tooth of control points) and on
/// a smooth wave, with the planner on the thesis' machine, the judged
/// smoothing plans no slower than either (straightened as `Judged`
/// straightens: in the sliding tube), and on the saw-tooth at 0.025
/// mm the straightened one is the faster (so the judgement changes
/// something; at 0.125 mm both are straight).
#[test]
fn fair_keeps_the_straightening_only_where_it_plans_faster() {
    use fairpath::smooth::Straighten;
    let saw = saw_tooth();
    let wave = spline(
        (0..30)
            .map(|i| Vec3::new(2.0 * i as f64, 3.0 * (0.3 * i as f64).sin(), 0.0))
            .collect(),
    );
    let objective: Shared<dyn Objective> =
        Shared::new(PlannedTime::new(MachineLimits::thesis(), false));
    // `On` as `Judged` tries it: the sliding tube (`FairOptions::straightened`).
    let time = |run: &Run, straighten: Straighten, tol: f64| {
        let options = match straighten {
            Straighten::On => FairOptions::default().straightened(),
            _ => FairOptions {
                straighten,
                ..FairOptions::default()
            },
        };
        let judged = JudgedFair {
            fair: Fair { options },
            objective: objective.clone(),
        };
        let out = judged.smooth_run(run, tol).unwrap();
        let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(tol));
        assert!(rep.within(tol), "{rep:?}");
        objective.cost(&out.pieces).unwrap()
    };
    for (name, run) in [("saw", &saw), ("wave", &wave)] {
        for tol in [0.025, 0.125] {
            let (off, on, judged) = (
                time(run, Straighten::Off, tol),
                time(run, Straighten::On, tol),
                time(run, Straighten::Judged, tol),
            );
            assert!(
                judged <= off.min(on) * (1.0 + 1e-12),
                "{name} {tol}: judged {judged}, off {off}, on {on}"
            );
            if name == "saw" && tol == 0.025 {
                assert!(on < off, "{name} {tol}: on {on}, off {off}");
            }
        }
    }
}

/// `fair`'s default (`Straighten::Judged`) straightens only runs that hold
/// a B-spline, and `auto` offers the straightened smoothing
/// (`FAIR_STRAIGHTENED`) on exactly those, so it plans no slower than
/// `fair`: on the saw-tooth spline at 0.025 mm (where the straightened
/// smoothing is the faster) `auto`'s time is at most judged `fair`'s; on
/// a run of lines and arcs judged `fair` writes what `Straighten::Off`
/// writes, and `auto` has no straightened candidate.
#[test]
fn auto_offers_the_straightening_fair_judges_and_only_on_splines() {
    use fairpath::choose::{Auto, AutoOptions, FAIR_STRAIGHTENED};
    use fairpath::smooth::Straighten;
    let objective: Shared<dyn Objective> =
        Shared::new(PlannedTime::new(MachineLimits::thesis(), false));
    let fair = |straighten: Straighten| JudgedFair {
        fair: Fair {
            options: FairOptions {
                straighten,
                ..FairOptions::default()
            },
        },
        objective: objective.clone(),
    };
    assert_eq!(FairOptions::default().straighten, Straighten::Judged);
    let auto = Auto::new(AutoOptions::default(), objective.clone());
    let tol = 0.025;
    let saw = saw_tooth();
    let names = |run: &Run| -> Vec<&'static str> {
        auto.candidates(run, tol)
            .unwrap()
            .into_iter()
            .map(|(n, _)| n)
            .collect()
    };
    assert!(names(&saw).contains(&FAIR_STRAIGHTENED));
    let judged = fair(Straighten::Judged).smooth_run(&saw, tol).unwrap();
    let off = fair(Straighten::Off).smooth_run(&saw, tol).unwrap();
    let cost = |pieces: &[Piece]| objective.cost(pieces).unwrap();
    assert!(cost(&judged.pieces) < cost(&off.pieces));
    let by_auto = auto.smooth_run(&saw, tol).unwrap();
    let rep = verify_run(&saw.pieces, &by_auto.pieces, &VerifyOptions::new(tol));
    assert!(rep.within(tol), "{rep:?}");
    assert!(
        cost(&by_auto.pieces) <= cost(&judged.pieces) * (1.0 + 1e-9),
        "auto {} against fair {}",
        cost(&by_auto.pieces),
        cost(&judged.pieces)
    );
    let arcs = lines_and_arcs();
    assert!(!names(&arcs).contains(&FAIR_STRAIGHTENED));
    let (judged, off) = (
        fair(Straighten::Judged).smooth_run(&arcs, 0.05).unwrap(),
        fair(Straighten::Off).smooth_run(&arcs, 0.05).unwrap(),
    );
    assert_eq!(judged.pieces, off.pieces);
}
