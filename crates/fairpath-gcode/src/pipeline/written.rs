//! What the writer does with the curves of a run, below the writing
//! itself: the forms a format can say ([`forms`]), the renderer's and the
//! writer's options ([`render_options`], [`write_options`]), and the
//! objective that ranks `auto`'s candidates by the time of what will be
//! written ([`objective_for`]). [`crate::emit`] renders and writes with
//! them; [`super::SmoothOptions`] builds `auto` with the objective.

use super::EmitOptions;
use crate::{
    ArcWords, Controller, Format, GcodeWriteOptions, NurbsBlocks, ProgramFacts, ROUNDING_SHARE,
};
use fairpath::choose::{Objective, PlannedTime, WrittenTime};
use fairpath::feed::limits::MachineLimits;
use fairpath::geom::Nurbs;
use fairpath::render::{CurveForm, NurbsLimits, RenderOptions};
use std::sync::Arc;

/// LinuxCNC spends at least this many servo periods on a block
/// (`TP_MIN_SEGMENT_CYCLES`, tp.c): shorter blocks cap the speed.
pub const MIN_BLOCK_PERIODS: f64 = 1.02;

/// Smallest arc radius written (mm): LinuxCNC refuses radii below
/// 0.00127 mm (`RADIUS_TOLERANCE_INCH` = 0.00005 in, interp_internal.hh);
/// twice that leaves room for the rounding of the written centre.
pub const MIN_ARC_RADIUS_MM: f64 = 0.00254;

/// Shortest arc written, in units of the last written decimal: the rounded
/// ends of a shorter one could coincide (a full circle in G-code).
pub const MIN_ARC_UNITS: f64 = 4.0;

/// Spread (mm) along a plane's normal below which a NURBS counts as in the
/// plane for LinuxCNC's spline blocks: well below any written decimal.
pub const PLANAR_MM: f64 = 1e-9;

/// Highest degree of Fanuc's G6.2 (order 4).
pub const FANUC_MAX_DEGREE: usize = 3;

/// G6.2 as Fanuc-style blocks: up to degree `max_degree`, in any plane or
/// in 3D.
fn fanuc_nurbs(max_degree: usize) -> NurbsLimits {
    NurbsLimits {
        max_degree,
        planar_mm: None,
        xy_only: false,
        linuxcnc_g5_2: false,
    }
}

/// Highest degree of the G6.2 blocks written for `controller` when the
/// program's own NURBS are of degree up to `program_degree` (0: none):
/// Fanuc's 3 (orders 2 to 4) for Fanuc, LinuxCNC's 7, and for a generic
/// control 3 or the program's own degree, which the control it was
/// written for runs. (LinuxCNC's G6.2 examples are of orders 5 and 6: held
/// to cubics, their faired curves were written as arcs, which planned
/// slower than the program, and every run was kept as written.)
pub fn g6_2_max_degree(controller: Controller, program_degree: usize) -> usize {
    match controller {
        Controller::Fanuc => FANUC_MAX_DEGREE,
        Controller::Linuxcnc => Nurbs::MAX_DEGREE,
        Controller::Generic => program_degree.clamp(FANUC_MAX_DEGREE, Nurbs::MAX_DEGREE),
    }
}

/// The forms a run's curves can be rendered in for `format` on
/// `controller`, in the order the writer tries them (none for JSON, which
/// writes the curves as they are); `program_degree` is the highest degree
/// of the program's own NURBS ([`crate::ProgramFacts::nurbs_degree`],
/// [`g6_2_max_degree`]).
pub fn forms(format: Format, controller: Controller, program_degree: usize) -> Vec<CurveForm> {
    let g6 = fanuc_nurbs(g6_2_max_degree(controller, program_degree));
    match format {
        Format::Json => vec![],
        Format::G1 => vec![CurveForm::Lines],
        Format::Arcs => vec![CurveForm::Arcs, CurveForm::Lines],
        Format::G5_2 => vec![
            CurveForm::Nurbs(NurbsLimits {
                max_degree: Nurbs::MAX_DEGREE,
                planar_mm: Some(PLANAR_MM),
                xy_only: true,
                linuxcnc_g5_2: true,
            }),
            CurveForm::Arcs,
        ],
        Format::G6_2 if controller == Controller::Linuxcnc => vec![CurveForm::Nurbs(NurbsLimits {
            max_degree: Nurbs::MAX_DEGREE,
            planar_mm: Some(PLANAR_MM),
            xy_only: false,
            linuxcnc_g5_2: false,
        })],
        Format::G6_2 if controller == Controller::Fanuc => vec![CurveForm::Nurbs(g6)],
        // A generic control that runs G6.2 runs arcs and lines too: each
        // run gets the form that plans fastest (a fairing of a zigzag of
        // lines written as a degree-1 G6.2 plans faster as G1).
        Format::G6_2 => vec![CurveForm::Nurbs(g6), CurveForm::Arcs, CurveForm::Lines],
    }
}

