//! Whole-program planning, as `fairpath simulate` does it: plan a
//! jerk-limited feed along every move of a program (its motions: runs of
//! feed moves and rapids, in order) and report the machining time, the
//! largest acceleration and jerk used, and the constraint that limits each
//! segment; optionally the sampled profile as CSV ([`Simulation::csv`]).
//! The smoothing pipeline times the input, the curves and the written
//! program with it. The motions of a G-code program are made by
//! `fairpath-gcode` (`Program::motions`) on [`program_motions`].

use crate::feed::limits::MachineLimits;
use crate::feed::plan::{plan_rapid, plan_run, Corners, PlanOptions, RunPlan};
use crate::feed::windowed::{plan_time_in_windows, PlanWindows};
use crate::feed::FeedError;
use crate::path::{Piece, Run};
use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write as _;
use core::ops::Range;

/// What a program needs to be simulated: its feed runs and rapids in order.
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    Feed(Run),
    Rapid(Piece),
}

/// Largest gap (mm) between consecutive feed pieces that [`chain_motions`]
/// still counts as one run.
pub const CHAIN_GAP_MM: f64 = 1e-9;

/// The motions of a program: for fairpath's JSON, consecutive continuous
/// feed pieces (meeting within [`CHAIN_GAP_MM`]) as one run, each rapid on
/// its own.
pub fn chain_motions(pieces: Vec<Piece>) -> Vec<Motion> {
    let mut out = Vec::new();
    let mut cur: Vec<Piece> = Vec::new();
    for p in pieces {
        let breaks = p.rapid
            || cur
                .last()
                .is_some_and(|q| q.end().dist(p.start()) > CHAIN_GAP_MM);
        if breaks && !cur.is_empty() {
            out.push(Motion::Feed(Run::new(core::mem::take(&mut cur))));
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
    out
}

/// The motions of a program whose moves are `moves` (in order; `piece`
/// gives a move's piece), with the moves of each of `spans` (ranges of
/// move indices, in order) replaced by the run of the same index in `runs`
/// (the program's own runs, or smoothed ones); every other feed move (a
/// pinned one) is a motion of its own, every rapid too. Also returns the
/// index of each run's motion.
pub fn program_motions<M>(
    moves: &[M],
    piece: impl Fn(&M) -> &Piece,
    spans: &[Range<usize>],
    runs: &[Run],
) -> (Vec<Motion>, Vec<usize>) {
    let mut out = Vec::new();
    let mut index = Vec::with_capacity(runs.len());
    let mut next_run = 0;
    let mut mi = 0;
    while mi < moves.len() {
        if next_run < spans.len() && spans[next_run].start == mi {
            index.push(out.len());
            out.push(Motion::Feed(runs[next_run].clone()));
            mi = spans[next_run].end;
            next_run += 1;
            continue;
        }
        let p = piece(&moves[mi]);
        if p.rapid {
            out.push(Motion::Rapid(p.clone()));
        } else {
            out.push(Motion::Feed(Run::new(alloc::vec![p.clone()])));
        }
        mi += 1;
    }
    (out, index)
}

/// Why a program could not be planned: the feed planner's error, with the
/// motion it was planning.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProgramPlanError {
    /// A run of feed moves (its first input line).
    #[error("planning the run at line {line}")]
    Run {
        line: usize,
        #[source]
        source: FeedError,
    },
    /// A rapid.
    #[error("planning a rapid")]
    Rapid(#[source] FeedError),
}

/// One planned motion: a feed run and its plan, or a rapid and its profile.
pub type PlannedMotion = (Option<Run>, RunPlan, Option<(Piece, crate::feed::DoubleS)>);

/// The result of a simulation.
pub struct Simulation {
    pub feed_time: f64,
    /// Length of the feed moves, mm (as planned).
    pub feed_length: f64,
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
) -> Result<Simulation, ProgramPlanError> {
    let opts = PlanOptions {
        limits: *m,
        override_feed,
        window,
        ends: Default::default(),
    };
    simulate_with(motions, &opts)
}

/// [`simulate`] with every planning option given, e.g. runs that start
/// and end at their speed cap ([`crate::feed::plan::RunEnds::AtCap`], the
/// thesis' simulation).
pub fn simulate_with(
    motions: &[Motion],
    opts: &PlanOptions,
) -> Result<Simulation, ProgramPlanError> {
    simulate_each(motions.iter().cloned(), opts)
}

/// [`simulate_with`] of motions given up to it: their runs are moved into
/// the simulation's plans, not copied (a long program's pieces held once).
pub fn simulate_owned(
    motions: Vec<Motion>,
    opts: &PlanOptions,
) -> Result<Simulation, ProgramPlanError> {
    simulate_each(motions.into_iter(), opts)
}

fn simulate_each(
    motions: impl Iterator<Item = Motion>,
    opts: &PlanOptions,
) -> Result<Simulation, ProgramPlanError> {
    let m = &opts.limits;
    let opts = *opts;
    let mut sim = Simulation {
        feed_time: 0.0,
        feed_length: 0.0,
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
                    .map_err(|source| ProgramPlanError::Run { line, source })?;
                let time = run_time(&run.pieces, &opts, &plan)
                    .map_err(|source| ProgramPlanError::Run { line, source })?;
                sim.feed_time += time;
                sim.feed_length += plan.segments.iter().map(|s| s.length).sum::<f64>();
                sim.max_acc = sim.max_acc.max(plan.max_acc);
                sim.max_jerk = sim.max_jerk.max(plan.max_jerk);
                sim.segments += plan.segments.len();
                for s in &plan.segments {
                    *sim.limiting.entry(s.constraint.as_str()).or_default() += 1;
                }
                sim.plans.push((Some(run), plan, None));
            }
            Motion::Rapid(p) => {
                let len = p.curve.length(m.chord_error * 1e-3);
                if len.is_nan() || len <= 0.0 {
                    // One plan per motion, so that callers can index them.
                    sim.plans.push((None, RunPlan::default(), None));
                } else {
                    let prof = plan_rapid(len, m).map_err(ProgramPlanError::Rapid)?;
                    sim.rapid_time += prof.duration();
                    sim.max_acc = sim.max_acc.max(prof.alim_a()).max(prof.alim_d());
                    if prof.phases().tj1 > 0.0 {
                        sim.max_jerk = sim.max_jerk.max(m.jerk);
                    }
                    sim.plans.push((None, RunPlan::default(), Some((p, prof))));
                }
            }
        }
    }
    Ok(sim)
}

