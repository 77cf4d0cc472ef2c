//! `fairpath compare`: every smoothing method (and the untouched program as
//! the baseline) on one program, in one table.
//!
//! Each method smooths every run with the budget `smooth` gives it (the
//! tolerance less the output share), its curves are checked by the
//! independent verifier, its exact path is planned on the machine (as
//! `fairpath simulate` plans the JSON output), rapids included, and then
//! the program `smooth` writes in each asked format is planned the same
//! way: what a controller would run. The run loop, the planning and the
//! writing are the libraries' (`fairpath::pipeline`, `fairpath_gcode::pipeline`),
//! as for `smooth`; a method whose curves fail verification gets a row that
//! says so and no written programs.
//!
//! Every row also gives its time over the program's lower bound
//! (`fairpath::feed::lower_bound`: the least time any path within the
//! tolerance of the original can take under the same limits, rapids as
//! planned): `x bound`; and over the bound of the paths that follow the
//! original in order within the tolerance (`BandPaths::InOrder`, which a
//! closed contour or a raster of close passes needs: there a band path may
//! cut across), where the row's path passes that bound's gates in order
//! (`fairpath::verify::follows_in_order`, checked on the curves and on
//! each written program read back; the gates at the tolerance and at each
//! wider one the bound is also taken at, `BoundOptions::wider`): `x order`.

use crate::read::read_program;
use crate::smooth::{option_error, options as smooth_options};
use crate::{Controller, Format};
use anyhow::{anyhow, bail, Context, Result};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::lower_bound::{
    in_order_gates_of, piece_speed, program_lower_bound, BandPaths, BoundOptions, InOrderGates,
};
use fairpath::feed::program::simulate;
use fairpath::geom::{curvature_variation_energy, Curve};
use fairpath::path::{Piece, Run};
use fairpath::pipeline::verify_runs;
use fairpath::pipeline::PipelineError;
use fairpath::verify::{follows_in_order_within, RunReport, VerifyOptions};
use fairpath_gcode::pipeline::{plan_curves, smooth_curves, Phases, SmoothOptions, Times};
use fairpath_gcode::{write_curves, Curves, Program, SmoothProgramError};
use serde_json::json;
use std::fmt::Write as _;
use std::path::Path;

/// Share of the tolerance the flattening of a path's curves may take when
/// it is checked against the in-order gates: far below the gates' radius.
const GATE_CHECK_ACCURACY_SHARE: f64 = 1e-4;

/// Relative accuracy of the curvature variation energy in the table.
const ENERGY_ACCURACY: f64 = 1e-3;

/// One line of the table.
#[derive(Clone, Debug)]
pub struct Row {
    /// `original` for the baseline, else the method's name.
    pub method: String,
    /// Upper bound of the distance from the original (mm).
    pub max_deviation: f64,
    /// Whether every run verified: within the budget, endpoints exact.
    pub verified: bool,
    /// Joints by continuity class: gaps, C0 (corners), C1, C2.
    pub joints: [usize; 4],
    /// Feed path length (mm).
    pub length: f64,
    /// Largest curvature of the feed path's curves (1/mm; corners of the
    /// baseline are counted in `joints`, not here).
    pub peak_curvature: f64,
    /// Curvature variation energy of the feed path (1/mm^3).
    pub energy: f64,
    /// Planned machining time (s), feed moves and rapids.
    pub time: f64,
    /// The part of `time` spent on feed moves (s): rapids are the same for
    /// every method.
    pub feed_time: f64,
    /// `time` over the baseline's.
    pub time_ratio: f64,
    /// Wall time of the smoothing alone (s).
    pub smoothing_time: f64,
    /// The program's lower bound (s), the same on every row.
    pub lower_bound: f64,
    /// `time` over `lower_bound`.
    pub x_bound: f64,
    /// The bound of paths that follow the original in order (s), the same
    /// on every row.
    pub lower_bound_in_order: f64,
    /// Whether the curves pass that bound's gates in order (`None`: not
    /// checked, as for curves that failed verification).
    pub in_order: Option<bool>,
    /// `time` over `lower_bound_in_order` where `in_order`, else NaN.
    pub x_bound_in_order: f64,
    /// The program written in each asked format (none for the baseline).
    pub written: Vec<WrittenRow>,
}