/// What `auto` ranks its candidates by when `opts` writes `program`:
/// for a G-code format, the time of the program as it will be written
/// ([`WrittenTime`]: the curves rendered as [`crate::emit::emit`] renders
/// them, in the format's forms but the all-G1 alternative to arcs, with
/// the budget [`EmitOptions::budget_for`] gives `program` and the units
/// of its first run, at the user's feeds); for JSON, which writes the
/// exact curves, their planned time ([`PlannedTime`], at the machine's
/// maximum feed).
///
/// `memo`, if any, is told of every rendering the objective costs
/// ([`super::RenderMemo`]).
pub fn objective_for(
    opts: &EmitOptions,
    facts: &ProgramFacts,
    memo: Option<Arc<super::RenderMemo>>,
) -> Arc<dyn Objective> {
    let exact = || Arc::new(PlannedTime::new(opts.machine, true)) as Arc<dyn Objective>;
    let forms = forms(opts.format, opts.controller, facts.nurbs_degree);
    let Ok(budget) = opts.budget_for_blending(&facts.blending) else {
        return exact();
    };
    if forms.is_empty() {
        return exact();
    }
    let opts = &EmitOptions { budget, ..*opts };
    let wo = write_options(opts, facts.nurbs_degree);
    let units = facts.render_units();
    // Not the all-G1 alternative the writer also tries where arcs fell
    // back to lines: it rarely wins (`docs/tuning.md`) and would double
    // the cost of ranking such candidates.
    let renders = forms
        .iter()
        .enumerate()
        .filter(|&(i, &form)| i == 0 || form != CurveForm::Lines)
        .map(|(_, &form)| render_options(opts, form, budget.output, units, &wo))
        .collect();
    let mut written = WrittenTime::new(opts.machine, opts.override_feed, renders);
    // The writer's all-G1 rendering where the arcs do not win, judged by
    // `written_instead` as the writer judges it.
    written.lines_alternative = forms
        .iter()
        .skip(1)
        .any(|&f| f == CurveForm::Lines)
        .then(|| render_options(opts, CurveForm::Lines, budget.output, units, &wo));
    written.corners = opts.judged_by;
    // What the writer tries beyond those (`emit::choose_run`).
    written.writer_tries = Some(fairpath::choose::WriterTries {
        finer_share: crate::emit::FINER_STEP,
        finer_steps: crate::emit::FINER_STEPS,
        long_pieces: crate::emit::LONG_RUN_PIECES,
        lines_without_arcs: budget
            .finer_lines_output()
            .map(|chord| render_options(opts, CurveForm::Lines, chord, units, &wo)),
    });
    written.observer = memo.map(|m| m as Arc<dyn fairpath::choose::RenderObserver>);
    Arc::new(written)
}

