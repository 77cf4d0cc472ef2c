//! The machine times are planned for: a machine file (TOML) and the
//! command line's flags over the defaults (the thesis machine).

use anyhow::{anyhow, Context, Result};
use fairpath::feed::limits::MachineLimits;
use serde::Deserialize;
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
    /// Least time the control spends on a block, s (0: none).
    pub block_time: Option<f64>,
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
    /// Least time the control spends on a block, s (0: none).
    pub block_time: Option<f64>,
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
        if let Some(v) = mf.block_time {
            m.block_time = v;
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
    if let Some(v) = flags.block_time {
        m.block_time = v;
    }
    m.validate().map_err(crate::usage::usage)?;
    Ok(m)
}