/// The program `smooth` writes in one format, planned.
#[derive(Clone, Debug)]
pub struct WrittenRow {
    pub format: Format,
    /// Planned time (s) of the written program, and on feed moves.
    pub time: f64,
    pub feed_time: f64,
    /// `time` over the baseline's.
    pub time_ratio: f64,
    /// `time` over the program's lower bound.
    pub x_bound: f64,
    /// Whether the written program, read back, passes the in-order bound's
    /// gates in order (`None`: it could not be read back here).
    pub in_order: Option<bool>,
    /// `time` over the in-order bound where `in_order`, else NaN.
    pub x_bound_in_order: f64,
    /// Lines of the written program.
    pub lines: usize,
    /// Whether it read back within the tolerance.
    pub verified: bool,
}

/// What to compare.
pub struct CompareOptions {
    pub tolerance: f64,
    pub machine: MachineLimits,
    pub methods: Vec<String>,
    pub override_feed: bool,
    /// Formats to write and plan for each method.
    pub formats: Vec<Format>,
    pub controller: Controller,
}

/// The reports of `smoothed` verified against `original` at `budget`.
fn verify(original: &[Run], smoothed: &[Run], budget: f64) -> Vec<RunReport> {
    let pairs: Vec<(&[Piece], &[Piece])> = original
        .iter()
        .zip(smoothed)
        .map(|(a, b)| (a.pieces.as_slice(), b.pieces.as_slice()))
        .collect();
    verify_runs(&pairs, &VerifyOptions::new(budget))
}

fn row(
    method: &str,
    smoothed: &[Run],
    reports: &[RunReport],
    budget: f64,
    (time, feed_time): (f64, f64),
    smoothing_time: f64,
) -> Row {
    let mut joints = [0; 4];
    for r in reports {
        for (j, c) in joints.iter_mut().zip(r.joint_counts()) {
            *j += c;
        }
    }
    let acc = budget * 1e-4;
    let curves = || smoothed.iter().flat_map(|r| &r.pieces);
    Row {
        method: method.to_string(),
        max_deviation: reports.iter().map(|r| r.max_deviation).fold(0.0, f64::max),
        verified: reports.iter().all(|r| r.within(budget)),
        joints,
        length: curves()
            .map(|p| p.curve.length(acc))
            .fold(0.0, |a, b| a + b),
        peak_curvature: reports.iter().map(|r| r.peak_curvature).fold(0.0, f64::max),
        energy: curves()
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .map(|p| curvature_variation_energy(&p.curve, ENERGY_ACCURACY))
            .fold(0.0, |a, b| a + b),
        time,
        feed_time,
        time_ratio: 1.0,
        smoothing_time,
        lower_bound: f64::NAN,
        x_bound: f64::NAN,
        lower_bound_in_order: f64::NAN,
        in_order: None,
        x_bound_in_order: f64::NAN,
        written: Vec::new(),
    }
}

/// Runs the baseline and every method on the program at `path` (`-`:
/// standard input).
pub fn compare(path: &Path, opts: &CompareOptions) -> Result<Vec<Row>> {
    compare_program(path, &read_program(path)?, opts)
}