/// The planned time of a run whose whole plan is `plan`: the time of its
/// windows where it is planned in [`PlanWindows::DEFAULT`]
/// ([`plan_time_in_windows`]), else `plan`'s. A long run's time is its
/// windows' wherever fairpath times a run (the writer's check, `auto`'s
/// objective, the plans carried across a program's parts), so that every
/// figure of a program is the same plan's; the windows' time can differ
/// from the whole plan's (the module docs of [`super::windowed`], "Where
/// windows are not the whole plan"), the segments kept are the whole
/// plan's.
pub fn run_time(pieces: &[Piece], opts: &PlanOptions, plan: &RunPlan) -> Result<f64, FeedError> {
    Ok(
        plan_time_in_windows(pieces, opts, Corners::Blended, PlanWindows::DEFAULT)?
            .unwrap_or(plan.time),
    )
}

impl Simulation {
    pub fn time(&self) -> f64 {
        self.feed_time + self.rapid_time
    }

    /// Average feed over the feed moves, mm/s: their length over their
    /// time (the time average of the speed; the thesis' Table 4-2 reports
    /// an average whose definition it does not give).
    pub fn average_feed(&self) -> f64 {
        if self.feed_time > 0.0 {
            self.feed_length / self.feed_time
        } else {
            0.0
        }
    }

    pub fn text(&self, m: &MachineLimits) -> String {
        let mut s = String::new();
        let _ = write!(
            s,
            "machine: max feed {} mm/min, acc {} mm/s^2, jerk {} mm/s^3, period {} s",
            m.max_feed * 60.0,
            m.acc,
            m.jerk,
            m.period
        );
        if m.block_time > 0.0 {
            let _ = write!(s, ", block time {} s", m.block_time);
        }
        s.push('\n');
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
            .map(|(k, v)| alloc::format!("{v} {k}"))
            .collect();
        let _ = writeln!(
            s,
            "  segments:        {} (limited by: {})",
            self.segments,
            lim.join(", ")
        );
        s
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
        let mut end: Option<crate::Vec3> = None;
        let row = |out: &mut String, t: f64, s: f64, v: f64, a: f64, j: f64, p: crate::Vec3| {
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
                    // The fluctuation only: the samples are not kept.
                    let it = crate::feed::interpolate::interpolate_each(
                        &run.pieces,
                        plan,
                        period,
                        t0,
                        |_| {},
                    );
                    fmax = fmax.max(it.max);
                    if it.samples > 0 {
                        fsum += it.mean * it.samples as f64;
                        fn_ += it.samples;
                    }
                    if rows {
                        let phase = (next_k as f64 * period - t0).max(0.0);
                        let samples = crate::feed::stream::sample_run(
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

/// Average curvature of the feed moves of `motions`, 1/mm: their total
/// curvature ([`crate::geom::total_curvature`], each piece to `accuracy`
/// radians) over their length (each to `accuracy` mm); corners between
/// pieces count nothing. The thesis' measure of a path (seed 003, Table
/// 4-1). `None` without feed moves.
pub fn average_curvature(motions: &[Motion], accuracy: f64) -> Option<f64> {
    let (mut turning, mut length) = (0.0, 0.0);
    for mo in motions {
        if let Motion::Feed(run) = mo {
            for p in &run.pieces {
                turning += crate::geom::total_curvature(&p.curve, accuracy);
                length += p.curve.length(accuracy);
            }
        }
    }
    (length > 0.0).then(|| turning / length)
}
