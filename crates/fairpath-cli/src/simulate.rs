//! `fairpath simulate`: plan a jerk-limited feed along every move of a
//! program (G-code or fairpath JSON) and report the machining time, the
//! largest acceleration and jerk used, and the constraint that limits each
//! segment; optionally the sampled profile as CSV.

use anyhow::{anyhow, bail, Context, Result};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_rapid, plan_run, PlanOptions, RunPlan};
use fairpath::path::{Piece, Run};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// A machine file (TOML). Feeds in mm/min as G-code writes them, the rest
/// in mm and s. Missing keys keep the defaults (the thesis machine).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineFile {
    pub max_feed: Option<f64>,
    pub acc: Option<f64>,
    pub normal_acc: Option<f64>,
    pub jerk: Option<f64>,
    pub period: Option<f64>,
    pub chord_error: Option<f64>,
    /// Junction deviation for corners of G1 moves, mm.
    pub junction_deviation: Option<f64>,
    /// Per-axis velocity limits, mm/min.
    pub axis_feed: Option<[f64; 3]>,
    /// Per-axis acceleration limits, mm/s^2.
    pub axis_acc: Option<[f64; 3]>,
    /// Whether the jerk limit caps the speed on curves (default true;
    /// false: the thesis' time model, see `MachineLimits::jerk_on_curves`).
    pub jerk_on_curves: Option<bool>,
    /// Per-axis jerk limits, mm/s^3 (`fairpath stream`; default: the
    /// path's jerk).
    pub axis_jerk: Option<[f64; 3]>,
}

/// Flags that override the machine file.
#[derive(Debug, Default, Clone, Copy)]
pub struct MachineFlags {
    pub max_feed: Option<f64>,
    pub acc: Option<f64>,
    pub jerk: Option<f64>,
    pub period: Option<f64>,
    pub junction_deviation: Option<f64>,
    /// `Some(false)`: the thesis' time model (no jerk caps on curves).
    pub jerk_on_curves: Option<bool>,
}

/// The machine: defaults (the thesis' V 400 mm/s, A 4000 mm/s^2, J 20000
/// mm/s^3, Ts 1 ms), then the file, then the flags. Every limit is checked.
pub fn machine(file: Option<&Path>, flags: MachineFlags) -> Result<MachineLimits> {
    let mut m = MachineLimits::thesis();
    if let Some(f) = file {
        let text =
            std::fs::read_to_string(f).with_context(|| format!("cannot read {}", f.display()))?;
        let mf: MachineFile = toml::from_str(&text).map_err(|e| anyhow!("{}: {e}", f.display()))?;
        if let Some(v) = mf.max_feed {
            m.max_feed = v / 60.0;
            m.axis_vel = [m.max_feed; 3];
        }
        if let Some(v) = mf.acc {
            m.acc = v;
            m.normal_acc = v;
            m.axis_acc = [v; 3];
        }
        if let Some(v) = mf.normal_acc {
            m.normal_acc = v;
        }
        if let Some(v) = mf.jerk {
            m.jerk = v;
        }
        if let Some(v) = mf.period {
            m.period = v;
        }
        if let Some(v) = mf.chord_error {
            m.chord_error = v;
        }
        if let Some(v) = mf.junction_deviation {
            m.junction_deviation = v;
        }
        if let Some(v) = mf.axis_feed {
            m.axis_vel = v.map(|x| x / 60.0);
        }
        if let Some(v) = mf.axis_acc {
            m.axis_acc = v;
        }
        if let Some(v) = mf.jerk_on_curves {
            m.jerk_on_curves = v;
        }
    }
    if let Some(v) = flags.max_feed {
        m.max_feed = v / 60.0;
        m.axis_vel = m.axis_vel.map(|a| a.max(m.max_feed));
    }
    if let Some(v) = flags.acc {
        m.acc = v;
        m.normal_acc = v;
        m.axis_acc = m.axis_acc.map(|a| a.max(v));
    }
    if let Some(v) = flags.jerk {
        m.jerk = v;
    }
    if let Some(v) = flags.period {
        m.period = v;
    }
    if let Some(v) = flags.junction_deviation {
        m.junction_deviation = v;
    }
    if let Some(v) = flags.jerk_on_curves {
        m.jerk_on_curves = v;
    }
    m.validate().map_err(|e| anyhow!("{e}"))?;
    Ok(m)
}

/// What a program needs to be simulated: its feed runs and rapids in order.
pub enum Motion {
    Feed(Run),
    Rapid(Piece),
}

