//! A long written run's time planned window by window
//! (`fairpath::feed::windowed`, as the writer's check and `auto`'s
//! objective plan it) is the whole plan's, to the bit, on a real written
//! program: the raster of the shared programs smoothed and written as
//! arcs, read back.

use crate::common;

use fairpath::feed::plan::{plan_time_shaped, Corners, PlanOptions, RunEnds};
use fairpath::feed::shaping::Shaping;
use fairpath::feed::windowed::{plan_time_in_windows, PlanWindows};
use fairpath_gcode::{read_motion, smooth_program};

#[test]
fn a_written_raster_plans_the_same_time_in_windows_as_whole() {
    let Some(shared) = common::shared_paths() else {
        return;
    };
    let text = std::fs::read_to_string(shared.join("synthetic/surface-raster.ngc")).unwrap();
    let opts = common::arcs_options(0.05, "bspline-corner");
    let (output, _) = smooth_program(&text, &opts).unwrap();
    let (_, runs) = read_motion(output.text.as_bytes()).unwrap();
    let run = runs.iter().max_by_key(|r| r.pieces.len()).unwrap();
    // Windows small enough for many on this run, with an overlap of 512
    // arcs (tens of mm: the machine reaches its feed within them).
    let w = PlanWindows {
        step: 2048,
        overlap: 512,
    };
    assert!(run.pieces.len() > 4 * w.step, "{} pieces", run.pieces.len());
    for override_feed in [false, true] {
        for corners in [Corners::Blended, Corners::BlockCapped] {
            let po = PlanOptions {
                limits: *opts.machine(),
                override_feed,
                window: None,
                ends: RunEnds::AtRest,
            };
            let whole = plan_time_shaped(&run.pieces, &po, &Shaping::none(), corners).unwrap();
            let windows = plan_time_in_windows(&run.pieces, &po, corners, w)
                .unwrap()
                .expect("the windows are stitched");
            assert_eq!(
                whole.to_bits(),
                windows.to_bits(),
                "override {override_feed}, {corners:?}: {whole} against {windows}"
            );
        }
    }
}
