//! Long runs cut into windows (`RunWindows`): where the reader cuts them,
//! that the parts hold the program's lines and path, and that the job in
//! windows writes a text whose path is the original's within the
//! tolerance, every line of the input kept in its place.

use fairpath::geom::{Curve, Vec3};
use fairpath_gcode::interp::{read_facts, read_motion, PartReader};
use fairpath_gcode::pipeline::{compare_runs, plan_text, Phases};
use fairpath_gcode::{
    parse, smooth_in_parts, Controller, Format, MoveKind, ParseOptions, PartSizes, Prepared,
    Program, RunWindows, SmoothOptions,
};

/// A raster of one run: `rows` rows of `per_row` lines along X over a
/// wavy Z, lines 0.3 to 3 mm long, step-overs in Y, with N numbers and a
/// comment here and there, as a CAM system writes them.
fn raster(rows: usize, per_row: usize) -> String {
    let mut s = String::from("G21 G90 G17\nG0 Z5\nG0 X0 Y0\nG1 Z0 F2000\n");
    let mut n = 10;
    for r in 0..rows {
        let y = r as f64 * 0.8;
        let mut x = 0.0f64;
        for i in 0..per_row {
            // Deterministic lengths 0.3 .. 3 mm.
            let step = 0.3 + 2.7 * (((i * 7919 + r * 104_729) % 97) as f64 / 96.0);
            x += step;
            let xr = if r % 2 == 0 { x } else { 150.0 - x };
            let z = (xr * 0.21).sin() * 1.5 + (y * 0.13).cos();
            if i % 50 == 7 {
                s += &format!("N{n} X{xr:.3} Y{y:.3} Z{z:.4} (pass {r})\n");
                n += 10;
            } else {
                s += &format!("X{xr:.3} Z{z:.4}\n");
            }
        }
        s += &format!("Y{:.3}\n", y + 0.8);
    }
    s += "G0 Z5\nM2\n";
    s
}

const WINDOWS: RunWindows = RunWindows {
    lines: 40,
    min_cut_mm: 2.0,
};

fn parts_of(text: &str, windows: RunWindows) -> Vec<Program> {
    let opts = ParseOptions::default();
    let facts = read_facts(text.as_bytes(), &opts).unwrap().unwrap();
    let mut r = PartReader::new(text.as_bytes(), &opts, 1, facts.block_delete).windowed(windows);
    let mut parts = Vec::new();
    while let Some(p) = r.next_part().unwrap() {
        parts.push(p);
    }
    parts
}

fn line_end(c: &Curve) -> (Vec3, Vec3) {
    match c {
        Curve::Line(l) => (l.p0, l.p1),
        other => panic!("a line, not {other:?}"),
    }
}

/// A run of a window's lines is cut at the middle of a line at least
/// `min_cut_mm` long: the
/// part ends with a `G1` to the midpoint, the next starts with the cut
/// line, which goes on from there; every line of the text is in one part,
/// with its number and text, and the moves are the program's with each
/// cut line split in two.
#[test]
fn long_runs_are_cut_at_the_middle_of_long_lines() {
    let text = raster(6, 60);
    let whole = parse(text.as_bytes()).unwrap();
    let parts = parts_of(&text, WINDOWS);
    let cuts = parts.iter().filter(|p| p.window_cut()).count();
    assert!(cuts >= 6, "{cuts} cuts");
    let mut next_number = 1;
    let mut moves = Vec::new();
    for (k, p) in parts.iter().enumerate() {
        assert_eq!(p.first_number(), next_number, "part {k}");
        next_number += p.source_lines();
        let held = p.source_lines();
        for (i, l) in p.lines()[..held].iter().enumerate() {
            let w = whole.line(p.first_number() + i);
            assert_eq!((l.number, &l.text), (w.number, &w.text), "part {k}");
        }
        moves.extend(p.moves().iter().cloned());
        if !p.window_cut() {
            continue;
        }
        let cut = p.lines().last().unwrap();
        assert!(cut.text.starts_with("G1 X"), "{}", cut.text);
        assert_eq!(cut.number, parts[k + 1].first_number());
        let (a, m) = line_end(&p.moves().last().unwrap().piece.curve);
        let first = &parts[k + 1].moves()[0];
        let (m2, b) = line_end(&first.piece.curve);
        assert_eq!(m, m2, "the next part goes on from the midpoint");
        assert!(m.dist(a.lerp(b, 0.5)) < 1e-12, "{m:?} is the midpoint");
        assert!(a.dist(b) >= WINDOWS.min_cut_mm);
        let w = whole.line(first.line);
        assert_eq!(line_end(&whole.moves()[w.moves.start].piece.curve), (a, b));
    }
    assert_eq!(next_number - 1, whole.lines().len());
    // The moves, each cut line's two halves as one, are the program's.
    let mut joined: Vec<(Vec3, Vec3, usize)> = Vec::new();
    for m in moves.iter().filter(|m| m.kind == MoveKind::Linear) {
        let (a, b) = line_end(&m.piece.curve);
        match joined.last_mut() {
            Some(last) if last.2 == m.line && last.1 == a => last.1 = b,
            _ => joined.push((a, b, m.line)),
        }
    }
    let want: Vec<(Vec3, Vec3)> = whole
        .moves()
        .iter()
        .filter(|m| m.kind == MoveKind::Linear)
        .map(|m| line_end(&m.piece.curve))
        .collect();
    assert_eq!(joined.len(), want.len());
    for (j, w) in joined.iter().zip(&want) {
        assert!(
            j.0.dist(w.0) < 1e-12 && j.1.dist(w.1) < 1e-12,
            "{j:?} {w:?}"
        );
    }
}

