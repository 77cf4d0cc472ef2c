//! What the fuzzer does with one input: G-code is parsed (both spline
//! readings), smoothed with the default method, feed-planned, written back
//! with several writer options and re-read, and written as JSON and
//! re-read; JSON is read with `read_json`, its curves evaluated, checked
//! against the original program as `fairpath check` does and feed-planned
//! as `fairpath simulate` does. A panic
//! anywhere is caught and reported with the stage it happened in; results
//! that are errors are fine, but output of our own writers that does not
//! read back is recorded as an anomaly.

use fairpath::choose::Auto;
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::geom::{Curve, ParamCurve};
use fairpath::path::{Piece, Run};
use fairpath::smooth::Smoother;
use fairpath::verify::{verify_run, VerifyOptions};
use fairpath_gcode::{
    parse, parse_with, read_json, write_gcode, write_json, ArcWords, GcodeWriteOptions,
    NurbsBlocks, ParseOptions, Program, SplineReading,
};
use std::cell::{Cell, RefCell};
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Mutex, Once};
use std::time::Instant;

/// The user's tolerance the fuzzer smooths to (mm), as in the brief.
pub const TOLERANCE_MM: f64 = 0.05;
/// The share of it written G-code may use (the CLI's default output share,
/// a tenth).
pub const CHORD_MM: f64 = 0.1 * TOLERANCE_MM;
/// Programs with more moves than this are parsed but not smoothed: it keeps
/// a run of thousands of inputs within a minute.
pub const MAX_SMOOTHED_MOVES: usize = 60;
/// Programs reaching farther than this from the origin (mm) are parsed but
/// not smoothed or checked: the verifier's refinement of a curve 1e297 mm
/// long runs for hours (see the report of issue 17; a hang, not a panic),
/// and no machine travels 10 km.
pub const MAX_SMOOTHED_EXTENT_MM: f64 = 1e7;
/// Programs whose feed path is longer than this (mm) are parsed but not
/// smoothed: smoothing time grows with length over tolerance, and a G2 of
/// radius 156 m (`R-6158` in an inch program) took 12 s, as long as
/// hundreds of ordinary inputs.
pub const MAX_SMOOTHED_LENGTH_MM: f64 = 5000.0;

thread_local! {
    static CAPTURING: Cell<bool> = const { Cell::new(false) };
    static CAUGHT: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// The stage the fuzzing thread is in (for panic reports and the hang
/// watchdog).
static STAGE: Mutex<&str> = Mutex::new("");

/// The stage the fuzzer is in now.
pub fn current_stage() -> &'static str {
    *STAGE.lock().unwrap_or_else(|e| e.into_inner())
}

/// A panic caught while exercising one input.
#[derive(Clone, Debug)]
pub struct Panic {
    pub stage: &'static str,
    /// `file:line:col: message` of the panic.
    pub message: String,
}

/// What one input gave.
#[derive(Debug, Default)]
pub struct Outcome {
    pub panic: Option<Panic>,
    /// Non-panic failures of our own round trips (text we wrote that does
    /// not read back), one line each.
    pub anomalies: Vec<String>,
    /// True when the input parsed (G-code) or read (JSON).
    pub accepted: bool,
}

/// Installs (once) a panic hook that records the panic of a thread that is
/// fuzzing instead of printing it, and defers to the previous hook for
/// every other thread.
pub fn install_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if CAPTURING.with(Cell::get) {
                let loc = info
                    .location()
                    .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()))
                    .unwrap_or_default();
                let msg = info
                    .payload()
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| info.payload().downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                CAUGHT.with(|c| *c.borrow_mut() = Some(format!("{loc}: {msg}")));
            } else {
                previous(info);
            }
        }));
    });
}

/// Time spent in each stage (s), and when the current stage began.
type StageTimes = (BTreeMap<&'static str, f64>, Option<Instant>);
static TIMES: Mutex<StageTimes> = Mutex::new((BTreeMap::new(), None));

fn stage(name: &'static str) {
    let mut st = STAGE.lock().unwrap_or_else(|e| e.into_inner());
    let mut times = TIMES.lock().unwrap_or_else(|e| e.into_inner());
    let now = Instant::now();
    if let Some(began) = times.1 {
        *times.0.entry(*st).or_insert(0.0) += (now - began).as_secs_f64();
    }
    times.1 = Some(now);
    *st = name;
}

/// Seconds spent in each stage so far, most first.
pub fn stage_times() -> Vec<(&'static str, f64)> {
    let times = TIMES.lock().unwrap_or_else(|e| e.into_inner());
    let mut v: Vec<_> = times.0.iter().map(|(k, t)| (*k, *t)).collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1));
    v
}

