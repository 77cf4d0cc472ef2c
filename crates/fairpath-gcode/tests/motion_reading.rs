//! A program read for its motion only (`read_motion`, no lines held: how
//! `fairpath simulate`, `stream`, `report` and `check` read a long
//! program) gives the motions of the program read whole, piece for piece.

mod common;

use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::PlanOptions;
use fairpath::feed::program::{simulate_owned, simulate_with};
use fairpath_gcode::{outline_motions, parse, read_motion};

fn same_motions(text: &[u8], what: &str) -> bool {
    let Ok(program) = parse(text) else {
        assert!(
            read_motion(text).is_err(),
            "{what}: read whole fails, for its motion not"
        );
        return false;
    };
    let whole = program.motions(&program.runs());
    let (outline, runs) = read_motion(text).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(outline_motions(outline, runs), whole, "{what}");
    true
}

#[test]
fn the_examples_read_for_their_motion_give_the_same_motions() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut read = 0;
    for path in common::files_under(&dir) {
        if path.extension().is_some_and(|e| e == "ngc") {
            read +=
                same_motions(&std::fs::read(&path).unwrap(), &path.display().to_string()) as usize;
        }
    }
    assert!(read >= 5, "{read} examples");
}

#[test]
fn the_shared_programs_read_for_their_motion_give_the_same_motions() {
    let Some(shared) = common::shared_paths() else {
        return;
    };
    let mut read = 0;
    for path in common::files_under(&shared) {
        let Ok(meta) = std::fs::metadata(&path) else {
            continue;
        };
        if meta.len() > 60_000 || path.extension().is_some_and(|e| e == "md") {
            continue;
        }
        read += same_motions(&std::fs::read(&path).unwrap(), &path.display().to_string()) as usize;
    }
    assert!(read >= 150, "{read} shared programs");
}

/// A simulation given its motions (`simulate_owned`: the runs moved into
/// it, as `fairpath simulate` does) is the simulation of borrowed ones, to
/// the bit: time, segments, the sampled profile and the segments' CSV.
#[test]
fn a_simulation_of_owned_motions_is_the_same_as_of_borrowed_ones() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let m = MachineLimits::thesis();
    let opts = PlanOptions {
        limits: m,
        override_feed: false,
        window: None,
        ends: Default::default(),
    };
    for path in common::files_under(&dir) {
        let Ok(program) = parse(&std::fs::read(&path).unwrap()) else {
            continue;
        };
        let motions = program.motions(&program.runs());
        let borrowed = simulate_with(&motions, &opts).unwrap();
        let owned = simulate_owned(motions, &opts).unwrap();
        let what = path.display().to_string();
        assert_eq!(borrowed.time().to_bits(), owned.time().to_bits(), "{what}");
        assert_eq!(borrowed.segments, owned.segments, "{what}");
        assert_eq!(borrowed.csv(&m, true), owned.csv(&m, true), "{what}");
        assert_eq!(borrowed.segments_csv(), owned.segments_csv(), "{what}");
    }
}