/// No window is cut where the program has `/` lines, in G91, or on lines
/// with more than N, G1 and X, Y, Z words.
#[test]
fn only_plain_lines_of_absolute_runs_are_cut() {
    let cuts = |text: &str| {
        parts_of(text, WINDOWS)
            .iter()
            .filter(|p| p.window_cut())
            .count()
    };
    let text = raster(3, 60);
    assert!(cuts(&text) > 0);
    assert_eq!(cuts(&text.replace("G21 G90", "G21 G91")), 0);
    assert_eq!(cuts(&text.replacen("G0 Z5\n", "G0 Z5\n/M1\n", 1)), 0);
    assert_eq!(cuts(&text.replace(" Z", " A0 Z")), 0);
    let feeds: String = text
        .lines()
        .map(|l| match l.starts_with(['X', 'Y', 'N']) {
            true => format!("{l} F2000\n"),
            false => format!("{l}\n"),
        })
        .collect();
    assert_eq!(cuts(&feeds), 0);
}

/// The job in parts of `lines` lines and `windows`: its evidence and text.
fn windowed_job(
    text: &str,
    opts: &SmoothOptions,
    lines: usize,
    windows: RunWindows,
) -> Result<(fairpath_gcode::Evidence, String), String> {
    let prepared = Prepared::read(text.as_bytes(), opts.format()).unwrap();
    let sizes = PartSizes {
        lines,
        windows: Some(windows),
    };
    let mut out = Vec::new();
    let (evidence, _) = smooth_in_parts(
        text.as_bytes(),
        prepared,
        opts,
        sizes,
        &mut out,
        Phases::new(),
    )
    .map_err(|e| e.to_string())?;
    Ok((evidence, String::from_utf8(out).unwrap()))
}

fn options(method: &str) -> SmoothOptions {
    SmoothOptions::new(0.05, None, method, Some(Format::Arcs), Controller::Generic).unwrap()
}

/// The job in windows: the written text reads back, whole, as a path
/// within the tolerance of the original's with the same run ends; every
/// N number and comment of the input is in it, in order; its times are
/// the input's and its own as planned whole; with `none` it is the input.
#[test]
fn a_long_run_smoothed_in_windows_stays_within_the_tolerance() {
    // Also with a blending command looser than the blending share, which
    // the writer tightens around the runs it rewrites: there no run is cut
    // (a window kept as written and the next rewritten would get the
    // command between them, inside the run: `Cereal.ngc`, `auto`, windows
    // of one line, read back as 51 runs where the program has 50).
    let plain = raster(6, 60);
    let g64 = plain.replacen("G21 G90 G17", "G21 G90 G17 G64 P0.5", 1);
    for text in [plain, g64] {
        in_windows_within_the_tolerance(&text);
    }
}

