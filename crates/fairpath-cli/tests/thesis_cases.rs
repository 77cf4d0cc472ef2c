//! The fairing on our builds of the thesis' cases (seed 003, chapter 4;
//! the cases are the `thesis_cases` example's own).

#[allow(dead_code)]
#[path = "../examples/thesis_cases/cases.rs"]
mod cases;
use crate::common;

use fairpath::geom::tube_fair::tube::{deviation_bound, difference};
use fairpath::geom::tube_fair::{fair_in_tube, Basis, PeakPass, TubeFairOptions};
use fairpath::geom::{Nurbs, ParamCurve};

/// Highest curvature (1/mm) at 20,001 equal parameter steps.
fn peak(c: &Nurbs) -> f64 {
    let (a, b) = c.domain();
    (0..=20_000)
        .map(|i| c.curvature(a + (b - a) * i as f64 / 20_000.0))
        .fold(0.0, f64::max)
}

/// Asserts that `faired` lies within `r` of `original` on the sure bound
/// and keeps its end points (`what` names the case in a failure).
fn in_tube_with_its_ends(faired: &Nurbs, original: &Nurbs, r: f64, what: &str) {
    let sure = deviation_bound(
        &difference(&faired.points, &original.points),
        &Basis::of(original),
        1e-9,
    );
    assert!(sure <= r, "{what}: bound {sure}");
    assert_eq!(faired.points[0], original.points[0], "{what}");
    assert_eq!(faired.points.last(), original.points.last(), "{what}");
}

/// The square whose corners an interpolation turned into ripples, at R =
/// 0.025 mm: the thesis' iterations leave control points up to 0.09 mm
/// from where they were (their curve within 0.025 mm: the difference
/// spline's control points alternate in sign). The peak pass refused
/// every trial that left a moved control point more than R away, which
/// is no condition on the curve, so it made no move and the corners kept
/// their peak (3.1729 1/mm). Now it lowers them, and the curve stays in
/// the tube on the sure bound.
#[test]
fn square_ripples_peak_pass_moves_points_the_iterations_took_past_the_radius() {
    let case = cases::cases()
        .into_iter()
        .find(|c| c.name == "square-ripples")
        .expect("the square case");
    let r = 0.025;
    let thesis_only = TubeFairOptions {
        peak_pass: PeakPass::Off,
        ..TubeFairOptions::new(r)
    };
    let bare = fair_in_tube(&case.curve, &thesis_only).unwrap();
    let far = bare
        .curve
        .points
        .iter()
        .zip(&case.curve.points)
        .map(|(p, q)| p.dist(*q))
        .fold(0.0, f64::max);
    assert!(far > 2.0 * r, "the iterations' largest move {far}");
    for pass in [PeakPass::DEFAULT_MACHINE, PeakPass::Curvature] {
        let opts = TubeFairOptions {
            peak_pass: pass,
            ..TubeFairOptions::new(r)
        };
        let f = fair_in_tube(&case.curve, &opts).unwrap();
        assert!(f.peak_pass.moves > 0, "{pass:?}: {:?}", f.peak_pass);
        let (before, after) = (peak(&bare.curve), peak(&f.curve));
        assert!(after < 0.99 * before, "{pass:?}: {before} -> {after}");
        in_tube_with_its_ends(&f.curve, &case.curve, r, &format!("{pass:?}"));
    }
}

