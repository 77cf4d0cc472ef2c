//! `fairpath report`: one self-contained HTML page (inline SVG and a few
//! lines of script, nothing fetched) with the three pictures a machinist
//! decides by, for the program as read and for what each method writes:
//!
//! 1. the path with the tolerance band, zoomable, corners of the original
//!    and the corners a method kept marked, one view per principal plane
//!    the path spans;
//! 2. curvature against arc length;
//! 3. the planned feed against time, and against arc length coloured by the
//!    constraint that limits it;
//!
//! and the summary table `smooth` prints. Everything drawn of a method is
//! of the program it writes, read back and planned as `fairpath simulate`
//! plans it (the times in the table are those plans).

mod chart;
mod page;
mod view;

use crate::read::read_program;
use crate::simulate_command::motions_of;
use crate::smooth::{option_error, options as smooth_options};
use crate::summary::Summary;
use crate::{Controller, Format};
use anyhow::{anyhow, Result};
use chart::{thin_indices, Chart, Series, Stretch};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::program::{simulate, Motion, Simulation};
use fairpath::geom::{flatten_params, ParamCurve, Vec3};
use fairpath::path::Piece;
use fairpath_gcode::pipeline::Phases;
use fairpath_gcode::{Evidence, SmoothOptions};
use std::path::Path;
use view::{Layer, Markers};

/// Points per chart series at most (about: twice the buckets of
/// [`chart::thin`]).
const CHART_BUCKETS: usize = 1500;

/// Largest turn (degrees) of the original at a vertex that is not marked
/// as a corner.
const CORNER_DEGREES: f64 = 5.0;

/// Least share of the feed length on moves that change height and move in
/// XY at once for which the XZ and YZ views are drawn (a 3D path, not the
/// plunges of a 2.5D one).
const SIDE_VIEW_SHARE: f64 = 0.05;

/// Curvature (1/mm) drawn for straight stretches on the logarithmic axis.
const CURVATURE_FLOOR: f64 = 1e-4;

/// Colours of the methods, in order, and of the original.
const METHOD_COLOURS: [&str; 7] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
];
const ORIGINAL_COLOUR: &str = "#444444";

/// The colour of each limiting constraint (and of rapids) in the feed
/// charts.
fn constraint_colour(name: &str) -> &'static str {
    match name {
        "feed" => "#2ca02c",
        "normal acceleration" => "#ff7f0e",
        "normal jerk" => "#d62728",
        "curvature change" => "#9467bd",
        "chord error" => "#7f7f7f",
        "axis velocity" => "#17becf",
        "axis acceleration" => "#1f77b4",
        "junction" => "#8c564b",
        "block time" => "#e377c2",
        _ => "#bbbbbb",
    }
}

/// What to put in the report.
pub struct ReportOptions {
    pub tolerance: f64,
    pub methods: Vec<String>,
    pub machine: MachineLimits,
    pub override_feed: bool,
    pub controller: Controller,
    pub format: Option<Format>,
    /// No progress line ([`crate::progress`]).
    pub quiet: bool,
}

/// What one method wrote, read back and planned (or why it could not).
struct MethodResult {
    name: String,
    outcome: Result<Written, String>,
}

struct Written {
    summary: Summary,
    motions: Vec<Motion>,
    sim: Simulation,
    kept: Vec<Vec3>,
    /// Curvature variation energy of the method's curves (1/mm^3, as
    /// `compare` reports it: the written arcs' curvature is piecewise
    /// constant, its steps are in the joints).
    energy: f64,
    /// Wall time of the smoothing alone (s).
    smoothing_s: f64,
}

/// Relative accuracy of the curvature variation energy (as `compare`).
const ENERGY_ACCURACY: f64 = 1e-3;

/// The report of the program at `path` as an HTML page.
pub fn report(path: &Path, opts: &ReportOptions) -> Result<String> {
    report_program(path, &read_program(path)?, opts)
}