/// [`compare`] on a program read already (`path` names it in messages).
pub fn compare_program(path: &Path, program: &Program, opts: &CompareOptions) -> Result<Vec<Row>> {
    if program.is_empty() {
        bail!(
            "{}: the program has no moves: nothing to compare",
            crate::read::name(path)
        );
    }
    let runs = program.runs();
    // (total, feed moves only)
    let plan_time = |runs: &[Run]| -> Result<(f64, f64)> {
        let motions = program.motions(runs);
        let sim = simulate(&motions, &opts.machine, opts.override_feed, None)?;
        Ok((sim.time(), sim.feed_time))
    };
    let mut rows = Vec::new();
    let base_time = plan_time(&runs)?;
    let bound = program_lower_bound(
        &program.motions(&runs),
        &BoundOptions::new(opts.tolerance),
        &opts.machine,
        opts.override_feed,
    )
    .context("the lower bound")?
    .time;
    let in_order_opts = BoundOptions {
        paths: BandPaths::InOrder,
        ..BoundOptions::new(opts.tolerance)
    };
    let bound_in_order = program_lower_bound(
        &program.motions(&runs),
        &in_order_opts,
        &opts.machine,
        opts.override_feed,
    )
    .context("the in-order lower bound")?
    .time;
    let gates = RunGates::new(&runs, &in_order_opts, &opts.machine, opts.override_feed);
    let options = |name: &str, format: Format| -> Result<SmoothOptions> {
        let mut so = smooth_options(opts.tolerance, None, name, Some(format), opts.controller)?;
        so.set_machine(opts.machine, opts.override_feed)
            .map_err(option_error)?;
        Ok(so)
    };
    let budget0 = options("bspline-corner", Format::Json)?
        .budget()
        .smoothing();
    let reports = verify(&runs, &runs, budget0);
    rows.push(row("original", &runs, &reports, budget0, base_time, 0.0));
    rows[0].in_order = gates.followed_by(&runs);
    for name in &opts.methods {
        let so = options(name, Format::Json)?;
        let budget = so.budget().smoothing();
        let mut phases = Phases::new();
        // The library's run loop. Curves that fail verification are a row
        // that says so (and no written program: nothing is written from
        // them).
        let (result, verified) = match smooth_curves(program, &so, &mut phases) {
            Ok(result) => (result, true),
            Err(PipelineError::NotVerified { result, .. }) => (*result, false),
            Err(e) => return Err(anyhow::Error::new(e).context(format!("{name}: smoothing"))),
        };
        let smoothing_time = phases.duration("smooth").as_secs_f64();
        let smoothed: Vec<Run> = result
            .runs
            .iter()
            .map(|r| Run::new(r.smoothed.pieces.clone()))
            .collect();
        let (exact, plans) =
            plan_curves(program, &result, &so).with_context(|| format!("{name}: planning"))?;
        let reports: Vec<RunReport> = result.runs.iter().map(|r| r.report.clone()).collect();
        let mut r = row(
            name,
            &smoothed,
            &reports,
            budget,
            (exact.total, exact.feed),
            smoothing_time,
        );
        r.in_order = verified.then(|| gates.followed_by(&smoothed)).flatten();
        let curves = Curves {
            result,
            input: Times {
                total: base_time.0,
                feed: base_time.1,
            },
            exact,
            plans,
            memo: None,
        };
        for &format in opts.formats.iter().filter(|_| verified) {
            let fo = options(name, format)?;
            // `auto` ranks by what is written in the format: smoothed again
            // for it, as `smooth` would.
            let curves = if fo.smooths_for_format() {
                // (its objective's renderings kept for the writer)
                let memo = std::sync::Arc::new(fairpath_gcode::pipeline::RenderMemo::default());
                let facts = fairpath_gcode::ProgramFacts::of(program);
                let result = fairpath_gcode::pipeline::smooth_curves_memo(
                    program,
                    &facts,
                    &fo,
                    &mut Phases::new(),
                    Some(memo.clone()),
                )
                .with_context(|| format!("{name}: smoothing for the {} output", format.name()))?;
                let (exact, plans) = plan_curves(program, &result, &fo)
                    .with_context(|| format!("{name}: planning"))?;
                Curves {
                    result,
                    input: curves.input,
                    exact,
                    plans,
                    memo: Some(memo),
                }
            } else {
                curves.clone()
            };
            // Written, read back, verified and planned as `smooth` does;
            // a written program that does not verify is a row that says so.
            let (report, in_order) = match write_curves(program, curves, &fo, Phases::new()) {
                Ok((output, report)) => (report, gates.followed_by_text(&output.text, format)),
                Err(SmoothProgramError::OutputNotVerified { report, .. }) => (*report, None),
                Err(e @ SmoothProgramError::Plan(_)) => {
                    return Err(anyhow::Error::new(e)
                        .context(format!("{name}: planning the {} output", format.name())))
                }
                Err(e) => {
                    return Err(
                        anyhow::Error::new(e).context(format!("{name}: writing {}", format.name()))
                    )
                }
            };
            let t = report.times.written;
            r.written.push(WrittenRow {
                format,
                time: t.total,
                feed_time: t.feed,
                time_ratio: 1.0,
                x_bound: f64::NAN,
                in_order,
                x_bound_in_order: f64::NAN,
                lines: report.lines_out,
                verified: report.written.within,
            });
        }
        rows.push(r);
    }
    let base_time = base_time.0;
    if base_time.is_nan() || base_time <= 0.0 {
        return Err(anyhow!("the program takes no time to run"));
    }
    for r in &mut rows {
        r.time_ratio = r.time / base_time;
        r.lower_bound = bound;
        r.x_bound = r.time / bound;
        r.lower_bound_in_order = bound_in_order;
        let over = |t: f64, ok: Option<bool>| {
            if ok == Some(true) {
                t / bound_in_order
            } else {
                f64::NAN
            }
        };
        r.x_bound_in_order = over(r.time, r.in_order);
        for w in &mut r.written {
            w.time_ratio = w.time / base_time;
            w.x_bound = w.time / bound;
            w.x_bound_in_order = over(w.time, w.in_order);
        }
    }
    Ok(rows)
}

