//! `auto`'s objective renders every candidate as the writer will; the
//! writer takes the chosen candidate's rendering from it
//! (`pipeline::RenderMemo`) instead of rendering it again, and writes the
//! same text as without it, byte for byte.

use fairpath_gcode::pipeline::{
    plan_input_and_curves, smooth_curves_memo, JobTimes, Phases, RenderMemo,
};
use fairpath_gcode::{
    parse, write_curves, Controller, Curves, Format, ProgramFacts, SmoothOptions,
};
use std::sync::Arc;

/// The job's text, its times and the renderings the writer took, with or
/// without a memo.
fn written(text: &str, format: Format, memo: bool) -> (String, JobTimes, usize) {
    let program = parse(text.as_bytes()).unwrap();
    let opts = SmoothOptions::new(0.05, None, "auto", Some(format), Controller::Generic).unwrap();
    let memo = memo.then(|| Arc::new(RenderMemo::default()));
    let facts = ProgramFacts::of(&program);
    let mut phases = Phases::new();
    let result = smooth_curves_memo(&program, &facts, &opts, &mut phases, memo.clone()).unwrap();
    let (input, exact, plans) = plan_input_and_curves(&program, &result, &opts).unwrap();
    let curves = Curves {
        result,
        input,
        exact,
        plans,
        memo: memo.clone(),
    };
    let (output, report) = write_curves(&program, curves, &opts, phases).unwrap();
    (output.text, report.times, memo.map_or(0, |m| m.taken()))
}

/// Where `auto` keeps a candidate other than the one whose rendering
/// planned fastest (its final choice, `choose::FINAL_COST_MARGIN`), the
/// memo holds no rendering of it and the writer renders it itself: the
/// same text either way, and the memo used on most cases.
#[test]
fn the_writer_takes_autos_renderings_and_writes_the_same_text() {
    let (mut cases, mut used) = (0, 0);
    for text in [
        include_str!("../../../examples/pocket-corners.ngc"),
        include_str!("../../../examples/rhombus.ngc"),
        include_str!("../../../examples/zigzag.ngc"),
    ] {
        for format in [Format::Arcs, Format::G1, Format::G6_2, Format::G5_2] {
            let (with, _, taken) = written(text, format, true);
            let (without, times, none) = written(text, format, false);
            assert_eq!(none, 0);
            cases += 1;
            used += usize::from(taken > 0);
            assert_eq!(with, without, "{format:?}");
            // The whole job, whose writer also plans no run it takes the
            // rendering of (and plans a run it must render after all).
            let opts =
                SmoothOptions::new(0.05, None, "auto", Some(format), Controller::Generic).unwrap();
            let (job, report) = fairpath_gcode::smooth_program(text, &opts).unwrap();
            assert_eq!(job.text, without, "{format:?}");
            // The curves' time taken from the objective's bounds: the same
            // to the bit.
            assert_eq!(report.times, times, "{format:?}");
        }
    }
    assert!(2 * used > cases, "the memo used on {used} of {cases} cases");
}

/// The memo holds renderings of the runs the writer will write only, not
/// of the sections `auto` cuts them into and costs too: after smoothing,
/// at most one per run (arcs, the objective's only rendering here).
#[test]
fn autos_sections_leave_no_rendering_in_the_memo() {
    for text in [
        include_str!("../../../examples/pocket-corners.ngc"),
        include_str!("../../../examples/zigzag.ngc"),
    ] {
        let program = parse(text.as_bytes()).unwrap();
        let opts = SmoothOptions::new(0.05, None, "auto", Some(Format::Arcs), Controller::Generic)
            .unwrap();
        let memo = Arc::new(RenderMemo::default());
        let facts = ProgramFacts::of(&program);
        let mut phases = Phases::new();
        smooth_curves_memo(&program, &facts, &opts, &mut phases, Some(memo.clone())).unwrap();
        let runs = program.runs().len();
        assert!(memo.held() > 0);
        assert!(
            memo.held() <= runs,
            "{} renderings for {runs} runs",
            memo.held()
        );
    }
}