/// [`report`] of a program read already (`path` names it).
pub fn report_program(
    path: &Path,
    program: &fairpath_gcode::Program,
    opts: &ReportOptions,
) -> Result<String> {
    let mut progress = crate::progress::Progress::start("planning the program", opts.quiet);
    let original = program.motions(&program.runs());
    let original_sim = simulate(&original, &opts.machine, opts.override_feed, None)
        .map_err(|e| anyhow!("{}: planning the program: {e}", path.display()))?;
    // Options checked for every method before any runs; a method whose
    // output fails (does not verify, cannot be planned) gets a row that
    // says why.
    // (The format `smooth` writes by default when none is asked.)
    let format = opts.format.unwrap_or_else(|| {
        let nurbs = fairpath_gcode::ProgramFacts::of(program).nurbs;
        opts.controller.default_format_for(nurbs)
    });
    let mut smooth_opts = Vec::new();
    for name in &opts.methods {
        let mut so = smooth_options(opts.tolerance, None, name, Some(format), opts.controller)?;
        so.set_machine(opts.machine, opts.override_feed)
            .map_err(option_error)?;
        smooth_opts.push(so);
    }
    let results: Vec<MethodResult> = opts
        .methods
        .iter()
        .zip(&smooth_opts)
        .map(|(name, so)| {
            progress.set(&format!("{name}: smoothing"));
            let clock = Phases::observed(progress.observer(&format!("{name}: ")));
            MethodResult {
                name: name.clone(),
                outcome: smooth_one(path, program, name, so, clock).map_err(|e| format!("{e:#}")),
            }
        })
        .collect();
    progress.set("drawing");
    let title = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    let mut sections = Vec::new();
    sections.push(("Summary", table(&results, &original_sim)));
    sections.push((
        "Path and tolerance band",
        path_views(&original, &results, opts.tolerance),
    ));
    sections.push((
        "Curvature along the path",
        curvature_chart(&original, &results).svg(),
    ));
    let (by_time, by_length) = feed_charts(&original_sim, &results);
    sections.push(("Planned feed against time", by_time.svg()));
    sections.push((
        "Planned feed against arc length, by limiting constraint",
        by_length
            .iter()
            .map(Chart::svg)
            .collect::<Vec<_>>()
            .join(""),
    ));
    let machine = &opts.machine;
    let subtitle = format!(
        "tolerance {} mm; machine V {} mm/s, A {} mm/s², J {} mm/s³, Ts {} ms{}; {}",
        opts.tolerance,
        machine.max_feed,
        machine.acc,
        machine.jerk,
        machine.period * 1e3,
        if machine.block_time > 0.0 {
            format!(", block time {} ms", machine.block_time * 1e3)
        } else {
            String::new()
        },
        if opts.override_feed {
            "feeds overridden to V"
        } else {
            "programmed feeds"
        }
    );
    progress.finish();
    Ok(page::page(&title, &subtitle, &sections))
}