/// The motions of a program: G-code runs (and each pinned move on its
/// own), or, for JSON, consecutive continuous feed pieces.
pub fn motions(path: &Path) -> Result<Vec<Motion>> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    motions_of(path, &bytes)
}

/// [`motions`] of a program's text (`path` names it in errors).
pub fn motions_of(path: &Path, bytes: &[u8]) -> Result<Vec<Motion>> {
    let is_json = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    let mut out = Vec::new();
    if is_json {
        let text =
            std::str::from_utf8(bytes).map_err(|_| anyhow!("{}: not UTF-8", path.display()))?;
        let pieces =
            fairpath_gcode::read_json(text).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        let mut cur: Vec<Piece> = Vec::new();
        for p in pieces {
            let breaks = p.rapid || cur.last().is_some_and(|q| q.end().dist(p.start()) > 1e-9);
            if breaks && !cur.is_empty() {
                out.push(Motion::Feed(Run::new(std::mem::take(&mut cur))));
            }
            if p.rapid {
                out.push(Motion::Rapid(p));
            } else {
                cur.push(p);
            }
        }
        if !cur.is_empty() {
            out.push(Motion::Feed(Run::new(cur)));
        }
    } else {
        let program = crate::pipeline::parse_program(path, bytes)?;
        out = gcode_motions(&program, &program.runs());
    }
    Ok(out)
}

/// The motions of a G-code program with its runs replaced by `runs` (the
/// program's own, or smoothed ones, in the order of `Program::runs`);
/// pinned feed moves are motions of their own.
pub fn gcode_motions(program: &fairpath_gcode::Program, runs: &[Run]) -> Vec<Motion> {
    gcode_motions_indexed(program, runs).0
}

/// [`gcode_motions`], and the index of each run's motion.
pub fn gcode_motions_indexed(
    program: &fairpath_gcode::Program,
    runs: &[Run],
) -> (Vec<Motion>, Vec<usize>) {
    let mut out = Vec::new();
    let mut index = Vec::with_capacity(runs.len());
    let spans = program.run_spans();
    let mut next_run = 0;
    let mut mi = 0;
    let moves = program.moves();
    while mi < moves.len() {
        if next_run < spans.len() && spans[next_run].moves.start == mi {
            index.push(out.len());
            out.push(Motion::Feed(runs[next_run].clone()));
            mi = spans[next_run].moves.end;
            next_run += 1;
            continue;
        }
        let m = &moves[mi];
        if m.piece.rapid {
            out.push(Motion::Rapid(m.piece.clone()));
        } else {
            out.push(Motion::Feed(Run::new(vec![m.piece.clone()])));
        }
        mi += 1;
    }
    (out, index)
}

/// One planned motion: a feed run and its plan, or a rapid and its profile.
pub type PlannedMotion = (
    Option<Run>,
    RunPlan,
    Option<(Piece, fairpath::feed::DoubleS)>,
);

/// The result of a simulation.
pub struct Simulation {
    pub feed_time: f64,
    pub rapid_time: f64,
    pub max_acc: f64,
    pub max_jerk: f64,
    pub segments: usize,
    pub limiting: BTreeMap<&'static str, usize>,
    /// One per motion, in order.
    pub plans: Vec<PlannedMotion>,
    /// With a bounded look-ahead: the time the full scan would take.
    pub full_scan_time: Option<f64>,
    /// Feed fluctuation of the interpolator: (largest, mean), as fractions.
    pub fluctuation: Option<(f64, f64)>,
}

/// Plans every motion.
/// `window`: bounded look-ahead of that many segments (`None`: whole run).
pub fn simulate(
    motions: &[Motion],
    m: &MachineLimits,
    override_feed: bool,
    window: Option<usize>,
) -> Result<Simulation> {
    let opts = PlanOptions {
        limits: *m,
        override_feed,
        window,
    };
    let mut sim = Simulation {
        feed_time: 0.0,
        rapid_time: 0.0,
        max_acc: 0.0,
        max_jerk: 0.0,
        segments: 0,
        limiting: BTreeMap::new(),
        plans: Vec::new(),
        full_scan_time: None,
        fluctuation: None,
    };
    for mo in motions {
        match mo {
            Motion::Feed(run) => {
                let line = run.pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
                let plan = plan_run(&run.pieces, &opts)
                    .map_err(|e| anyhow!("planning the run at line {line}: {e}"))?;
                sim.feed_time += plan.time;
                sim.max_acc = sim.max_acc.max(plan.max_acc);
                sim.max_jerk = sim.max_jerk.max(plan.max_jerk);
                sim.segments += plan.segments.len();
                for s in &plan.segments {
                    *sim.limiting.entry(s.constraint.as_str()).or_default() += 1;
                }
                sim.plans.push((Some(run.clone()), plan, None));
            }
            Motion::Rapid(p) => {
                let len = p.curve.length(1e-6);
                if len.is_nan() || len <= 0.0 {
                    // One plan per motion, so that callers can index them.
                    sim.plans.push((None, RunPlan::default(), None));
                } else {
                    let prof = plan_rapid(len, m).map_err(|e| anyhow!("planning a rapid: {e}"))?;
                    sim.rapid_time += prof.duration();
                    sim.max_acc = sim.max_acc.max(prof.alim_a()).max(prof.alim_d());
                    if prof.phases().tj1 > 0.0 {
                        sim.max_jerk = sim.max_jerk.max(m.jerk);
                    }
                    sim.plans
                        .push((None, RunPlan::default(), Some((p.clone(), prof))));
                }
            }
        }
    }
    Ok(sim)
}

