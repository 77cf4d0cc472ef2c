//! Issue 21: `auto` writes a program no slower than the best single
//! curvature-continuous method's, on the shared programs where it once
//! was slower (read in place; skipped without `../shared/paths`).
//!
//! Regressions: `surface-raster.ngc`, where the curves' time pruned
//! `bspline-fit` although its arcs plan faster than its curves (auto
//! 59.597 s against `fair` 59.489 s and `bspline-fit` 59.497 s), and where
//! `fair` was no candidate on a run of 2,979 lines; `square-wave.ngc`,
//! where `auto` writes `bspline-corner`'s program and `ctm` the same
//! transitions, rounded differently in the seventh decimal (a tie);
//! `tort.ngc`, whose run at lines 83-90 (a tight arc, two lines, an arc,
//! at a feed above the machine's) `bspline-corner` writes with its arcs
//! and only the corner between the lines replaced, while every candidate
//! of `auto` sampled the arcs and put a transition on each chord (1.97 s
//! against 0.50 s): `auto` kept the run as written, 0.0039 s slower over
//! the program (0.0015 s since short rendered pieces get more decimals).
//! With `curves_as_written = true` it is not (the same run, moved, in
//! `tort_arcs_and_lines_auto_with_curves_as_written`); by default neither
//! since those candidates are its fallback where every G2 candidate would
//! leave the run as written. Moved, the run also showed why `auto`'s fit
//! was not written: rounded to 7 decimals, its micrometre lines read back
//! kinked (`tort_arcs_and_lines_auto_falls_back_to_the_curves_as_written`).
//! `arc_splitting_0.90.ngc`: `auto`'s fits gained at the programmed feed
//! and lost at the maximum one, and the run was kept as written.
//! `3D_Chips.ngc`: fits that pass only after knot insertion beyond the
//! doubling's count were lost to a bound on that insertion.
//! `parabolic_split1.ngc`: a near-reversal turned G2 inside the band.
//! `line-contouring-xz.ngc`: narrow U-turns at its step-overs turned G2.
//! `spiral_tight_circular.ngc`: `fair` (with its peak pass) wrote it
//! 0.028% faster than `auto`, whose `fair` candidate goes without it.
//! `3D_Chips.ngc` at 0.02 mm: `auto` ranked by the default curvature
//! step a mix the writer's finer step wrote slower than `bspline-fit`;
//! at 0.05 mm its three contenders missed the fastest written, the fourth
//! cheapest.
//! `tight-corner-tolerance.ngc` at 0.1 mm: `ctm`, not a candidate then,
//! wrote it 1.9% faster than `auto`.

use fairpath_cli::compare::{compare, CompareOptions};
use fairpath_cli::{Controller, Format};
use std::path::Path;

use crate::common;

/// `f` on the shared program `rel`, read in place; skipped without it.
fn with_shared(rel: &str, f: impl FnOnce(&Path)) {
    match common::shared(rel) {
        Some(p) => f(&p),
        None => eprintln!("{rel} not found: skipped"),
    }
}

/// Two times of written programs count as equal within this share: the
/// same geometry, its coordinates rounded differently.
const TIE: f64 = 1e-6;

/// `auto` writes `p` no slower than each curvature-continuous method.
fn check(rel: &str, p: &Path) {
    check_at(rel, p, 0.05)
}

/// The times of the programs `methods` write for `p` at `tolerance` mm
/// (arcs, generic controller, the thesis' machine), each verified.
fn written_times(rel: &str, p: &Path, tolerance: f64, methods: &[&str]) -> Vec<f64> {
    written_times_at(rel, p, (tolerance, false), methods)
}

/// [`written_times`] at `tolerance` mm, with every feed at the machine's
/// maximum where `override_feed`.
fn written_times_at(
    rel: &str,
    p: &Path,
    (tolerance, override_feed): (f64, bool),
    methods: &[&str],
) -> Vec<f64> {
    let opts = CompareOptions {
        tolerance,
        machine: fairpath::feed::limits::MachineLimits::thesis(),
        methods: methods.iter().map(|m| m.to_string()).collect(),
        override_feed,
        formats: vec![Format::Arcs],
        controller: Controller::Generic,
    };
    let rows = compare(p, &opts).unwrap();
    methods
        .iter()
        .map(|&m| {
            let w = &rows.iter().find(|r| r.method == m).unwrap().written[0];
            assert!(w.verified, "{rel} {m}: not verified");
            w.time
        })
        .collect()
}