/// Smooths, writes, reads back and plans the program with method `name`.
fn smooth_one(
    path: &Path,
    program: &fairpath_gcode::Program,
    name: &str,
    so: &SmoothOptions,
    clock: Phases,
) -> Result<Written> {
    let (output, report) =
        fairpath_gcode::smooth_parsed_with(program, so, clock).map_err(|e| anyhow!("{e}"))?;
    let written_name = Path::new("written");
    let motions = motions_of(written_name, output.text.as_bytes())?;
    let sim = simulate(&motions, so.machine(), so.override_feed(), None)
        .map_err(|e| anyhow!("planning what {name} wrote: {e}"))?;
    // What was written: a run kept as the program had it shows its own
    // corners and has no curves.
    let kept = (0..report.result.runs.len())
        .flat_map(|i| -> Vec<fairpath::geom::Vec3> {
            match report.kept_run_report(i) {
                Some(own) => own
                    .joints
                    .iter()
                    .filter(|j| j.class == fairpath::geom::Continuity::G0)
                    .map(|j| j.at)
                    .collect(),
                None => {
                    let kept = &report.result.runs[i].smoothed.kept_corners;
                    kept.iter().map(|k| k.at).collect()
                }
            }
        })
        .collect();
    let accuracy = so.tolerance() * fairpath_gcode::entry::LENGTH_ACCURACY_SHARE;
    let summary = Summary::new(path, written_name, so, &Evidence::of(&report, accuracy));
    let energy = report
        .result
        .runs
        .iter()
        .enumerate()
        .filter(|&(i, _)| !report.kept.get(i).copied().unwrap_or(false))
        .flat_map(|(_, r)| &r.smoothed.pieces)
        .filter(|p| !matches!(p.curve, fairpath::geom::Curve::Line(_)))
        .map(|p| fairpath::geom::curvature_variation_energy(&p.curve, ENERGY_ACCURACY))
        .sum();
    Ok(Written {
        smoothing_s: report.phases.duration("smooth").as_secs_f64(),
        summary,
        motions,
        sim,
        kept,
        energy,
    })
}

/// The summary table: one row for the program, one per method.
fn table(results: &[MethodResult], original: &Simulation) -> String {
    use chart::esc;
    let mut o = String::from(
        "<table><thead><tr><th>method</th><th>max deviation (mm)</th>\
         <th>joints C2 / C1 / C0</th><th>kept corners</th><th>length (mm)</th>\
         <th>peak curvature (1/mm)</th><th>curvature variation energy of the curves (1/mm³)</th>\
         <th>lines</th><th>planned time (s)</th><th>of the program</th>\
         <th>smoothing (s)</th></tr></thead><tbody>",
    );
    o.push_str(&format!(
        "<tr><td>program as read</td><td>0</td><td></td><td></td><td>{:.3}</td><td></td>\
         <td></td><td></td><td>{:.3}</td><td>1.000</td><td></td></tr>",
        original.feed_length,
        original.time()
    ));
    for r in results {
        match &r.outcome {
            Ok(w) => {
                let s = &w.summary;
                let kept = s.kept_total();
                o.push_str(&format!(
                    "<tr><td>{}</td><td>{:.6}</td><td>{} / {} / {}</td><td>{kept}</td>\
                     <td>{:.3}</td><td>{:.4}</td><td>{:.4e}</td><td>{}</td><td>{:.3}</td>\
                     <td>{:.3}</td><td>{:.3}</td></tr>",
                    esc(&r.name),
                    s.e.written.max_deviation,
                    s.e.joints[3],
                    s.e.joints[2],
                    s.e.joints[1],
                    s.e.length_after,
                    s.e.peak_curvature,
                    w.energy,
                    s.e.lines_out,
                    s.e.times.written.total,
                    s.e.times.written.total / s.e.times.input.total,
                    w.smoothing_s,
                ));
            }
            Err(e) => o.push_str(&format!(
                "<tr class=\"failed\"><td>{}</td><td colspan=\"10\">failed: {}</td></tr>",
                esc(&r.name),
                esc(e)
            )),
        }
    }
    o.push_str("</tbody></table>");
    o
}

/// Feed pieces of `motions` as polylines (one per run), each piece
/// flattened to `chord` mm, and the rapids.
fn polylines(motions: &[Motion], chord: f64) -> (Vec<Vec<Vec3>>, Vec<Vec<Vec3>>) {
    let (mut feed, mut rapids) = (Vec::new(), Vec::new());
    for m in motions {
        match m {
            Motion::Feed(run) => {
                let mut line: Vec<Vec3> = Vec::new();
                for p in &run.pieces {
                    flatten_into(p, chord, &mut line);
                }
                feed.push(line);
            }
            Motion::Rapid(p) => rapids.push(vec![p.start(), p.end()]),
        }
    }
    (feed, rapids)
}