/// The in-order bound's gates of each run of the original, to check the
/// rows' paths against: at the tolerance and at each wider one the bound
/// also takes ([`BoundOptions::wider`]), a path passing them all in order.
struct RunGates<'a> {
    original: &'a [Run],
    gates: Vec<Vec<InOrderGates>>,
    machine: MachineLimits,
    override_feed: bool,
    accuracy: f64,
}

impl<'a> RunGates<'a> {
    fn new(
        original: &'a [Run],
        o: &BoundOptions,
        machine: &MachineLimits,
        override_feed: bool,
    ) -> Self {
        RunGates {
            original,
            gates: original
                .iter()
                .map(|r| {
                    o.tolerances()
                        .map(|tolerance| {
                            let o = BoundOptions { tolerance, ..*o };
                            in_order_gates_of(&r.pieces, &o, machine, override_feed)
                        })
                        .collect()
                })
                .collect(),
            machine: *machine,
            override_feed,
            accuracy: o.tolerance * GATE_CHECK_ACCURACY_SHARE,
        }
    }

    /// Whether every run of `path` (paired with the original's, zero-length
    /// runs left out) passes its run's gates in order; `None` where the
    /// runs do not pair.
    fn followed_by(&self, path: &[Run]) -> Option<bool> {
        let pairs = fairpath_gcode::pipeline::pair_runs(self.original, path).ok()?;
        Some(pairs.iter().all(|&(o, c)| {
            self.gates[o].iter().all(|g| {
                follows_in_order_within(
                    &path[c].pieces,
                    &g.gates,
                    &g.caps,
                    |p| piece_speed(p, &self.machine, self.override_feed),
                    self.accuracy,
                )
            })
        }))
    }

    /// [`RunGates::followed_by`] a written program, read back; `None`
    /// where it cannot be read here (JSON keeps no runs: its curves are
    /// the row's own, checked as such).
    fn followed_by_text(&self, text: &str, format: Format) -> Option<bool> {
        if format == Format::Json {
            return None;
        }
        let runs = fairpath_gcode::read_motion(text.as_bytes()).ok()?.1;
        self.followed_by(&runs)
    }
}

const HEADER: [&str; 19] = [
    "method",
    "max_deviation_mm",
    "verified",
    "gaps",
    "c0",
    "c1",
    "c2",
    "length_mm",
    "peak_curvature_per_mm",
    "curvature_variation_energy",
    "time_s",
    "feed_time_s",
    "time_ratio",
    "smoothing_s",
    "lower_bound_s",
    "x_bound",
    "lower_bound_in_order_s",
    "follows_in_order",
    "x_bound_in_order",
];

/// The formats written for the methods (the first method's list).
fn formats(rows: &[Row]) -> Vec<Format> {
    rows.iter()
        .find(|r| !r.written.is_empty())
        .map(|r| r.written.iter().map(|w| w.format).collect())
        .unwrap_or_default()
}

/// The `x order` cell: the ratio, or whether the path was not checked or
/// does not follow in order.
fn x_order(x: f64, in_order: Option<bool>) -> String {
    match in_order {
        Some(true) => format!("{x:.3}"),
        Some(false) => "no".to_string(),
        None => "-".to_string(),
    }
}

/// A CSV cell of an optional flag (empty where not checked).
fn opt_bool(b: Option<bool>) -> String {
    b.map(|b| b.to_string()).unwrap_or_default()
}

