//! Runs: the feed moves grouped into runs of moves smoothed together.

use crate::program::{Feed, Move, MoveKind, ProgramLine, RunSpan};

/// Groups the runs: consecutive non-pinned feed moves on lines that do not
/// break runs, at one feed. A run that starts with a spline block's moves
/// starts at the block's first line.
///
/// A move whose feed differs from the move before it starts a new run
/// (the line that changes the feed lies between the two runs): the
/// programmed feed then changes exactly at the programmed vertex, which
/// smoothing keeps (run end points are kept exactly). Smoothing across it
/// would make one feed apply to a stretch of path programmed at the other
/// (`linuxcnc/diagnostic/feed-tracking-test.ngc`: `X2 F1000`, `X2.001
/// F10`, `X5 F1000` became one move at F10, far slower; measurements:
/// docs/tuning.md, `group_runs`).
///
/// `lines` may be a part of a program: `first_number` is the number of
/// its first line, `feed_before` the feed in force before it.
pub(super) fn group_runs(
    lines: &[ProgramLine],
    moves: &[Move],
    first_number: usize,
    mut feed_before: Option<Feed>,
) -> Vec<RunSpan> {
    let mut runs = Vec::new();
    let mut cur: Option<RunSpan> = None;
    for line in lines {
        if line.breaks_run || !line.interpreted {
            if let Some(r) = cur.take() {
                runs.push(r);
            }
        } else {
            for mi in line.moves.clone() {
                let m = &moves[mi];
                debug_assert!(m.pinned.is_none() && m.kind != MoveKind::Rapid);
                if let Some(r) = &cur {
                    if moves[r.moves.end - 1].piece.feed != m.piece.feed {
                        runs.extend(cur.take());
                    }
                }
                match &mut cur {
                    Some(r) => {
                        r.moves.end = mi + 1;
                        r.last_line = line.number;
                        r.feed_after = line.feed_after.clone();
                    }
                    None => {
                        // A spline block's moves start the run at the
                        // block's first line, with the feed before it.
                        let first = m.piece.source_lines.0.min(line.number);
                        let before = if first == line.number {
                            feed_before.clone()
                        } else {
                            (first - 1)
                                .checked_sub(first_number)
                                .and_then(|i| lines[i].feed_after.clone())
                        };
                        cur = Some(RunSpan {
                            moves: mi..mi + 1,
                            first_line: first,
                            last_line: line.number,
                            units: line.units,
                            incremental: line.incremental,
                            feed_before: before,
                            feed_after: line.feed_after.clone(),
                        })
                    }
                }
            }
            // Feed changes on interior lines after the last move count too:
            // they are emitted after the run, so feed_after is the modal
            // feed after the run's last line.
        }
        feed_before = line.feed_after.clone();
    }
    if let Some(r) = cur.take() {
        runs.push(r);
    }
    runs
}