fn flatten_into(p: &Piece, chord: f64, out: &mut Vec<Vec3>) {
    let c = &p.curve;
    for t in flatten_params(c, chord) {
        let q = c.eval(t);
        if out.last() != Some(&q) {
            out.push(q);
        }
    }
}

/// Vertices of the original's feed runs where the path turns by more than
/// [`CORNER_DEGREES`].
fn corners(motions: &[Motion]) -> Vec<Vec3> {
    let cos = CORNER_DEGREES.to_radians().cos();
    let mut out = Vec::new();
    for m in motions {
        if let Motion::Feed(run) = m {
            for w in run.pieces.windows(2) {
                let (a, b) = (&w[0].curve, &w[1].curve);
                if let (Some(u), Some(v)) = (a.unit_tangent(1.0), b.unit_tangent(0.0)) {
                    if u.dot(v) < cos {
                        out.push(b.start());
                    }
                }
            }
        }
    }
    out
}

/// Least slope (height over XY travel) of a move that counts as moving in
/// 3D: a hundredth, about half a degree.
const SPATIAL_SLOPE: f64 = 0.01;

/// Whether the feed moves of `motions` are a 3D path: at least
/// [`SIDE_VIEW_SHARE`] of their length on pieces that travel in XY by more
/// than a thousandth of `tolerance` and climb or descend at a slope of at
/// least [`SPATIAL_SLOPE`] (plunges, which do not travel in XY, and flat
/// moves do not count).
fn is_3d(motions: &[Motion], tolerance: f64) -> bool {
    let (mut spatial, mut total) = (0.0, 0.0);
    for m in motions {
        if let Motion::Feed(run) = m {
            for p in &run.pieces {
                let d = p.end() - p.start();
                let len = d.norm();
                total += len;
                let xy = d.x.hypot(d.y);
                if xy > 1e-3 * tolerance && d.z.abs() >= SPATIAL_SLOPE * xy {
                    spatial += len;
                }
            }
        }
    }
    total > 0.0 && spatial >= SIDE_VIEW_SHARE * total
}

/// One view per principal plane the path spans (XY always).
fn path_views(original: &[Motion], results: &[MethodResult], tolerance: f64) -> String {
    // Drawn to a twentieth of the tolerance, then thinned to a fiftieth:
    // far below what the band's width shows at any zoom that shows it.
    let chord = tolerance / 20.0;
    let simplify = |lines: Vec<Vec<Vec3>>| -> Vec<Vec<Vec3>> {
        lines
            .iter()
            .map(|l| view::simplify(l, tolerance / 50.0))
            .collect()
    };
    let (feed, rapids) = polylines(original, chord);
    let feed = simplify(feed);
    let mut layers = vec![
        Layer {
            label: format!("tolerance band (±{tolerance} mm)"),
            colour: "#f2c94c",
            class: "band",
            polylines: feed.clone(),
        },
        Layer {
            label: "rapids".into(),
            colour: "#999999",
            class: "rapid",
            polylines: rapids,
        },
        Layer {
            label: "program as read".into(),
            colour: ORIGINAL_COLOUR,
            class: "original",
            polylines: feed,
        },
    ];
    let mut markers = vec![Markers {
        label: format!("corners of the program (turn > {CORNER_DEGREES}°)"),
        colour: "#444444",
        points: corners(original),
    }];
    for (i, r) in results.iter().enumerate() {
        if let Ok(w) = &r.outcome {
            let colour = METHOD_COLOURS[i % METHOD_COLOURS.len()];
            layers.push(Layer {
                label: format!("{} (written)", r.name),
                colour,
                class: "written",
                polylines: simplify(polylines(&w.motions, chord).0),
            });
            if !w.kept.is_empty() {
                markers.push(Markers {
                    label: format!("corners {} kept", r.name),
                    colour: "#e31a1c",
                    points: w.kept.clone(),
                });
            }
        }
    }
    let three_d = is_3d(original, tolerance);
    let mut out = String::new();
    for plane in [view::XY, view::XZ, view::YZ] {
        if plane != view::XY && !three_d {
            continue;
        }
        out.push_str(&format!(
            "<h3>{} plane</h3>{}",
            plane.name,
            view::view_svg(
                &format!("view-{}", plane.name),
                plane,
                tolerance,
                &layers,
                &markers
            )
        ));
    }
    out
}