/// Runs `f` with panics caught and recorded in the outcome.
fn guarded(f: impl FnOnce(&mut Outcome)) -> Outcome {
    install_hook();
    let mut out = Outcome::default();
    CAPTURING.with(|c| c.set(true));
    stage("start");
    let r = catch_unwind(AssertUnwindSafe(|| f(&mut out)));
    CAPTURING.with(|c| c.set(false));
    if r.is_err() {
        out.panic = Some(Panic {
            stage: current_stage(),
            message: CAUGHT.with(|c| c.borrow_mut().take()).unwrap_or_default(),
        });
    }
    out
}

/// Parse, smooth, write and re-read one G-code input.
pub fn exercise_gcode(bytes: &[u8]) -> Outcome {
    guarded(|out| {
        stage("parse (exact splines)");
        let _ = parse_with(
            bytes,
            &ParseOptions {
                block_delete: false,
                splines: SplineReading::Exact,
            },
        );
        stage("parse");
        let Ok(program) = parse(bytes) else {
            return;
        };
        out.accepted = true;
        stage("runs");
        let runs = program.runs();
        let _ = program.pieces();
        let pieces = program.pieces();
        if program.moves().len() > MAX_SMOOTHED_MOVES
            || extent(&pieces) > MAX_SMOOTHED_EXTENT_MM
            || feed_length(&pieces) > MAX_SMOOTHED_LENGTH_MM
        {
            return;
        }
        let smoothed = smooth_runs(&runs);
        for pieces in &smoothed {
            plan(pieces);
        }
        write_and_reread(&program, &smoothed, out);
    })
}

/// Each run smoothed with the default method (`auto`) to the smoothing
/// share of [`TOLERANCE_MM`], and verified; a run the smoother refuses
/// keeps its own pieces.
fn smooth_runs(runs: &[Run]) -> Vec<Vec<Piece>> {
    let budget = TOLERANCE_MM - CHORD_MM;
    let method = Auto::default();
    runs.iter()
        .map(|run| {
            stage("smooth");
            match method.smooth_run(run, budget) {
                Ok(s) => {
                    stage("verify smoothed");
                    let _ = verify_run(&run.pieces, &s.pieces, &VerifyOptions::new(budget));
                    s.pieces
                }
                Err(_) => run.pieces.clone(),
            }
        })
        .collect()
}

/// The writer options the fuzzer writes with: G1 chords, arcs, and each
/// kind of NURBS block.
fn write_options() -> Vec<GcodeWriteOptions> {
    let base = GcodeWriteOptions {
        chord_mm: CHORD_MM,
        ..GcodeWriteOptions::default()
    };
    let mut all = vec![base.clone()];
    for arcs in [ArcWords::Ijk, ArcWords::R] {
        all.push(GcodeWriteOptions {
            arcs: Some(arcs),
            ..base.clone()
        });
    }
    for nurbs in [
        NurbsBlocks::G6_2Fanuc { max_degree: 3 },
        NurbsBlocks::G6_2Linuxcnc,
        NurbsBlocks::G5_2,
    ] {
        all.push(GcodeWriteOptions {
            arcs: Some(ArcWords::Ijk),
            nurbs: Some(nurbs),
            ..base.clone()
        });
    }
    all
}

fn write_and_reread(program: &Program, smoothed: &[Vec<Piece>], out: &mut Outcome) {
    for opts in write_options() {
        stage("write_gcode");
        let Ok(text) = write_gcode(program, smoothed, &opts) else {
            continue;
        };
        stage("parse written G-code");
        if let Err(e) = parse(text.as_bytes()) {
            out.anomalies.push(format!(
                "written G-code (arcs {:?}, nurbs {:?}) does not read back: {e}",
                opts.arcs, opts.nurbs
            ));
        }
    }
    stage("write_json");
    if let Ok(json) = write_json(program, smoothed) {
        stage("read written JSON");
        if let Err(e) = read_json(&json) {
            out.anomalies
                .push(format!("written JSON does not read back: {e}"));
        }
    }
}