/// [`check`] at `tolerance` mm.
fn check_at(rel: &str, p: &Path, tolerance: f64) {
    let methods = [
        "auto",
        "bspline-corner",
        "ctm",
        "lotm",
        "bspline-fit",
        "fair",
    ];
    check_methods(rel, p, tolerance, &methods);
}

/// `auto` (the first of `methods`) writes `p` at `tolerance` mm no slower
/// than each of the others.
fn check_methods(rel: &str, p: &Path, tolerance: f64, methods: &[&str]) {
    let times = written_times(rel, p, tolerance, methods);
    let auto = times[0];
    for (m, &t) in methods.iter().zip(&times).skip(1) {
        assert!(
            auto <= t * (1.0 + TIE),
            "{rel}: auto {auto:.4} s, slower than {m} {t:.4} s"
        );
    }
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn surface_raster_auto_is_no_slower_than_fair_or_bspline_fit() {
    with_shared("synthetic/surface-raster.ngc", |p| {
        check("surface-raster", p)
    });
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn square_wave_auto_ties_ctm() {
    with_shared("synthetic/square-wave.ngc", |p| check("square-wave", p));
}

/// `parabolic_split1.ngc`: a line, then an arc starting back along it (a
/// turn of 165.5 degrees). Every curvature-continuous method but `auto`
/// keeps the corners next to its arcs; `auto` turned that near-reversal G2
/// inside the band (peak curvature 357 1/mm) and wrote 2.270 s against
/// `bspline-corner`'s 2.220 s. It now also keeps near-reversals as corners
/// where that plans faster (`choose::REVERSAL_TURN`).
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn parabolic_split1_auto_keeps_its_near_reversal() {
    with_shared("linuxcnc/diagnostic/parabolic_split1.ngc", |p| {
        check("parabolic_split1", p)
    });
}

/// `spiral_tight_circular.ngc` at 0.05 mm: a spiral of 60 arcs, which
/// `auto` samples into chords. Its `fair` candidate fairs them without the
/// peak pass and came 1.3% behind the jerk-faired fit on one run; method
/// `fair` runs the pass and wrote the program in 1.61028 s against
/// `auto`'s 1.61073 s. `auto` now makes a `fair` candidate that near the
/// best again with the pass (`Auto::fair_with_peak_pass`).
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn spiral_tight_circular_auto_fairs_near_candidates_with_the_peak_pass() {
    with_shared("linuxcnc/quick-tests/spiral_tight_circular.ngc", |p| {
        check("spiral_tight_circular", p)
    });
}

/// `line-contouring-xz.ngc`: a zigzag of arches in XZ whose step-overs
/// (1.21 mm across in Y, most with a 4 um move down before the next arch)
/// are narrow U-turns of two right angles. G2 through them (with the
/// near-reversal cuts alone) `auto` wrote 15.173 s; with their corners
/// kept where that plans faster (`choose::u_turn_cuts`), 13.150 s. Since
/// curves that arcs cannot follow are cut as lines like the G1 format's
/// (their neighbours' caps), G2 through them writes 14.555 s and the
/// corners 13.149 s: still kept, 9.7% faster.
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn line_contouring_xz_auto_keeps_its_step_over_corners() {
    with_shared("linuxcnc/performance/line-contouring-xz.ngc", |p| {
        let kept = |v: &serde_json::Value| v["kept_corners"]["at a U-turn"].as_u64().unwrap();
        let with = summary(p, "auto", None);
        let without = summary(p, "auto", Some("u_turn_width = 0\n"));
        let (t, t0) = (
            with["written_time_s"].as_f64().unwrap(),
            without["written_time_s"].as_f64().unwrap(),
        );
        assert!(kept(&with) > 0 && kept(&without) == 0, "{with} {without}");
        assert!(t < 0.95 * t0, "with U-turn corners {t} s, without {t0} s");
        check("line-contouring-xz", p);
    });
}

/// `line-contouring-xz.ngc` with `final_cost_margin = 0.03`: the writer's
/// judgement kept another whole-run candidate than the cheapest by cost,
/// one of the plain fit alone, and the runs between the corners of its
/// U-turns, which are offered the candidates the whole run's best chose,
/// got the plain fit alone: 12.889 s against 12.489 s at the default
/// margin (then 0.02). They are now also offered those the cheapest by
/// cost chose: the default margin (0.1 since stop 107) and a wider one
/// write no slower than that (to its millisecond).
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn line_contouring_xz_a_wider_final_cost_margin_keeps_the_split_candidates() {
    with_shared("linuxcnc/performance/line-contouring-xz.ngc", |p| {
        let t = |o| summary(p, "auto", o)["written_time_s"].as_f64().unwrap();
        let (wide, default) = (t(Some("final_cost_margin = 0.2\n")), t(None));
        assert!(
            default < 12.4895 && wide <= default * (1.0 + TIE),
            "margin 0.2: {wide} s, default: {default} s"
        );
    });
}

/// `3D_Chips.ngc`: where no control-point count of the doubling passed,
/// knot insertion bounded by that count (41ef47c, for a spiral whose fits
/// cannot pass) left fits that pass only with knots crowded where the data
/// bend unfound, and `auto` wrote 68.029 s where it had written 65.725 s;
/// the bound is now twice that count (`fit_search::INSERTION_PER_DOUBLING`).
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn three_d_chips_auto_keeps_the_fits_knot_insertion_finds() {
    with_shared("linuxcnc/performance/3D_Chips.ngc", |p| {
        let auto = written_times("3D_Chips", p, 0.05, &["auto"])[0];
        assert!(auto <= 65.73, "auto wrote 3D_Chips.ngc in {auto} s");
    });
}

/// `3D_Chips.ngc` at 0.05 mm, once the planner took an arc that goes on as
/// short moves to keep its curvature at the joint (b1d905b): `auto` wrote
/// 62.738 s against `bspline-fit`'s 61.860 s. Its main run's fastest
/// written candidate was the fourth cheapest by cost, and a mix of
/// sections reached twice had taken two of the three contenders' places;
/// six are judged now, a smoothing reached twice once
/// (`choose::SAME_COST_SHARE`).
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn three_d_chips_auto_judges_the_fourth_cheapest_as_written() {
    with_shared("linuxcnc/performance/3D_Chips.ngc", |p| {
        check_methods("3D_Chips", p, 0.05, &["auto", "bspline-fit"])
    });
}

/// `3D_Chips.ngc` at 0.02 mm: `auto` ranked a mix of sections 0.6% ahead
/// of its best whole-run fit at the default curvature step, but the
/// writer renders each run again at the finer step, where the fit gained
/// more, and the program `auto` wrote (68.027 s) was slower than
/// `bspline-fit`'s (67.966 s). `auto` now judges the candidates near its
/// best as the writer finally writes them (`choose::FINER_STEP_MARGIN`).
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn three_d_chips_at_0_02mm_auto_judges_near_candidates_at_the_finer_step() {
    with_shared("linuxcnc/performance/3D_Chips.ngc", |p| {
        check_methods("3D_Chips", p, 0.02, &["auto", "bspline-fit"])
    });
}

/// `tight-corner-tolerance.ngc` at 0.1 mm: a star of 1-inch strokes out
/// and back, every vertex a near-reversal. Every candidate of `auto` was
/// kept as the run was written (77.198 s); `ctm`, which `auto` did not
/// offer, sizes its transitions differently from `bspline-corner` and
/// wrote 75.738 s. `ctm` is now a candidate.
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn tight_corner_tolerance_at_0_1mm_auto_is_no_slower_than_ctm() {
    with_shared("linuxcnc/performance/tight-corner-tolerance.ngc", |p| {
        check_at("tight-corner-tolerance", p, 0.1)
    });
}

/// The JSON summary of `fairpath smooth --method METHOD` on `path` at
/// 0.05 mm, with the options file holding `options` if given.
fn summary(path: &Path, method: &str, options: Option<&str>) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let mut cmd = common::bin();
    cmd.args(["smooth", "-t", "0.05mm", "--json-summary", "-m", method])
        .arg(path)
        .arg("-o")
        .arg(&out);
    if let Some(o) = options {
        let f = dir.path().join("options.toml");
        std::fs::write(&f, o).unwrap();
        cmd.arg("--options").arg(&f);
    }
    let run = cmd.output().unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    serde_json::from_slice(&run.stdout).unwrap()
}

/// The written time (s) of [`summary`]'s run, and the number of corners
/// next to arcs it keeps.
fn written(path: &Path, method: &str, options: Option<&str>) -> (f64, u64) {
    let v = summary(path, method, options);
    let k = &v["kept_corners"];
    (
        v["written_time_s"].as_f64().unwrap(),
        k["next to an arc"]
            .as_u64()
            .unwrap_or_else(|| panic!("{k}")),
    )
}

/// `auto` with the corner methods on the curves as written is no slower
/// than `bspline-corner` and `lotm`; by default it is G2 where they keep
/// corners next to arcs.
fn check_curves_as_written(rel: &str, p: &Path) {
    let (fast, _) = written(p, "auto", Some("curves_as_written = true\n"));
    for m in ["bspline-corner", "lotm"] {
        let (t, _) = written(p, m, None);
        assert!(
            fast <= t * (1.0 + TIE),
            "{rel}: auto with curves as written {fast:.6} s, slower than {m} {t:.6} s"
        );
    }
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn tort_auto_with_curves_as_written_is_no_slower_than_the_corner_methods() {
    with_shared("linuxcnc/performance/tort.ngc", |p| {
        check_curves_as_written("tort", p)
    });
}

/// Issue 21's target "never slower than the best single method": by
/// default `auto` was 0.0015 s slower than `bspline-corner` on `tort.ngc`
/// (it kept the run at lines 83-90 as written).
#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn tort_auto_is_no_slower_than_any_method() {
    with_shared("linuxcnc/performance/tort.ngc", |p| check("tort", p));
}

/// LinuxCNC's `arc_splitting_0.90.ngc` (an inch program at F100: a line,
/// an arc and a line, meeting at corners): `auto`'s best G2 candidate (a
/// mix of fits) rendered 0.4% faster than the run as written at the
/// programmed feed, which `auto`'s objective costs, but slower at the
/// machine's maximum feed, where the writer judges a run too, so the run
/// was kept as written: 2.547 s against `bspline-corner`'s 2.490 s. The
/// fallback to the corner methods on the curves as written now asks the
/// writer's rule at both feeds (`Objective::written_instead`).
#[test]
fn arc_splitting_0_90_auto_is_no_slower_than_any_method() {
    with_shared("linuxcnc/quick-tests/arc_splitting_0.90.ngc", |p| {
        check("arc_splitting_0.90", p)
    });
}

/// LinuxCNC's `cap.ngc` (rectangles, and rectangles rounded by tangent
/// arcs): at 0.01 mm `auto`'s best G2 candidate on a rounded rectangle
/// would be kept as written (not faster than the run at every feed the
/// writer judges at), and so would the corner methods on the curves as
/// written, so `auto` wrote 45.074 s where `fair`, once it judged its
/// sampled arcs by the planner, wrote 44.339 s (43.535 against 43.488 s
/// at 0.05 mm). `auto`'s fallback now also tries `fair` on the curves as
/// written.
#[test]
fn cap_auto_is_no_slower_than_any_method() {
    with_shared("linuxcnc/performance/cap.ngc", |p| {
        check_at("cap", p, 0.05);
        check_at("cap", p, 0.01);
    });
}

/// LinuxCNC's `Curva_Chitarra_p1.ngc` (a G6.2 guitar outline) at 0.05 mm:
/// `fair`'s curves lose as arcs at the machine's maximum feed and gain as
/// G1 at both feeds, which the writer tries wherever the arcs do not win,
/// by no margin on a run of splines; `auto`'s judge of what the writer
/// writes (`Objective::written_instead`) tried neither, so `auto` kept
/// the run as written: 58.076 s against `fair`'s 58.024 s. It now judges
/// the all-G1 rendering and the writer's margin as the writer does.
#[test]
fn curva_chitarra_p1_auto_is_no_slower_than_fair() {
    with_shared("linuxcnc-nurbs/G6/Curva_Chitarra_p1.ngc", |p| {
        check("Curva_Chitarra_p1", p)
    });
}

/// LinuxCNC's `simple_blend.ngc` (inch: four right angles): once the
/// outer-edge candidate's corners were held to the corner reach, its
/// right angles next to the run's ends, on moves the guide tilts, fell
/// 0.2% beyond the reach at the largest shift, and `auto` wrote 1.3913 s
/// against `bspline-corner`'s 1.3906 s (docs/lower-bound-all.md, stop
/// 109). The candidate now tries a narrower reach (`OUTER_REACH_RETRY`).
#[test]
fn simple_blend_auto_is_no_slower_than_any_method() {
    with_shared("linuxcnc/diagnostic/simple_blend.ngc", |p| {
        check("simple_blend", p)
    });
}

/// LinuxCNC's `helix_slowdown.ngc` at 0.05 mm: `auto`'s best G2
/// candidate (fits) loses as arcs at the maximum feed and gains as G1;
/// `auto` falls back to the corner methods on the curves as written
/// (`bspline-corner`'s 3.642 s). Judging the G1 rendering in place of that
/// fallback wrote the fits' G1, 3.698 s: G1 is judged only where no
/// fallback candidate would be written from its forms.
#[test]
fn helix_slowdown_auto_is_no_slower_than_any_method() {
    with_shared("linuxcnc/diagnostic/helix_slowdown.ngc", |p| {
        check("helix_slowdown", p)
    });
}

/// The run of `tort.ngc` at lines 83-90, moved to end its first arc at
/// the origin: a 270-degree arc of radius 8 mm, two lines with a corner
/// between them, an arc of radius 6 mm, at a feed the machine caps.
const TORT_ARCS_AND_LINES: &str = "G21 G90 G17\nG0 X0 Y0 Z20\nG0 X9.657 Y-12.585 Z2\n\
     G3 X0 Y0 Z0 I-5.656854 J5.656854 F99630\nG1 X4.5 Y4.5 Z3.5\n\
     G1 X3 Y9.5 Z4.5\nG2 X-4.242641 Y8.546488 Z7.5 I-3 J-5.196152\n\
     G0 Z20\nM2\n";

#[test]
fn tort_arcs_and_lines_auto_with_curves_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("arcs-lines.ngc");
    std::fs::write(&p, TORT_ARCS_AND_LINES).unwrap();
    check_curves_as_written("tort's arcs and lines", &p);
    // The corner methods keep the corners next to the arcs, and so does
    // `auto`, with the option or without (its fallback here).
    let (_, with) = written(&p, "auto", Some("curves_as_written = true\n"));
    let (_, without) = written(&p, "auto", None);
    let (_, corner) = written(&p, "bspline-corner", None);
    assert_eq!((with, without, corner), (2, 2, 2));
}