/// Curvature against arc length of the feed moves of `motions` (rapids
/// not counted): curves sampled where they are flattened to `chord`,
/// lines at the floor; where two lines meet, the discrete curvature of the
/// corner (its turning angle over the mean length of the two lines), the
/// curvature a path through the corner would have if it turned evenly
/// between the lines' midpoints.
fn curvature_points(motions: &[Motion], chord: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut s0 = 0.0;
    let acc = chord / 100.0;
    for m in motions {
        let Motion::Feed(run) = m else { continue };
        for (i, p) in run.pieces.iter().enumerate() {
            let c = &p.curve;
            let len = c.length(acc);
            if let (Some(prev), fairpath::geom::Curve::Line(_)) =
                (i.checked_sub(1).map(|j| &run.pieces[j]), c)
            {
                if let fairpath::geom::Curve::Line(_) = prev.curve {
                    if let (Some(u), Some(v)) = (prev.curve.unit_tangent(1.0), c.unit_tangent(0.0))
                    {
                        let angle = u.dot(v).clamp(-1.0, 1.0).acos();
                        let mean = 0.5 * (prev.curve.length(acc) + len);
                        if angle > 0.0 && mean > 0.0 {
                            out.push((s0, angle / mean));
                        }
                    }
                }
            }
            match c {
                fairpath::geom::Curve::Line(_) => {
                    out.push((s0, 0.0));
                    out.push((s0 + len, 0.0));
                }
                _ => {
                    let ts = flatten_params(c, chord);
                    let mut s = s0;
                    let mut prev = c.eval(0.0);
                    for t in ts {
                        let q = c.eval(t);
                        s += q.dist(prev);
                        prev = q;
                        out.push((s, c.curvature(t)));
                    }
                }
            }
            s0 += len;
        }
    }
    out
}

fn curvature_chart(original: &[Motion], results: &[MethodResult]) -> Chart {
    let chord = 1e-3;
    let thin = |pts: Vec<(f64, f64)>| chart::thin(&pts, CHART_BUCKETS);
    let mut series = vec![Series::plain(
        "program as read (corners: turn over mean length)",
        ORIGINAL_COLOUR,
        thin(curvature_points(original, chord)),
    )];
    series[0].dashed = true;
    for (i, r) in results.iter().enumerate() {
        if let Ok(w) = &r.outcome {
            series.push(Series::plain(
                &r.name,
                METHOD_COLOURS[i % METHOD_COLOURS.len()],
                thin(curvature_points(&w.motions, chord)),
            ));
        }
    }
    Chart {
        id: "curvature".into(),
        title: "Curvature of the feed moves".into(),
        x_label: "arc length of the feed moves (mm)".into(),
        y_label: "curvature (1/mm)".into(),
        series,
        keys: Vec::new(),
        log_y: true,
        log_floor: CURVATURE_FLOOR,
    }
}

