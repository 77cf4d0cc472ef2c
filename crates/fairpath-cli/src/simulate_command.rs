//! `fairpath simulate`: plan a jerk-limited feed along every move of a
//! program (G-code or fairpath JSON) and report the machining time, the
//! largest acceleration and jerk used, and the constraint that limits each
//! segment; optionally the sampled profile as CSV. The planning is the
//! library's ([`fairpath::feed::program`]); this reads the file and prints.

use anyhow::{anyhow, bail, Result};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{PlanOptions, RunEnds};
use fairpath::feed::program::{
    average_curvature, simulate_owned, simulate_with, Motion, Simulation, MAX_SAMPLES,
};
use std::path::Path;

/// The motions of a program: G-code runs (and each pinned move on its
/// own), or, for JSON, consecutive continuous feed pieces.
pub fn motions(path: &Path) -> Result<Vec<Motion>> {
    let bytes = crate::read::read_bytes(path)?;
    motions_of(path, &bytes)
}

/// [`motions`] of a program's text (`path` names it in errors).
pub fn motions_of(path: &Path, bytes: &[u8]) -> Result<Vec<Motion>> {
    let is_json = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    if is_json {
        let text = std::str::from_utf8(bytes)
            .map_err(|_| anyhow!("{}: not UTF-8", crate::read::name(path)))?;
        fairpath_gcode::json_motions(text).map_err(|e| anyhow!("{}: {e}", crate::read::name(path)))
    } else {
        // Its motion only: a long program's lines are not held.
        let (outline, runs) = crate::read::read_motion_of(path, bytes)?;
        Ok(fairpath_gcode::outline_motions(outline, runs))
    }
}

/// Accuracy of the average curvature's integrals (radians and mm).
const CURVATURE_ACCURACY: f64 = 1e-6;

/// The simulation as JSON (at least `time_s`, `feed_time_s`, `max_acc`,
/// `max_jerk`), with the average curvature of the feed moves (1/mm).
pub fn simulation_json(sim: &Simulation, average_curvature: Option<f64>) -> String {
    serde_json::json!({
        "time_s": sim.time(),
        "feed_time_s": sim.feed_time,
        "feed_length_mm": sim.feed_length,
        "average_feed_mm_s": sim.average_feed(),
        "average_curvature_per_mm": average_curvature,
        "rapid_time_s": sim.rapid_time,
        "max_acc": sim.max_acc,
        "max_jerk": sim.max_jerk,
        "segments": sim.segments,
        "limiting": sim.limiting,
        "full_scan_time_s": sim.full_scan_time,
        "feed_fluctuation_max": sim.fluctuation.map(|f| f.0),
        "feed_fluctuation_mean": sim.fluctuation.map(|f| f.1),
    })
    .to_string()
}

/// `fairpath simulate`: runs start and end as `ends` says.
#[allow(clippy::too_many_arguments)]
pub fn run(
    path: &Path,
    m: &MachineLimits,
    override_feed: bool,
    ends: RunEnds,
    window: Option<usize>,
    profile: Option<&Path>,
    segments: Option<&Path>,
    json: bool,
) -> Result<()> {
    let motions = motions(path)?;
    if motions.is_empty() {
        // Tool changes, coolant ...: nothing to plan, a time of zero.
        eprintln!(
            "note: {}: the program has no moves",
            crate::read::name(path)
        );
    }
    let opts = PlanOptions {
        limits: *m,
        override_feed,
        window,
        ends,
    };
    // The full scan's time and the curvature first: the simulation then
    // takes the motions (a long program's pieces held once, not twice).
    let full_scan_time = match window {
        Some(_) => {
            let full = PlanOptions {
                window: None,
                ..opts
            };
            Some(simulate_with(&motions, &full)?.time())
        }
        None => None,
    };
    let curvature = average_curvature(&motions, CURVATURE_ACCURACY);
    let mut sim = simulate_owned(motions, &opts)?;
    sim.full_scan_time = full_scan_time;
    // One sample per period: refuse absurd counts rather than run out of
    // memory (a program of hours at 1 ms).
    let samples = sim.time() / m.period;
    if samples <= MAX_SAMPLES {
        let (csv, fmax, fmean) = sim.csv(m, profile.is_some());
        sim.fluctuation = Some((fmax, fmean));
        if let Some(p) = profile {
            crate::output::write_output(p, csv.as_bytes())?;
        }
    } else if profile.is_some() {
        bail!(
            "the profile would have {samples:.0} rows (more than {MAX_SAMPLES:.0}); use a longer --period"
        );
    }
    if let Some(p) = segments {
        crate::output::write_output(p, sim.segments_csv().as_bytes())?;
    }
    // A CSV written to standard output (`-`) has it to itself: the
    // summary goes to standard error.
    let to_stdout = |p: Option<&Path>| p.is_some_and(crate::read::is_stdio);
    let mut summary = String::new();
    if json {
        summary = format!("{}\n", simulation_json(&sim, curvature));
    } else {
        summary.push_str(&format!(
            "fairpath simulate: {}\n{}",
            crate::read::name(path),
            sim.text(m)
        ));
        summary.push_str(&format!(
            "  feed moves:      {:.3} mm, average feed {:.1} mm/s",
            sim.feed_length,
            sim.average_feed()
        ));
        match curvature {
            Some(k) => summary.push_str(&format!(", average curvature {k:.6} 1/mm\n")),
            None => summary.push('\n'),
        }
        if ends == RunEnds::AtCap {
            summary.push_str("  runs start and end at their speed cap (--run-ends cap)\n");
        }
    }
    if to_stdout(profile) || to_stdout(segments) {
        eprint!("{summary}");
    } else {
        print!("{summary}");
    }
    Ok(())
}