/// The straight line whose two displaced control points have neighbours
/// 0.05 mm away, and the line whose spline interpolates 32 points, two of
/// them displaced: the thesis' iterations leave a bend over a few short
/// legs (the sharp line: 0.0028 rad at R = 0.125 mm; its curvature rate
/// capped the full model at 0.906 s against 0.543 s straight), and each
/// of those points lay almost on the chord of its own neighbours, so the
/// peak pass's bisector trials could not move them. Laid on the chord of
/// the long legs around them (up to three points for the sharp line, up
/// to five for the interpolated one), the bend spreads over those legs:
/// the curve is nearly straight.
#[test]
fn lines_with_displaced_points_peak_pass_spreads_the_bend_over_the_long_legs() {
    for (name, radii, before, after) in [
        ("line-two-points-sharp", &[0.125, 0.25][..], 0.01, 0.001),
        ("line-two-points-interpolated", &[0.125][..], 0.005, 0.002),
    ] {
        let case = cases::cases()
            .into_iter()
            .find(|c| c.name == name)
            .expect("the case");
        for &r in radii {
            let thesis_only = TubeFairOptions {
                peak_pass: PeakPass::Off,
                ..TubeFairOptions::new(r)
            };
            let bare = peak(&fair_in_tube(&case.curve, &thesis_only).unwrap().curve);
            assert!(bare > before, "{name} {r}: the iterations alone {bare}");
            let f = fair_in_tube(&case.curve, &TubeFairOptions::new(r)).unwrap();
            let k = peak(&f.curve);
            assert!(k < after, "{name} {r}: {bare} -> {k}, {:?}", f.peak_pass);
            in_tube_with_its_ends(&f.curve, &case.curve, r, &format!("{name} {r}"));
        }
    }
}

/// `fairpath smooth examples/thesis/NAME.ngc -t TOL -m METHOD EXTRA
/// --json-summary`, which must succeed and whose output must pass
/// `fairpath check`: its summary.
fn smooth_summary(name: &str, tol: &str, method: &str, extra: &[&str]) -> serde_json::Value {
    let input = common::example(&format!("thesis/{name}.ngc"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
    let mut args = vec![
        "smooth",
        i,
        "-o",
        o,
        "-t",
        tol,
        "-m",
        method,
        "--json-summary",
    ];
    args.extend_from_slice(extra);
    let s = common::bin().args(&args).output().unwrap();
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let c = common::bin()
        .args(["check", i, o, "--tolerance", tol])
        .output()
        .unwrap();
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stdout));
    let printed = String::from_utf8_lossy(&s.stdout);
    serde_json::from_str(&printed[printed.find('{').unwrap()..]).unwrap()
}

/// A time (s) of a `--json-summary`.
fn time(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key}: {v}"))
}

/// `auto` on the design wave (`examples/thesis/design-wave.ngc`, one
/// G6.2 curve) at 0.025 mm: its fit (141 cubics of 64 spans of 0.085 mm,
/// some with a shorter last span) was written as Bezier spans where the
/// knots did not normalise, and with the run's 7 decimals everywhere; the
/// rounded control points stepped the curvature at every joint, the text
/// read back at 4.016 s against 3.741 s for the curves, and the run was
/// kept as the program wrote it (3.921 s). Now it is written within 1%
/// of its curves' time, in fewer lines than the Bezier form, and the
/// output checks (`smooth_summary`). (3.745 against 3.741 s at first;
/// since the planner flattens splines span by span, 3.733 against 3.714 s:
/// it sees the caps of each span, which the rounded control points ripple
/// by a few parts in a thousand, and 196 segments against the curves' 104.)
#[test]
fn design_wave_auto_at_0_025_mm_is_written_near_its_curves_time() {
    let v = smooth_summary("design-wave", "0.025mm", "auto", &[]);
    let (input_s, curves_s, written_s) = (
        time(&v, "input_time_s"),
        time(&v, "curves_time_s"),
        time(&v, "written_time_s"),
    );
    assert!(written_s < 0.97 * input_s, "{written_s} against {input_s}");
    assert!(
        written_s <= 1.01 * curves_s,
        "{written_s} against {curves_s}"
    );
}

/// `fair` on the design wave at 0.25 mm, planned in the thesis' model
/// (`--time-model thesis`: curvature caps `sqrt(A/k)` only): its peak pass
/// lowered the default machine's jerk-limited demand whatever the model,
/// 2.535 -> 2.527 s (0.3% less, the thesis' Table 4-4 kind: 1.1%). The
/// pass now lowers what the job's machine caps, the curvature here:
/// at least the thesis' 1.1% less.
#[test]
fn design_wave_fair_in_the_thesis_model_lowers_the_curvature_it_caps() {
    let extra = ["--time-model", "thesis", "--override-feed"];
    let v = smooth_summary("design-wave", "0.25mm", "fair", &extra);
    let (input_s, written_s) = (time(&v, "input_time_s"), time(&v, "written_time_s"));
    assert!(
        written_s <= 0.989 * input_s,
        "{written_s} against {input_s}"
    );
}