/// Samples of a simulation's feed profile: (time, arc length along the feed
/// moves, speed, what limits it), a few per planned segment; rapids count
/// in time only.
fn feed_samples(sim: &Simulation) -> Vec<(f64, f64, f64, &'static str)> {
    const PER_SEGMENT: usize = 6;
    let mut out = Vec::new();
    let (mut t0, mut s0) = (0.0, 0.0);
    for (run, plan, rapid) in &sim.plans {
        if run.is_some() {
            for sg in &plan.segments {
                let d = sg.profile.duration();
                for k in 0..=PER_SEGMENT {
                    let t = d * k as f64 / PER_SEGMENT as f64;
                    let st = sg.profile.eval(t);
                    out.push((t0 + t, s0 + st.q, st.v, sg.constraint.as_str()));
                }
                t0 += d;
                s0 += sg.length;
            }
        } else if let Some((_, prof)) = rapid {
            let d = prof.duration();
            for k in 0..=PER_SEGMENT {
                let t = d * k as f64 / PER_SEGMENT as f64;
                out.push((t0 + t, s0, prof.eval(t).v, "rapid"));
            }
            t0 += d;
        }
    }
    out
}

/// Stretches of one colour from samples tagged with their colour, thinned
/// (neighbouring stretches share their boundary point).
fn coloured(points: &[(f64, f64)], colours: &[&'static str]) -> Vec<Stretch> {
    let keep = thin_indices(points, CHART_BUCKETS);
    let mut out: Vec<Stretch> = Vec::new();
    for i in keep {
        let (p, c) = (points[i], colours[i]);
        match out.last_mut() {
            Some(s) if s.colour == c => s.points.push(p),
            Some(s) => {
                let last = *s.points.last().expect("a stretch has points");
                out.push(Stretch {
                    colour: c,
                    points: vec![last, p],
                });
            }
            None => out.push(Stretch {
                colour: c,
                points: vec![p],
            }),
        }
    }
    out
}

fn feed_charts(original: &Simulation, results: &[MethodResult]) -> (Chart, Vec<Chart>) {
    let mut sims: Vec<(&str, &'static str, &Simulation)> =
        vec![("program as read", ORIGINAL_COLOUR, original)];
    for (i, r) in results.iter().enumerate() {
        if let Ok(w) = &r.outcome {
            sims.push((&r.name, METHOD_COLOURS[i % METHOD_COLOURS.len()], &w.sim));
        }
    }
    let mut by_time = Vec::new();
    let mut by_length = Vec::new();
    let mut used: Vec<&'static str> = Vec::new();
    for (k, (name, colour, sim)) in sims.iter().enumerate() {
        let samples = feed_samples(sim);
        let vt: Vec<(f64, f64)> = samples.iter().map(|s| (s.0, s.2)).collect();
        let mut series = Series::plain(name, colour, chart::thin(&vt, CHART_BUCKETS));
        series.dashed = k == 0;
        by_time.push(series);
        let feed: Vec<_> = samples.iter().filter(|s| s.3 != "rapid").collect();
        let vs: Vec<(f64, f64)> = feed.iter().map(|s| (s.1, s.2)).collect();
        let tags: Vec<&'static str> = feed.iter().map(|s| constraint_colour(s.3)).collect();
        for s in &feed {
            if !used.contains(&s.3) {
                used.push(s.3);
            }
        }
        by_length.push(Chart {
            id: format!("feed-length-{k}"),
            title: format!("{name}: {:.3} s", sim.time()),
            x_label: "arc length of the feed moves (mm)".into(),
            y_label: "feed (mm/s)".into(),
            series: vec![Series {
                label: String::new(),
                colour,
                stretches: coloured(&vs, &tags),
                dashed: false,
            }],
            keys: Vec::new(),
            log_y: false,
            log_floor: 0.0,
        });
    }
    used.sort_unstable();
    let keys: Vec<(&'static str, String)> = used
        .iter()
        .map(|c| (constraint_colour(c), (*c).to_string()))
        .collect();
    for c in &mut by_length {
        c.keys = keys.clone();
    }
    let time_chart = Chart {
        id: "feed-time".into(),
        title: "Planned feed (rapids included)".into(),
        x_label: "time (s)".into(),
        y_label: "feed (mm/s)".into(),
        series: by_time,
        keys: Vec::new(),
        log_y: false,
        log_floor: 0.0,
    };
    (time_chart, by_length)
}