fn in_windows_within_the_tolerance(text: &str) {
    let text = text.to_string();
    let (_, original) = read_motion(text.as_bytes()).unwrap();
    for method in ["none", "bspline-corner", "bspline-fit", "auto"] {
        let opts = options(method);
        let (evidence, written) =
            windowed_job(&text, &opts, 1, WINDOWS).unwrap_or_else(|e| panic!("{method}: {e}"));
        assert_eq!(evidence.lines_in, text.lines().count(), "{method}");
        // The times are those of the input and of the written text, planned
        // whole as `fairpath simulate` plans them, to the bit.
        let (input, wrote) = (evidence.times.input, evidence.times.written);
        assert_eq!(input, plan_text(&text, &opts).unwrap(), "{method}");
        assert_eq!(wrote, plan_text(&written, &opts).unwrap(), "{method}");
        let (_, runs) = read_motion(written.as_bytes()).unwrap();
        assert_eq!(runs.len(), original.len(), "{method}: the runs of the text");
        let check = compare_runs(&original, &runs, opts.tolerance()).unwrap();
        assert!(check.within, "{method}: {}", check.max_deviation);
        // Every N number and every comment, in order.
        let marks = |t: &str, c: char| -> Vec<String> {
            t.lines()
                .filter(|l| !l.starts_with("(smoothed") && !l.contains("merged"))
                .flat_map(|l| l.split_whitespace())
                .filter(|w| w.starts_with(c))
                .map(str::to_string)
                .collect()
        };
        for c in ['N', '('] {
            assert_eq!(marks(&written, c), marks(&text, c), "{method}");
        }
        // Where the run is kept as written on both sides of a cut, the
        // line put in is dropped: with `none`, the text is the input's.
        // The run cut into windows counts once, as it is in the program.
        assert_eq!(evidence.runs, original.len(), "{method}");
        let moves: usize = original.iter().map(|r| r.pieces.len()).sum();
        assert_eq!(evidence.feed_moves_in, moves, "{method}");
        if method == "none" {
            assert_eq!(evidence.kept_runs, original.len());
            let lines: Vec<&str> = written
                .lines()
                .filter(|l| !l.starts_with("(smoothed"))
                .collect();
            assert_eq!(lines, text.lines().collect::<Vec<_>>(), "{method}");
            assert_eq!(wrote, input, "{method}");
        }
    }
}

/// A run longer than a plan's window ([`fairpath::feed::windowed`]: the
/// carried plans stitch windows of the plan, not only of the parts): the
/// times are still those of the input and of the written text planned
/// whole, to the bit.
#[test]
fn a_run_longer_than_a_plan_window_is_timed_as_planned_whole() {
    let text = raster(160, 250);
    let opts = options("none");
    let windows = RunWindows {
        lines: 4096,
        min_cut_mm: 1.0,
    };
    let (evidence, written) = windowed_job(&text, &opts, 256, windows).unwrap();
    assert!(evidence.parts >= 9, "{} parts", evidence.parts);
    assert_eq!(evidence.times.input, plan_text(&text, &opts).unwrap());
    assert_eq!(evidence.times.written, plan_text(&written, &opts).unwrap());
    // The curves of `none` are the input: the cut lines' halves planned as
    // one line, as in the program.
    assert_eq!(evidence.times.exact, evidence.times.input);
}

/// Windows of one line cut at every plain line of 0.5 mm or more, on our
/// programs that part in many places (feed changes, rapids, plane changes,
/// R arcs, G64, inch and mm, `/` lines, a spline block, comments and N
/// numbers in runs, a line relying on the modal motion), in every
/// configuration of
/// `parts.rs`: each job writes a text whose runs are the program's, within
/// the tolerance, and times that are the input's and the text's planned
/// whole.
#[test]
fn windows_at_every_line_keep_our_programs_runs_path_and_times() {
    let windows = RunWindows {
        lines: 1,
        min_cut_mm: 0.5,
    };
    let cuts: usize = crate::parts::OWN
        .iter()
        .map(|t| {
            parts_of(t, windows)
                .iter()
                .filter(|p| p.window_cut())
                .count()
        })
        .sum();
    assert!(cuts >= 8, "{cuts} cuts");
    for (i, text) in crate::parts::OWN.iter().enumerate() {
        for (method, format, controller) in crate::parts::CONFIGS {
            if format == Format::Json {
                continue;
            }
            let opts = SmoothOptions::new(0.05, None, method, Some(format), controller).unwrap();
            let what = format!("program {i}, {method} {format:?} {controller:?}");
            let (evidence, written) =
                windowed_job(text, &opts, 1, windows).unwrap_or_else(|e| panic!("{what}: {e}"));
            keeps_runs_path_and_times(text, &opts, &evidence, &written, &what);
        }
    }
}