/// Planned time (s) of `c` alone in the thesis' model (section 4.5:
/// curvature caps only, starting and ending at the feed) on its machine.
fn thesis_model_time(c: &Nurbs) -> f64 {
    use fairpath::feed::limits::MachineLimits;
    use fairpath::feed::plan::{PlanOptions, RunEnds};
    use fairpath::feed::program::{simulate_with, Motion};
    use fairpath::geom::Curve;
    use fairpath::path::{Piece, Run};
    let mut limits = MachineLimits::thesis();
    limits.jerk_on_curves = false;
    let opts = PlanOptions {
        limits,
        override_feed: true,
        window: None,
        ends: RunEnds::AtCap,
    };
    let run = Run::new(vec![Piece {
        curve: Curve::from(c.clone()),
        rapid: false,
        source_lines: (1, 1),
        feed: None,
    }]);
    simulate_with(&[Motion::Feed(run)], &opts).unwrap().time()
}

/// The square at R = 0.025 mm, the one cell of the thesis' Table 4-4 its
/// method beat ours on: the thesis planned its square 2.4% faster (1.97
/// -> 1.922 s), ours 1.7% with the peak pass (1.508 -> 1.482 s), and a
/// global optimiser found no more than 1.8% with the tube measured at
/// equal parameters (docs/tuning.md, "straightening"). With the turning
/// minimised inside the tube measured to the original curve (the sliding
/// tube), the ripples beside the corners flatten and the time falls by
/// more than the thesis'; the curve stays within R of the original path
/// (checked against a dense polyline of it, not by the fairing's bound)
/// and keeps its ends.
#[test]
fn square_ripples_straightened_in_the_sliding_tube_beats_the_thesis_at_0_025_mm() {
    use fairpath::geom::tube_fair::TubeMeasure;
    let case = cases::cases()
        .into_iter()
        .find(|c| c.name == "square-ripples")
        .expect("the square case");
    let r = 0.025;
    let opts = TubeFairOptions {
        tube: TubeMeasure::Sliding,
        straighten: true,
        ..TubeFairOptions::new(r)
    };
    let f = fair_in_tube(&case.curve, &opts).unwrap();
    let (before, after) = (thesis_model_time(&case.curve), thesis_model_time(&f.curve));
    let thesis_share = 1.0 - 1.922 / 1.97;
    assert!(
        after <= (1.0 - thesis_share) * before,
        "{before} -> {after} s: less than the thesis' {:.2}%",
        100.0 * thesis_share
    );
    assert_eq!(f.curve.points[0], case.curve.points[0]);
    assert_eq!(f.curve.points.last(), case.curve.points.last());
    // Within R of the original path: each of 10,000 points of the result
    // against the chords of 100,000 points of the original (chords of
    // about 1.2 um, whose sag at the highest curvature, 3.3 1/mm, is under
    // a nanometre).
    let dense = |c: &Nurbs, n: usize| -> Vec<fairpath::geom::Vec3> {
        let (a, b) = c.domain();
        (0..=n)
            .map(|i| c.eval(a + (b - a) * i as f64 / n as f64))
            .collect()
    };
    let line = dense(&case.curve, 100_000);
    let mut from = 0usize;
    for p in dense(&f.curve, 10_000) {
        // The nearest chord near the last one (the curves run alike).
        let window = from.saturating_sub(5_000)..(from + 5_000).min(line.len() - 1);
        let (i, d) = window
            .map(|i| {
                let (a, b) = (line[i], line[i + 1]);
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.dot(ab)).clamp(0.0, 1.0);
                (i, p.dist(a + ab * t))
            })
            .fold((0, f64::INFINITY), |x, y| if y.1 < x.1 { y } else { x });
        assert!(d <= r, "{p:?}: {d} mm from the original");
        from = i;
    }
}