/// The same run with `auto` by default: its G2 fit reaches 198 1/mm at a
/// near-reversal and is rendered there as G1 lines about 1 um long. Its
/// rendering planned 1.267 s on feed moves against 1.287 s for the run as
/// written, but its curves 1.328 s, and its text read back 1.296 s (the
/// rounding of the micrometre lines): the run was kept as written, slower
/// than `bspline-corner`. Since the fit's curves do not beat the run,
/// `auto` falls back to the corner methods on the curves as written, and
/// writes what `bspline-corner` writes.
#[test]
fn tort_arcs_and_lines_auto_falls_back_to_the_curves_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("arcs-lines.ngc");
    std::fs::write(&p, TORT_ARCS_AND_LINES).unwrap();
    let v = summary(&p, "auto", None);
    let t = |k: &str| v[k].as_f64().unwrap();
    assert_eq!(v["kept_runs"].as_u64(), Some(0), "run kept as written");
    assert!(
        t("written_time_s") < t("input_time_s"),
        "written {:.6} s, input {:.6} s",
        t("written_time_s"),
        t("input_time_s")
    );
    let chose = v["auto_chose"].to_string();
    assert!(chose.contains("curves as written"), "{chose}");
    let (corner, _) = written(&p, "bspline-corner", None);
    assert!(
        t("written_time_s") <= corner * (1.0 + TIE),
        "{} s",
        t("written_time_s")
    );
}