/// The writer's options for `opts` (arcs in IJK form; [`crate::emit::emit`] writes R
/// when the program does) for a program whose own NURBS are of degree up
/// to `program_degree` ([`g6_2_max_degree`]).
pub fn write_options(opts: &EmitOptions, program_degree: usize) -> GcodeWriteOptions {
    let blend = opts.budget.blend;
    GcodeWriteOptions {
        chord_mm: opts.budget.output,
        arcs: (opts.format != Format::G1).then_some(ArcWords::Ijk),
        nurbs: match (opts.format, opts.controller) {
            (Format::G5_2, _) => Some(NurbsBlocks::G5_2),
            (Format::G6_2, Controller::Linuxcnc) => Some(NurbsBlocks::G6_2Linuxcnc),
            (Format::G6_2, c) => Some(NurbsBlocks::G6_2Fanuc {
                max_degree: g6_2_max_degree(c, program_degree),
            }),
            _ => None,
        },
        // The input's own style adds to this (NumberStyle::of).
        decimal_point: opts.controller == Controller::Fanuc,
        // Written around every run for LinuxCNC, and for any controller
        // around runs where the program's own G64 blends beyond the share
        // (EmitOptions::budget_for gives one then); never where no run is
        // rewritten.
        g64_blend_mm: (blend > 0.0 && !opts.keeps_every_run).then_some(blend),
        g64_always: opts.controller == Controller::Linuxcnc,
        // For every controller: a Fanuc control reads these decimals only
        // with a fine increment system (IS-D/IS-E); with IS-C (4 decimals
        // in mm) the rounded control points of G6.2 blocks break curvature
        // continuity at every knot (butterfly-80 planned far slower;
        // measurements: docs/tuning.md, `write_options`).
        resolution_mm: Some(resolution(&opts.machine)),
        period_s: Some(opts.machine.period),
        ..Default::default()
    }
}

/// Largest rounding (mm) of a written point for `m`: `J Ts^3 / 40` (see
/// [`GcodeWriteOptions::resolution_mm`]; a tenth of what keeps block-long
/// pieces at their speed, because at the slow, tight places of a path the
/// kinks rounding leaves cost the most time: 7 decimals in mm on the
/// default machine, where one fewer planned `surface-raster.ngc` slower
/// than its rendering; measurements: docs/tuning.md, `resolution`).
pub fn resolution(m: &MachineLimits) -> f64 {
    0.025 * m.jerk * m.period * m.period * m.period
}

/// The renderer's options for a run in `units` with output share `chord`.
pub fn render_options(
    opts: &EmitOptions,
    form: CurveForm,
    chord: f64,
    units: crate::Units,
    wo: &GcodeWriteOptions,
) -> RenderOptions {
    let scale = units.mm_per_unit();
    let min_decimals = match units {
        crate::Units::Mm => wo.decimals_mm,
        crate::Units::Inch => wo.decimals_inch,
    };
    let (decimals, _) = crate::output_decimals(wo, scale, min_decimals);
    RenderOptions {
        form,
        // The writer's rounding takes at most ROUNDING_SHARE of it.
        chord: chord * (1.0 - ROUNDING_SHARE),
        limits: opts.machine,
        min_block_periods: MIN_BLOCK_PERIODS,
        min_radius: MIN_ARC_RADIUS_MM,
        step_share: opts.step_share,
        min_arc_length: MIN_ARC_UNITS * 10f64.powi(-(decimals as i32)) * scale,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g6_degree(forms: &[CurveForm]) -> Option<usize> {
        forms.iter().find_map(|f| match f {
            CurveForm::Nurbs(l) => Some(l.max_degree),
            _ => None,
        })
    }

    #[test]
    fn a_generic_control_writes_the_programs_own_nurbs_degree() {
        let g = Controller::Generic;
        for (program, want) in [
            (0, 3),
            (2, 3),
            (3, 3),
            (4, 4),
            (5, 5),
            (99, Nurbs::MAX_DEGREE),
        ] {
            assert_eq!(g6_2_max_degree(g, program), want, "{program}");
            assert_eq!(g6_degree(&forms(Format::G6_2, g, program)), Some(want));
        }
        // Fanuc is held to its orders 2 to 4, LinuxCNC reads up to 7.
        assert_eq!(g6_2_max_degree(Controller::Fanuc, 5), FANUC_MAX_DEGREE);
        assert_eq!(g6_2_max_degree(Controller::Linuxcnc, 0), Nurbs::MAX_DEGREE);
        assert_eq!(g6_degree(&forms(Format::Arcs, g, 5)), None);
    }
}
