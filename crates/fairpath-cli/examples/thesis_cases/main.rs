//! Chapter 4 of the thesis of seed 003 (Naseath 2007), reproduced: its
//! kinds of test case, faired by the thesis' method (`fair_in_tube`) in
//! tubes of R = 0.025, 0.125 and 0.25 mm, and measured as its Tables 4-1
//! (average curvature), 4-3 (length) and 4-4 (machining time) measure
//! them, beside its published numbers where the case matches.
//!
//! ```sh
//! cargo run --release -p fairpath-cli --example thesis_cases > docs/thesis-cases.md
//! cargo run --release -p fairpath-cli --example thesis_cases -- --write-programs examples/thesis
//! ```
//!
//! The second form also writes each case as a G6.2 program, for
//! `fairpath smooth -m fair` and `fairpath simulate`.
//!
//! The thesis gives its cases' geometry only in figures; these are ours,
//! built to the descriptions (see [`cases`]): the line with two control
//! points displaced 0.2 mm (its case 5: 32 control points, 100.444 mm;
//! gentle bumps on a uniform polygon and sharp ones with close neighbours), the
//! square whose 90-degree corners a CAM interpolation turned into ripples
//! (its case 6: 28 control points, 123.277 mm), a smooth design curve
//! (its case 1: 62 control points, 766 mm, peak curvature 0.175 1/mm), and
//! a family of single ripples of increasing curvature.
//!
//! Times: the thesis' own model (section 4.5: curvature caps
//! `v = sqrt(A / k)` only, S-curves between them, the path starting and
//! ending at the feed; `--time-model thesis --override-feed --run-ends
//! cap`) and fairpath's full model (jerk caps on curves too, at rest at
//! both ends), both on the thesis' machine (400 mm/s, 4000 mm/s^2,
//! 20000 mm/s^3).

mod cases;

use cases::{cases, Case};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{PlanOptions, RunEnds};
use fairpath::feed::program::{simulate_with, Motion};
use fairpath::geom::tube_fair::{fair_in_tube, PeakPass, TubeFairOptions, TubeMeasure};
use fairpath::geom::{arc_length, total_curvature, Curve, Nurbs, ParamCurve};
use fairpath::path::{Piece, Run};
use std::fmt::Write as _;

/// Tube radii of the thesis' tables (mm).
const RADII: [f64; 3] = [0.025, 0.125, 0.25];

/// The variants of the method in the tables: the thesis' iterations
/// alone, then followed by the peak pass (ours) on fairpath's full model's
/// speed caps (the default) or on curvature (the thesis' model's measure).
const VARIANTS: [(&str, PeakPass, TubeMeasure, bool); 5] = [
    ("thesis", PeakPass::Off, TubeMeasure::EqualParameter, false),
    (
        "+ pass (speed caps)",
        PeakPass::DEFAULT_MACHINE,
        TubeMeasure::EqualParameter,
        false,
    ),
    (
        "+ pass (curvature)",
        PeakPass::Curvature,
        TubeMeasure::EqualParameter,
        false,
    ),
    (
        "+ straighten, pass (speed caps), sliding",
        PeakPass::DEFAULT_MACHINE,
        TubeMeasure::Sliding,
        true,
    ),
    (
        "+ straighten, pass (curvature), sliding",
        PeakPass::Curvature,
        TubeMeasure::Sliding,
        true,
    ),
];

/// Accuracy of lengths and curvature integrals (mm, radians).
const ACCURACY: f64 = 1e-9;

/// (average curvature 1/mm, length mm, peak curvature 1/mm).
fn measure(c: &Nurbs) -> (f64, f64, f64) {
    let length = arc_length(c, ACCURACY);
    let (a, b) = c.domain();
    let peak = (0..=20_000)
        .map(|i| c.curvature(a + (b - a) * i as f64 / 20_000.0))
        .fold(0.0, f64::max);
    (total_curvature(c, ACCURACY) / length, length, peak)
}