/// The table as aligned text.
pub fn text(rows: &[Row]) -> String {
    let mut out = String::new();
    let fmts = formats(rows);
    let _ = write!(
        out,
        "{:<16} {:>11} {:>4} {:>22} {:>12} {:>12} {:>12} {:>10} {:>10} {:>7} {:>7} {:>7} {:>10}",
        "method",
        "max dev mm",
        "ok",
        "joints C2/C1/C0/gap",
        "length mm",
        "peak k 1/mm",
        "energy",
        "time s",
        "feed s",
        "ratio",
        "x bound",
        "x order",
        "smooth s"
    );
    for f in &fmts {
        let _ = write!(
            out,
            " {:>10} {:>7} {:>7} {:>7} {:>8}",
            format!("{} s", f.name()),
            "ratio",
            "x bound",
            "x order",
            "lines"
        );
    }
    out.push('\n');
    for r in rows {
        let joints = format!(
            "{}/{}/{}/{}",
            r.joints[3], r.joints[2], r.joints[1], r.joints[0]
        );
        let _ = write!(
            out,
            "{:<16} {:>11.6} {:>4} {:>22} {:>12.4} {:>12.4} {:>12.4e} {:>10.3} {:>10.3} {:>7.3} {:>7.3} {:>7} {:>10.4}",
            r.method,
            r.max_deviation,
            if r.verified { "yes" } else { "NO" },
            joints,
            r.length,
            r.peak_curvature,
            r.energy,
            r.time,
            r.feed_time,
            r.time_ratio,
            r.x_bound,
            x_order(r.x_bound_in_order, r.in_order),
            r.smoothing_time
        );
        for w in &r.written {
            let _ = write!(
                out,
                " {:>10.3} {:>7.3} {:>7.3} {:>7} {:>8}{}",
                w.time,
                w.time_ratio,
                w.x_bound,
                x_order(w.x_bound_in_order, w.in_order),
                w.lines,
                if w.verified { "" } else { " NOT VERIFIED" }
            );
        }
        out.push('\n');
    }
    if let Some(r) = rows.first() {
        let _ = writeln!(
            out,
            "(lower bound {:.3} s: the least time of any path within the tolerance under the same limits; x bound: time over it)",
            r.lower_bound
        );
        let _ = writeln!(
            out,
            "(in-order bound {:.3} s: the same for paths that follow the original in order; x order: time over it, \"no\" where the path does not pass its gates in order)",
            r.lower_bound_in_order
        );
    }
    if !fmts.is_empty() {
        let _ = writeln!(
            out,
            "(time s: the exact curves; <format> s: the program smooth writes in that format, as simulate plans it; auto chooses again for each format, as smooth does: its joints, length, peak curvature and time s are those of its choice of exact curves, and the program it writes in a format may be another choice)"
        );
    }
    out
}

/// The table as CSV with a header row (written formats as
/// `written_<format>_time_s`, `_feed_time_s`, `_time_ratio`, `_lines`,
/// `_verified` columns).
pub fn csv(rows: &[Row]) -> String {
    let fmts = formats(rows);
    let mut out = HEADER.join(",");
    for f in &fmts {
        for c in [
            "time_s",
            "feed_time_s",
            "time_ratio",
            "x_bound",
            "lines",
            "verified",
            "follows_in_order",
            "x_bound_in_order",
        ] {
            let _ = write!(out, ",written_{}_{c}", f.name());
        }
    }
    out.push('\n');
    for r in rows {
        let _ = write!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.method,
            r.max_deviation,
            r.verified,
            r.joints[0],
            r.joints[1],
            r.joints[2],
            r.joints[3],
            r.length,
            r.peak_curvature,
            r.energy,
            r.time,
            r.feed_time,
            r.time_ratio,
            r.smoothing_time,
            r.lower_bound,
            r.x_bound,
            r.lower_bound_in_order,
            opt_bool(r.in_order),
            r.x_bound_in_order
        );
        for f in &fmts {
            match r.written.iter().find(|w| w.format == *f) {
                Some(w) => {
                    let _ = write!(
                        out,
                        ",{},{},{},{},{},{},{},{}",
                        w.time,
                        w.feed_time,
                        w.time_ratio,
                        w.x_bound,
                        w.lines,
                        w.verified,
                        opt_bool(w.in_order),
                        w.x_bound_in_order
                    );
                }
                None => out.push_str(",,,,,,,,"),
            }
        }
        out.push('\n');
    }
    out
}

/// The table as a JSON array of objects (keys as the CSV header; the
/// written programs under `written`).
pub fn json(rows: &[Row]) -> String {
    let v: Vec<_> = rows
        .iter()
        .map(|r| {
            json!({
                "method": r.method,
                "max_deviation_mm": r.max_deviation,
                "verified": r.verified,
                "gaps": r.joints[0],
                "c0": r.joints[1],
                "c1": r.joints[2],
                "c2": r.joints[3],
                "length_mm": r.length,
                "peak_curvature_per_mm": r.peak_curvature,
                "curvature_variation_energy": r.energy,
                "time_s": r.time,
                "feed_time_s": r.feed_time,
                "time_ratio": r.time_ratio,
                "smoothing_s": r.smoothing_time,
                "lower_bound_s": r.lower_bound,
                "x_bound": r.x_bound,
                "lower_bound_in_order_s": r.lower_bound_in_order,
                "follows_in_order": r.in_order,
                "x_bound_in_order": r.x_bound_in_order,
                "written": r.written.iter().map(|w| json!({
                    "format": w.format.name(),
                    "time_s": w.time,
                    "feed_time_s": w.feed_time,
                    "time_ratio": w.time_ratio,
                    "x_bound": w.x_bound,
                    "lines": w.lines,
                    "verified": w.verified,
                    "follows_in_order": w.in_order,
                    "x_bound_in_order": w.x_bound_in_order,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    serde_json::to_string_pretty(&v).expect("rows serialise")
}