impl Simulation {
    pub fn time(&self) -> f64 {
        self.feed_time + self.rapid_time
    }

    pub fn text(&self, m: &MachineLimits) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "machine: max feed {} mm/min, acc {} mm/s^2, jerk {} mm/s^3, period {} s",
            m.max_feed * 60.0,
            m.acc,
            m.jerk,
            m.period
        );
        let _ = writeln!(
            s,
            "  time:            {:.4} s ({:.4} s feed, {:.4} s rapid)",
            self.time(),
            self.feed_time,
            self.rapid_time
        );
        let _ = writeln!(s, "  max |a|:         {:.3} mm/s^2", self.max_acc);
        let _ = writeln!(s, "  max |j|:         {:.3} mm/s^3", self.max_jerk);
        if let Some((a, b)) = self.fluctuation {
            let _ = writeln!(
                s,
                "  feed fluctuation: {:.4}% max, {:.4}% mean (interpolator)",
                100.0 * a,
                100.0 * b
            );
        }
        if let Some(f) = self.full_scan_time {
            let _ = writeln!(
                s,
                "  look-ahead cost: {:.4} s more than the full scan ({:.4} s, +{:.2}%)",
                self.time() - f,
                f,
                100.0 * (self.time() / f - 1.0)
            );
        }
        let lim: Vec<String> = self
            .limiting
            .iter()
            .map(|(k, v)| format!("{v} {k}"))
            .collect();
        let _ = writeln!(
            s,
            "  segments:        {} (limited by: {})",
            self.segments,
            lim.join(", ")
        );
        s
    }

    pub fn json(&self) -> String {
        serde_json::json!({
            "time_s": self.time(),
            "feed_time_s": self.feed_time,
            "rapid_time_s": self.rapid_time,
            "max_acc": self.max_acc,
            "max_jerk": self.max_jerk,
            "segments": self.segments,
            "limiting": self.limiting,
            "full_scan_time_s": self.full_scan_time,
            "feed_fluctuation_max": self.fluctuation.map(|f| f.0),
            "feed_fluctuation_mean": self.fluctuation.map(|f| f.1),
        })
        .to_string()
    }

    /// The motion sampled every period of `m` on one clock from the start
    /// (`t,s,v,a,j,x,y,z`: sample `k` at `k Ts`, positions exact in arc
    /// length as `fairpath stream` samples them, rapids along their line,
    /// the last row at the end; empty unless `rows`), and the feed
    /// fluctuation of the second-order Taylor interpolator (`interpolate`):
    /// (largest, mean).
    pub fn csv(&self, m: &MachineLimits, rows: bool) -> (String, f64, f64) {
        let period = m.period;
        let accuracy = m.chord_error * 1e-4;
        let mut out = String::from("t,s,v,a,j,x,y,z\n");
        let (mut t0, mut s0) = (0.0f64, 0.0f64);
        let (mut fmax, mut fsum, mut fn_) = (0.0f64, 0.0f64, 0usize);
        let mut next_k = 0usize;
        let mut end: Option<fairpath::Vec3> = None;
        let row = |out: &mut String, t: f64, s: f64, v: f64, a: f64, j: f64, p: fairpath::Vec3| {
            if !rows {
                return;
            }
            let _ = writeln!(
                out,
                "{t:.6},{s:.6},{v:.6},{a:.6},{j:.6},{:.6},{:.6},{:.6}",
                p.x, p.y, p.z
            );
        };
        for (run, plan, rapid) in &self.plans {
            match (run, rapid) {
                (Some(run), _) => {
                    let it =
                        fairpath::feed::interpolate::interpolate(&run.pieces, plan, period, t0);
                    fmax = fmax.max(it.max_fluctuation);
                    if !it.samples.is_empty() {
                        fsum += it.mean_fluctuation * it.samples.len() as f64;
                        fn_ += it.samples.len();
                    }
                    if rows {
                        let phase = (next_k as f64 * period - t0).max(0.0);
                        let samples = fairpath::feed::stream::sample_run(
                            &run.pieces,
                            plan,
                            accuracy,
                            phase,
                            period,
                        );
                        for smp in &samples {
                            let st = smp.state;
                            row(&mut out, t0 + smp.t, s0 + smp.s, st.v, st.a, st.j, smp.p);
                        }
                        next_k += samples.len();
                    }
                    t0 += plan.time;
                    s0 += plan.segments.iter().map(|s| s.length).sum::<f64>();
                    if let Some(p) = run.pieces.last() {
                        end = Some(p.end());
                    }
                }
                (None, Some((p, prof))) => {
                    let (d, len) = (prof.duration(), prof.length());
                    while rows && (next_k as f64) * period < t0 + d {
                        let t = next_k as f64 * period;
                        let st = prof.eval(t - t0);
                        let at = p.start().lerp(p.end(), (st.q / len).clamp(0.0, 1.0));
                        row(&mut out, t, s0 + st.q, st.v, st.a, st.j, at);
                        next_k += 1;
                    }
                    t0 += d;
                    s0 += len;
                    end = Some(p.end());
                }
                _ => {}
            }
        }
        if let Some(p) = end {
            row(&mut out, next_k as f64 * period, s0, 0.0, 0.0, 0.0, p);
        }
        let mean = if fn_ > 0 { fsum / fn_ as f64 } else { 0.0 };
        (out, fmax, mean)
    }
}