/// `Cereal.ngc` (`G64 P0.1`, which blends beyond the blending share, so
/// the writer tightens it around the runs it rewrites) in windows of one
/// line: windows kept as written lie next to windows rewritten, and the
/// writer's command goes before a cut run's first window, kept or not,
/// and the program's own after its last, so no path-control line falls
/// inside a run (the writer's command between a kept window and a
/// rewritten one made the text read back as 51 runs where the program has
/// 50). A run counts as kept only where all its windows are. Read in
/// place; nothing to check without `shared/paths`.
#[test]
fn cereal_in_windows_of_one_line_keeps_its_runs_under_one_blending_command() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/paths/linuxcnc/performance/Cereal.ngc");
    let Ok(text) = std::fs::read_to_string(path) else {
        return;
    };
    let windows = RunWindows {
        lines: 1,
        min_cut_mm: 1.0,
    };
    for controller in [Controller::Generic, Controller::Linuxcnc] {
        let opts = SmoothOptions::new(0.05, None, "bspline-corner", Some(Format::Arcs), controller)
            .unwrap();
        let (evidence, written) = windowed_job(&text, &opts, 1, windows).unwrap();
        let what = format!("{controller:?}");
        keeps_runs_path_and_times(&text, &opts, &evidence, &written, &what);
        assert!(
            evidence.kept_runs < evidence.runs,
            "{controller:?}: {} of {} runs kept",
            evidence.kept_runs,
            evidence.runs
        );
    }
}

/// The text `written` of a job on `text` with `opts` reads back with the
/// program's runs, within the tolerance of its path, and `evidence` counts
/// those runs and gives the times of the input and of the text, each
/// planned whole (`what` names the job in messages).
fn keeps_runs_path_and_times(
    text: &str,
    opts: &SmoothOptions,
    evidence: &fairpath_gcode::Evidence,
    written: &str,
    what: &str,
) {
    let (_, original) = read_motion(text.as_bytes()).unwrap();
    let (_, runs) = read_motion(written.as_bytes()).unwrap();
    assert_eq!(runs.len(), original.len(), "{what}: runs\n{written}");
    let check = compare_runs(&original, &runs, opts.tolerance()).unwrap();
    assert!(check.within, "{what}: {}", check.max_deviation);
    assert_eq!(evidence.runs, original.len(), "{what}");
    assert_eq!(
        evidence.times.input,
        plan_text(text, opts).unwrap(),
        "{what}"
    );
    let wrote = plan_text(written, opts).unwrap();
    assert_eq!(evidence.times.written, wrote, "{what}");
}

/// Regression (`surface-raster-large.ngc`, `auto` at 0.05 mm, the job
/// the CLI runs): its written raster runs whole passes at the maximum
/// feed, one planner segment for thousands of arcs. With carried windows
/// of 2,048 pieces of overlap the written run did not stitch and the job
/// was done again without windows: twice the time and ten times the
/// memory (548 MB for a 3.7 MB input). The job must stitch.
#[test]
#[ignore = "slow: auto on a 3.7 MB program, about 20 s in the test profile"]
fn surface_raster_large_auto_written_stitches_in_windows() {
    let Some(shared) = super::common::shared_paths() else {
        return;
    };
    let path = shared.join("synthetic/surface-raster-large.ngc");
    let text = std::fs::read(&path).unwrap();
    let opts = options("auto");
    let prepared = Prepared::read(&text, opts.format()).unwrap();
    let sizes = PartSizes {
        lines: fairpath_gcode::PART_LINES,
        windows: Some(RunWindows::DEFAULT),
    };
    let mut out = Vec::new();
    // (An output that does not verify is an error.)
    let (evidence, phases) =
        smooth_in_parts(&text, prepared, &opts, sizes, &mut out, Phases::new()).unwrap();
    assert_eq!(
        phases.duration(fairpath_gcode::WINDOWS_UNSTITCHED),
        std::time::Duration::ZERO,
        "the written run did not stitch in windows; the steps: {}",
        phases.report()
    );
    assert_eq!(evidence.feed_moves_in, 138_804);
}
