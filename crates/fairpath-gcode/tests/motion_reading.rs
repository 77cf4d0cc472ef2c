//! A program read for its motion only (`read_motion`, no lines held: how
//! `fairpath simulate`, `stream`, `report` and `check` read a long
//! program) gives the motions of the program read whole, piece for piece.

use crate::common;

use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::PlanOptions;
use fairpath::feed::program::{simulate_owned, simulate_with};
use fairpath::path::{Piece, Run};
use fairpath_gcode::interp::{MotionReader, RunStream};
use fairpath_gcode::{outline_motions, parse, read_motion};

/// Takes every other run that moves, and records what it is given.
#[derive(Default)]
struct EveryOther {
    /// Per run taken: its index, its index among the runs that move, the
    /// pieces given, whether its end came.
    taken: Vec<(usize, usize, Vec<Piece>, bool)>,
}

impl RunStream for EveryOther {
    fn wants(&mut self, run: usize, moving: usize) -> bool {
        if moving % 2 == 1 {
            return false;
        }
        self.taken.push((run, moving, Vec::new(), false));
        true
    }
    fn pieces(&mut self, run: usize, pieces: &[Piece], end: bool) {
        let last = self.taken.last_mut().expect("a run taken");
        assert_eq!(last.0, run);
        assert!(!last.3, "pieces after the end");
        last.2.extend_from_slice(pieces);
        last.3 = end;
    }
}

/// A reading that hands runs out part by part (`read_part_streaming`, how
/// the writer's check reads a long written run) gives the runs and
/// motions of the reading that holds them.
fn same_streamed(text: &[u8], what: &str) {
    let Ok((_, outline, runs)) = MotionReader::new().read_part(text) else {
        return;
    };
    for chunk in [1, 3, 64] {
        let mut stream = EveryOther::default();
        let (_, o, r) = MotionReader::new()
            .read_part_streaming(text, chunk, &mut stream)
            .unwrap();
        assert_eq!(o, outline, "{what}");
        assert_eq!(r.len(), runs.len(), "{what}");
        // Each run's index among the runs before it that move (its own if
        // it moves).
        let moves = |run: &Run| {
            run.pieces
                .iter()
                .any(|p| !matches!(&p.curve, fairpath::geom::Curve::Line(l) if l.p0 == l.p1))
        };
        let moving_before: Vec<usize> = runs
            .iter()
            .scan(0, |n, run| {
                let before = *n;
                *n += usize::from(moves(run));
                Some(before)
            })
            .collect();
        let mut given: Vec<Option<Run>> = vec![None; runs.len()];
        for (k, m, pieces, end) in stream.taken {
            assert!(end, "{what}: run {k} did not end");
            assert_eq!(moving_before[k], m, "{what}: run {k}");
            given[k] = Some(Run::new(pieces));
        }
        for (k, run) in runs.iter().enumerate() {
            match &given[k] {
                Some(g) => {
                    assert!(r[k].pieces.is_empty(), "{what}");
                    assert_eq!(g.pieces, run.pieces, "{what}: run {k}");
                }
                None => assert_eq!(r[k].pieces, run.pieces, "{what}: run {k}"),
            }
        }
        // Every other run (by that index) that holds a chunk is taken.
        let taken = (0..runs.len())
            .filter(|&k| moving_before[k] % 2 == 0 && runs[k].pieces.len() >= chunk)
            .count();
        assert_eq!(taken, given.iter().flatten().count(), "{what}");
    }
}

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
    same_streamed(text, what);
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