impl Simulation {
    /// One row per planned segment of the feed runs, in order:
    /// `s0,length,cap,constraint,v_in,v_out,time` (mm, mm, mm/s, name,
    /// mm/s, mm/s, s), `s0` the arc length at the segment start counted over
    /// all feed runs.
    pub fn segments_csv(&self) -> String {
        let mut out = String::from("s0,length,cap,constraint,v_in,v_out,time\n");
        let mut s0 = 0.0;
        for (run, plan, _) in &self.plans {
            if run.is_none() {
                continue;
            }
            for sg in &plan.segments {
                let _ = writeln!(
                    out,
                    "{s0:.6},{:.6},{:.6},{},{:.6},{:.6},{:.6}",
                    sg.length,
                    sg.cap,
                    sg.constraint.as_str(),
                    sg.profile.v0(),
                    sg.profile.v1(),
                    sg.profile.duration()
                );
                s0 += sg.length;
            }
        }
        out
    }
}

/// Most interpolation periods `simulate` samples (for the profile and the
/// feed fluctuation): 1e8 periods of 1 ms is more than a day of machining.
pub const MAX_SAMPLES: f64 = 1e8;

/// `fairpath simulate`.
pub fn run(
    path: &Path,
    m: &MachineLimits,
    override_feed: bool,
    window: Option<usize>,
    profile: Option<&Path>,
    segments: Option<&Path>,
    json: bool,
) -> Result<()> {
    let motions = motions(path)?;
    if motions.is_empty() {
        // Tool changes, coolant ...: nothing to plan, a time of zero.
        eprintln!("note: {}: the program has no moves", path.display());
    }
    let mut sim = simulate(&motions, m, override_feed, window)?;
    if window.is_some() {
        sim.full_scan_time = Some(simulate(&motions, m, override_feed, None)?.time());
    }
    // One sample per period: refuse absurd counts rather than run out of
    // memory (a program of hours at 1 ms).
    let samples = sim.time() / m.period;
    if samples <= MAX_SAMPLES {
        let (csv, fmax, fmean) = sim.csv(m, profile.is_some());
        sim.fluctuation = Some((fmax, fmean));
        if let Some(p) = profile {
            crate::output::write_atomically(p, csv.as_bytes())?;
        }
    } else if profile.is_some() {
        bail!(
            "the profile would have {samples:.0} rows (more than {MAX_SAMPLES:.0}); use a longer --period"
        );
    }
    if let Some(p) = segments {
        crate::output::write_atomically(p, sim.segments_csv().as_bytes())?;
    }
    if json {
        println!("{}", sim.json());
    } else {
        print!("fairpath simulate: {}\n{}", path.display(), sim.text(m));
    }
    Ok(())
}