/// A zigzag finishing raster over a smooth surface, as
/// `scripts/random-programs.py /tmp/gras 8 9702 raster` writes its
/// rasters: passes along X of `seg` mm moves at `places` decimals, `step`
/// mm apart in Y, a micro jog of 1 um beyond each pass's end (the script
/// draws its sign; here it runs on), the surface a sum of `terms`
/// (amplitude, x and y frequencies, phase).
struct Raster {
    terms: &'static [(f64, f64, f64, f64)],
    width: f64,
    step: f64,
    seg: f64,
    places: usize,
    feed: u32,
    passes: usize,
}

impl Raster {
    /// The program's text.
    fn program(&self) -> String {
        let z = |x: f64, y: f64| -> f64 {
            self.terms
                .iter()
                .map(|(a, fx, fy, p)| a * (fx * x + fy * y + p).sin())
                .sum()
        };
        let num = |v: f64| {
            let s = format!("{v:.*}", self.places);
            let s = s.trim_end_matches('0').trim_end_matches('.');
            if s.is_empty() || s == "-0" {
                "0".to_string()
            } else {
                s.to_string()
            }
        };
        let n = (self.width / self.seg) as usize;
        let mut out = vec![
            "G21 G90 G17".to_string(),
            "G0 Z10".to_string(),
            "G0 X0 Y0".to_string(),
            format!("G1 Z{} F{}", num(z(0.0, 0.0)), self.feed / 3),
        ];
        let mut y = 0.0;
        for k in 0..self.passes {
            let forward = k % 2 == 0;
            let xs: Vec<f64> = (0..=n)
                .map(|i| {
                    let x = self.width * i as f64 / n as f64;
                    if forward {
                        x
                    } else {
                        self.width - x
                    }
                })
                .collect();
            for (i, &x) in xs.iter().enumerate() {
                let feed = if i == 0 {
                    format!(" F{}", self.feed)
                } else {
                    String::new()
                };
                out.push(format!(
                    "G1 X{} Y{} Z{}{feed}",
                    num(x),
                    num(y),
                    num(z(x, y))
                ));
            }
            let x = xs[n] + if forward { 1e-3 } else { -1e-3 };
            out.push(format!("G1 X{} Y{} Z{}", num(x), num(y), num(z(x, y))));
            y += self.step;
        }
        out.push("G0 Z10\nM2\n".to_string());
        out.join("\n")
    }
}