/// Planned time (s) of the curve alone: the thesis' model, or the full one.
fn time(c: &Nurbs, thesis: bool) -> f64 {
    let mut limits = MachineLimits::thesis();
    limits.jerk_on_curves = !thesis;
    let opts = PlanOptions {
        limits,
        override_feed: true,
        window: None,
        ends: if thesis {
            RunEnds::AtCap
        } else {
            RunEnds::AtRest
        },
    };
    let run = Run::new(vec![Piece {
        curve: Curve::from(c.clone()),
        rapid: false,
        source_lines: (1, 1),
        feed: None,
    }]);
    simulate_with(&[Motion::Feed(run)], &opts)
        .expect("a plannable curve")
        .time()
}

/// The curve as a G6.2 program (Fanuc syntax, mm, order 4).
fn g6_2_program(case: &Case) -> String {
    let c = &case.curve;
    // Parentheses inside a comment are not G-code.
    let what = case.what.replace(['(', ')'], "");
    let mut s = format!(
        "({})\n(fairpath: seed 003 chapter 4 case: {what})\nG21 G90 G17 G94\n",
        case.name
    );
    let p0 = c.points[0];
    let _ = writeln!(s, "G0 X{:.6} Y{:.6}", p0.x, p0.y);
    let _ = writeln!(s, "G1 F24000");
    for (i, p) in c.points.iter().enumerate() {
        let head = if i == 0 { "G6.2 P4 " } else { "" };
        let _ = writeln!(s, "{head}K{:.9} X{:.6} Y{:.6} R1", c.knots[i], p.x, p.y);
    }
    for k in &c.knots[c.points.len()..] {
        let _ = writeln!(s, "K{k:.9}");
    }
    s.push_str("M2\n");
    s
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cases = cases();
    if let Some(dir) = args
        .iter()
        .position(|a| a == "--write-programs")
        .and_then(|i| args.get(i + 1))
    {
        std::fs::create_dir_all(dir).expect("the programs' folder");
        for case in &cases {
            let path = std::path::Path::new(dir).join(format!("{}.ngc", case.name));
            std::fs::write(&path, g6_2_program(case)).expect("a written program");
        }
    }
    let mut out = String::new();
    let _ = writeln!(out, "# Seed 003, chapter 4, reproduced\n");
    let _ = writeln!(
        out,
        "Generated by `cargo run --release -p fairpath-cli --example thesis_cases > docs/thesis-cases.md`.\n\
         Each case is faired by the thesis' method (`fairpath::geom::tube_fair::fair_in_tube`, ends\n\
         pinned, the thesis' precision 5 and accuracy 1%, the U-to-V guard on) in tubes of R = 0.025,\n\
         0.125 and 0.25 mm: its iterations alone (`thesis`), and followed by the peak pass (ours,\n\
         `fairpath::geom::tube_fair::peak`; the library's default) lowering the highest demand of\n\
         fairpath's full model (`speed caps`: `sqrt(k/A)`, `cbrt(k^2/J)`, `cbrt(|dk/ds|/J)`) or the\n\
         highest curvature (`curvature`, what the thesis' model caps); `+ straighten, ..., sliding`:\n\
         the tube measured to the original curve (`fairpath::geom::tube_fair::slide`, ours) and the\n\
         turning minimised inside it after the iterations (`fairpath::geom::tube_fair::straighten`,\n\
         ours; off in the library's tube options, judged by the planner in method `fair`), then\n\
         the pass. Curvature is the average over\n\
         the length (integral of the curvature over the arc length, divided by it), as the thesis'\n\
         Table 4-1; times are planned on the thesis' machine (400 mm/s, 4000 mm/s^2, 20000 mm/s^3) by\n\
         its own model (`thesis`: curvature caps `v = sqrt(A/k)` only, the path starting and ending at\n\
         the feed) and by fairpath's full model (`full`: jerk caps on curves too, at rest at both\n\
         ends). The thesis' numbers (Tables 4-1, 4-3, 4-4) are beside ours where the case is one of\n\
         its own; the geometry is ours (the thesis gives its cases only as figures), so compare the\n\
         changes, not the values.\n"
    );
    // Per variant and radius: the percent reductions of length, average
    // curvature and thesis-model and full-model time of every case, for
    // the averages of Table 4-6.
    let mut reductions: Vec<Vec<Vec<[f64; 4]>>> =
        vec![vec![Vec::new(); RADII.len()]; VARIANTS.len()];
    for case in &cases {
        let _ = writeln!(out, "## {}: {}\n", case.name, case.what);
        let _ = writeln!(
            out,
            "| R (mm) | fairing | avg curvature (1/mm) | peak curvature (1/mm) | length (mm) | time, thesis model (s) | time, full model (s) | iterations, pass moves | thesis: curvature, length, time |"
        );
        let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|");
        let published = |j: usize| {
            case.published.map_or(String::from("-"), |p| {
                format!("{}, {}, {}", p[0][j], p[1][j], p[2][j])
            })
        };
        let (k0, l0, peak) = measure(&case.curve);
        let (t0, f0) = (time(&case.curve, true), time(&case.curve, false));
        let _ = writeln!(
            out,
            "| original | | {k0:.6} | {peak:.4} | {l0:.3} | {t0:.3} | {f0:.3} | - | {} |",
            published(0)
        );
        for (j, &r) in RADII.iter().enumerate() {
            for (v, &(name, pass, tube, straighten)) in VARIANTS.iter().enumerate() {
                let opts = TubeFairOptions {
                    peak_pass: pass,
                    tube,
                    straighten,
                    ..TubeFairOptions::new(r)
                };
                let shown = if v == 0 {
                    published(j + 1)
                } else {
                    String::new()
                };
                match fair_in_tube(&case.curve, &opts) {
                    Ok(f) => {
                        let (k, l, peak) = measure(&f.curve);
                        let (t, tf) = (time(&f.curve, true), time(&f.curve, false));
                        let pct = |new: f64, old: f64| 100.0 * (old - new) / old;
                        reductions[v][j].push([pct(l, l0), pct(k, k0), pct(t, t0), pct(tf, f0)]);
                        let _ = writeln!(
                            out,
                            "| {r} | {name} | {k:.6} | {peak:.4} | {l:.3} | {t:.3} | {tf:.3} | {}, {} | {shown} |",
                            f.iterations.len(),
                            f.peak_pass.moves,
                        );
                    }
                    Err(e) => {
                        let _ = writeln!(out, "| {r} | {name} | error: {e} | | | | | | {shown} |");
                    }
                }
            }
        }
        let _ = writeln!(out);
    }
    // The thesis' Table 4-6: average percent reductions over its six cases.
    let thesis = [
        [0.20, 2.78, 1.10],
        [1.02, 13.28, 6.61],
        [1.93, 23.26, 18.12],
    ];
    let _ = writeln!(
        out,
        "## Averages over these cases (the thesis' Table 4-6 over its six)\n\n\
         | R (mm) | fairing | length reduction % | avg curvature reduction % | time reduction % (thesis model) | time reduction % (full model) | thesis: length, curvature, time % |\n\
         |---|---|---|---|---|---|---|"
    );
    for (j, &r) in RADII.iter().enumerate() {
        for (v, &(name, _, _, _)) in VARIANTS.iter().enumerate() {
            let n = reductions[v][j].len().max(1) as f64;
            let avg = |i: usize| reductions[v][j].iter().map(|x| x[i]).sum::<f64>() / n;
            let shown = if v == 0 {
                format!("{}, {}, {}", thesis[j][0], thesis[j][1], thesis[j][2])
            } else {
                String::new()
            };
            let _ = writeln!(
                out,
                "| {r} | {name} | {:.2} | {:.2} | {:.2} | {:.2} | {shown} |",
                avg(0),
                avg(1),
                avg(2),
                avg(3),
            );
        }
    }
    print!("{out}");
}