/// `fair`'s straightening on the square at 0.25 mm: forced on by the
/// bundled `examples/options/fair-straighten.toml`, the written program
/// checks (`smooth_summary`) and plans faster on the default machine than
/// with it off; judged (`straighten = "judged"`, the default), `fair`
/// writes a program no slower than either.
#[test]
fn the_bundled_straightening_options_plan_the_square_faster() {
    let on = common::example("options/fair-straighten.toml");
    let dir = tempfile::tempdir().unwrap();
    let off = dir.path().join("off.toml");
    std::fs::write(&off, "straighten = \"off\"\n").unwrap();
    let judge = dir.path().join("judged.toml");
    std::fs::write(&judge, "straighten = \"judged\"\n").unwrap();
    let run = |extra: &[&str]| {
        let v = smooth_summary("square-ripples", "0.25mm", "fair", extra);
        time(&v, "written_time_s")
    };
    let with = run(&["--options", on.to_str().unwrap()]);
    let without = run(&["--options", off.to_str().unwrap()]);
    let judged = run(&["--options", judge.to_str().unwrap()]);
    assert_eq!(run(&[]), judged, "judged is the default");
    assert!(with < 0.99 * without, "{with} against {without}");
    assert!(
        judged <= with.min(without) * (1.0 + 1e-9),
        "judged {judged}: on {with}, off {without}"
    );
}

/// Feed time (s) of `program` in the thesis' model as `fairpath simulate
/// --time-model thesis --override-feed --run-ends cap` prints it.
fn thesis_model_feed_time(program: &std::path::Path) -> f64 {
    let s = common::bin()
        .args(["simulate", program.to_str().unwrap()])
        .args([
            "--time-model",
            "thesis",
            "--override-feed",
            "--run-ends",
            "cap",
        ])
        .output()
        .unwrap();
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let text = String::from_utf8_lossy(&s.stdout);
    let line = text.lines().find(|l| l.contains("time:")).unwrap();
    let feed = line
        .split('(')
        .nth(1)
        .unwrap()
        .split(" s feed")
        .next()
        .unwrap();
    feed.trim().parse().unwrap()
}

/// `fair` with its defaults, as a user runs it: `fairpath smooth -m fair -t
/// 0.025mm` on the square of rippled corners, written as G6.2 (within a
/// fiftieth of the tolerance, `fairpath::budget::EXACT_OUTPUT_SHARE`) and
/// with the straightening judged by the planner (`Straighten::Judged`),
/// plans at least the thesis' 2.4% faster in the thesis' own model
/// (3.7% when measured). Before the two, 1.7%: the straightening was off
/// by default and a tenth of the tolerance went to writing curves that
/// G6.2 writes exactly. The written program checks against the input.
#[test]
fn square_ripples_fair_by_default_beats_the_thesis_at_0_025_mm() {
    let input = common::example("thesis/square-ripples.ngc");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let (i, o) = (input.to_str().unwrap(), out.to_str().unwrap());
    let s = common::bin()
        .args(["smooth", i, "-o", o, "-t", "0.025mm", "-m", "fair"])
        .output()
        .unwrap();
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let printed = String::from_utf8_lossy(&s.stdout);
    assert!(
        printed.contains("writing 0.000500 mm"),
        "G6.2 gets a fiftieth of the tolerance: {printed}"
    );
    let c = common::bin()
        .args(["check", i, o, "--tolerance", "0.025mm"])
        .output()
        .unwrap();
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stdout));
    let (before, after) = (thesis_model_feed_time(&input), thesis_model_feed_time(&out));
    let thesis_share = 1.0 - 1.922 / 1.97;
    assert!(
        after <= (1.0 - thesis_share) * before,
        "{before} -> {after} s: less than the thesis' {:.2}%",
        100.0 * thesis_share
    );
}