/// `r001_raster.ngc` of that set.
const RASTER_R001: Raster = Raster {
    terms: &[
        (
            2.1495920133650896,
            0.07346384790785866,
            0.2492731392310225,
            5.607940118288135,
        ),
        (
            1.2058757376064546,
            0.07896602914573908,
            0.13493514850536378,
            0.256009266122989,
        ),
    ],
    width: 33.58,
    step: 1.02859,
    seg: 0.16987,
    places: 5,
    feed: 600,
    passes: 27,
};

/// `r005_raster.ngc` of that set.
const RASTER_R005: Raster = Raster {
    terms: &[(
        0.3388219998609282,
        0.08743512412745963,
        0.1686919425792121,
        3.739397026237484,
    )],
    width: 45.80904162244596,
    step: 0.379193871036762,
    seg: 0.6992771914930521,
    places: 5,
    feed: 6000,
    passes: 15,
};

/// The written time of each of `methods` for `p` at 0.05 mm (arcs, the
/// thesis' machine, the default, every feed at its maximum), each
/// verified.
fn written_at_max_feed(p: &Path, methods: &[&str]) -> Vec<f64> {
    written_times_at(&p.display().to_string(), p, (0.05, true), methods)
}

/// The written times of `methods` for `p` ([`written_at_max_feed`]),
/// with `auto`, the first, no slower than any other.
fn auto_no_slower_at_max_feed(p: &Path, methods: &[&str]) -> Vec<f64> {
    let t = written_at_max_feed(p, methods);
    for (m, &tm) in methods.iter().zip(&t).skip(1) {
        assert!(
            t[0] <= tm * (1.0 + TIE),
            "auto {:.4} s, slower than {m} {tm:.4} s",
            t[0]
        );
    }
    t
}