/// Read one JSON input, evaluate its curves, and check it against
/// `original` (the program it was written from) as `fairpath check` does.
pub fn exercise_json(bytes: &[u8], original: Option<&Program>) -> Outcome {
    guarded(|out| {
        let Ok(text) = std::str::from_utf8(bytes) else {
            return;
        };
        stage("read_json");
        let Ok(pieces) = read_json(text) else {
            return;
        };
        out.accepted = true;
        stage("evaluate pieces");
        for p in &pieces {
            evaluate(&p.curve);
        }
        if extent(&pieces) <= MAX_SMOOTHED_EXTENT_MM
            && feed_length(&pieces) <= MAX_SMOOTHED_LENGTH_MM
        {
            for run in continuous_feeds(&pieces) {
                plan(&run);
            }
        }
        let Some(original) = original else {
            return;
        };
        if extent(&pieces) > MAX_SMOOTHED_EXTENT_MM {
            return;
        }
        let runs = original.runs();
        let grouped = group_by_source(&runs, &pieces);
        for (a, b) in runs.iter().zip(&grouped) {
            stage("check (verify_run)");
            let _ = verify_run(&a.pieces, &b.pieces, &VerifyOptions::new(TOLERANCE_MM));
        }
    })
}

/// Feed planning of one run, as `fairpath simulate` plans it (the
/// default machine, programmed feeds, whole-run look-ahead).
fn plan(pieces: &[Piece]) {
    stage("plan feed");
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    let _ = plan_run(pieces, &opts);
}

/// The runs `fairpath simulate` makes of JSON pieces: consecutive feed
/// pieces that join within 1 nm.
fn continuous_feeds(pieces: &[Piece]) -> Vec<Vec<Piece>> {
    let mut out: Vec<Vec<Piece>> = Vec::new();
    let mut cur: Vec<Piece> = Vec::new();
    for p in pieces {
        let breaks = p.rapid || cur.last().is_some_and(|q| q.end().dist(p.start()) > 1e-9);
        if breaks && !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
        if !p.rapid {
            cur.push(p.clone());
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Everything a consumer asks of a curve: points, derivatives, curvature,
/// length.
fn evaluate(c: &Curve) {
    let (a, b) = c.domain();
    for k in 0..=4 {
        let t = a + (b - a) * k as f64 / 4.0;
        let _ = c.eval(t);
        let _ = c.deriv1(t);
        let _ = c.deriv2(t);
        let _ = c.curvature(t);
    }
    let _ = c.start();
    let _ = c.end();
    let _ = c.length(1e-3);
}

/// The feed pieces of each original run, by the source lines they name
/// (as the CLI's `pipeline::group_by_source`, which `fairpath check` uses
/// for JSON).
fn group_by_source(original: &[Run], pieces: &[Piece]) -> Vec<Run> {
    original
        .iter()
        .map(|run| {
            let lo = run.pieces.first().map_or(0, |p| p.source_lines.0);
            let hi = run.pieces.last().map_or(0, |p| p.source_lines.1);
            Run::new(
                pieces
                    .iter()
                    .filter(|p| !p.rapid && p.source_lines.0 >= lo && p.source_lines.1 <= hi)
                    .cloned()
                    .collect(),
            )
        })
        .collect()
}

/// The largest coordinate (mm) the pieces reach: ends, arc centres plus
/// radii and rises, NURBS control points.
fn extent(pieces: &[Piece]) -> f64 {
    let norm = |v: fairpath::geom::Vec3| v.to_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    pieces
        .iter()
        .map(|p| {
            let ends = norm(p.curve.start()).max(norm(p.curve.end()));
            match &p.curve {
                Curve::Line(_) => ends,
                Curve::Arc(a) => {
                    ends.max(norm(a.center) + a.r0.abs().max(a.r1.abs()) + a.rise.abs())
                }
                Curve::Nurbs(n) => n.points.iter().fold(ends, |m, &q| m.max(norm(q))),
            }
        })
        .fold(
            0.0,
            |m: f64, x| if x.is_nan() { f64::INFINITY } else { m.max(x) },
        )
}

/// Length of the feed moves (mm), to 1 um.
fn feed_length(pieces: &[Piece]) -> f64 {
    pieces
        .iter()
        .filter(|p| !p.rapid)
        .map(|p| p.curve.length(1e-3))
        .sum()
}