/// `r001_raster.ngc` (27 passes, 5,379 lines): `auto`'s ranking kept
/// `bspline-fit`, whose passes are written as G1 (they bend out of their
/// plane next to the step-overs, where helical arcs would kink), slower
/// than the run as written, so the run was kept as written: 15.930 s,
/// where `ctm` wrote 15.036 s and `bspline-corner` 15.072 s. Their curves
/// plan at twice that (a transition with its curvature ramps at every
/// vertex of a pass), so the ranking's bound never costed them. Where
/// the best would be kept as written, `auto` now costs every candidate.
#[test]
fn zigzag_raster_r001_auto_is_no_slower_than_the_corner_methods() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("r001_raster.ngc");
    std::fs::write(&p, RASTER_R001.program()).unwrap();
    let methods = ["auto", "ctm", "bspline-corner", "bspline-fit", "none"];
    let t = auto_no_slower_at_max_feed(&p, &methods);
    assert!(t[0] < t[4] * 0.99, "auto {:.4} s, none {:.4} s", t[0], t[4]);
}

/// `r005_raster.ngc` (15 passes, 1,013 lines): `bspline-corner`'s curves
/// plan about a third slower than its arcs, which beat every candidate
/// `auto` costed; the ranking's bound (the curves' time less
/// `RENDER_GAIN`, then 3%) never costed them, and `auto` was 0.85% slower
/// (8.145 s against 8.076 s).
#[test]
fn zigzag_raster_r005_auto_is_no_slower_than_bspline_corner() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("r005_raster.ngc");
    std::fs::write(&p, RASTER_R005.program()).unwrap();
    let methods = ["auto", "bspline-corner", "ctm"];
    auto_no_slower_at_max_feed(&p, &methods);
}
