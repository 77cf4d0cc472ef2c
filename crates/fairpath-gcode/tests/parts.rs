//! A program processed a part at a time (`smooth_in_parts`) writes the text
//! the whole program's job (`smooth_parsed`) writes, byte for byte, with
//! the same figures and the times to the bit, however small its parts; the
//! facts read as a stream (`read_facts`) are those of the whole reading;
//! parts start only where the module docs of `interp::parts` say.

use crate::common;

use fairpath_gcode::interp::{read_facts, PartReader};
use fairpath_gcode::pipeline::Phases;
use fairpath_gcode::{
    parse, smooth_in_parts, smooth_parsed, Controller, Evidence, Format, ParseOptions, PartSizes,
    Prepared, ProgramFacts, SmoothOptions,
};

/// The configurations compared: method, format, controller.
pub const CONFIGS: [(&str, Format, Controller); 6] = [
    ("bspline-corner", Format::Arcs, Controller::Generic),
    ("none", Format::Arcs, Controller::Generic),
    ("lotm", Format::G1, Controller::Linuxcnc),
    ("arc-fit", Format::Arcs, Controller::Linuxcnc),
    ("bspline-fit", Format::G6_2, Controller::Fanuc),
    ("auto", Format::Arcs, Controller::Generic),
];

/// Programs of our own that part in many places: feed changes, rapids,
/// plane changes, R arcs, G64, inch and mm, `/` lines, a spline block,
/// comments and N numbers in runs, a line relying on the modal motion.
pub const OWN: [&str; 4] = [
    "%\nG21 G90 G64 P0.2\nG0 X0 Y0\nN10 G1 X10 F1000 (first)\nN20 X10 Y10\nX20 Y10 F600\n\
     X20 Y20\nG0 Z5\nG0 X30 Y0\nG1 Z0 F300\nX40\nG2 X50 Y10 R10\nG1 X60 F900\nX60 Y20\n\
     X70 Y20 F1200\nG18\nG2 X80 Z-10 R10\nG1 X90\nG17\nG0 X0 Y0\nG1 X5 Y5\nX10 Y0\nM30\n%\n",
    "G20 G90\nG0 X0 Y0\nG1 X1 F20\nX1 Y1\nX2 Y1 F30\nX2 Y2\nX3 Y2 F20\nG0 X0 Y0\nG21\n\
     G1 X10 F500\nX10 Y10\nX20 Y10 F400\nX20 Y20\nM2\n",
    "G21 G90\nG0 X0 Y0\nG1 X10 F1000\nX10 Y10\n/G1 X15 Y15\nX20 Y10 F600\nX20 Y20\n\
     G0 X0 Y0\nG1 X5 F500\nX5 Y5 F400\nX10 Y5\nM2\n",
    "G21 G90\nG0 X0 Y0\nG1 X1 F600\nG5.2 X2 Y0 P1 L3\nX3 Y1 P1\nX4 Y0 P1\nX5 Y1 P1\nG5.3\n\
     G1 X6 F500\nX7 Y2\nX8 Y0 F400\nX9 Y2\nG0 X0 Y0\nM2\n",
];

fn options(method: &str, format: Format, controller: Controller) -> SmoothOptions {
    SmoothOptions::new(0.05, None, method, Some(format), controller).unwrap()
}

/// Whether the job in parts of `part_lines` writes what the whole job
/// writes, with the same evidence (a message saying what differs if not).
fn same_in_parts(text: &[u8], opts: &SmoothOptions, part_lines: usize) -> Result<(), String> {
    let program = parse(text).map_err(|e| e.to_string())?;
    let whole = smooth_parsed(&program, opts);
    let prepared = Prepared::read(text, opts.format()).unwrap();
    let mut out = Vec::new();
    let sizes = PartSizes::of(part_lines);
    let parts = smooth_in_parts(text, prepared, opts, sizes, &mut out, Phases::new());
    let (output, report) = match (whole, parts) {
        (Ok((o, r)), Ok((e, _))) => {
            if program.is_empty() {
                return (out == text)
                    .then_some(())
                    .ok_or("no moves: not as given".into());
            }
            let accuracy = opts.tolerance() * fairpath_gcode::entry::LENGTH_ACCURACY_SHARE;
            let mut of_whole = Evidence::of(&r, accuracy);
            of_whole.parts = e.parts;
            if of_whole != e {
                return Err(format!("evidence differs:\n{of_whole:?}\n{e:?}"));
            }
            (o, r)
        }
        (Err(_), Err(_)) => return Ok(()),
        (w, p) => {
            return Err(format!(
                "one fails: whole {:?}, parts {:?}",
                w.err(),
                p.err()
            ))
        }
    };
    if output.text.as_bytes() != out.as_slice() {
        let first = output
            .text
            .lines()
            .zip(String::from_utf8_lossy(&out).lines())
            .position(|(a, b)| a != b);
        return Err(format!("text differs, first at line {first:?}"));
    }
    let _ = report;
    Ok(())
}

#[test]
fn our_programs_in_parts_of_every_size_are_written_as_whole() {
    for (i, text) in OWN.iter().enumerate() {
        for (method, format, controller) in CONFIGS {
            let opts = options(method, format, controller);
            for part_lines in [1, 2, 3, 5, 1000] {
                same_in_parts(text.as_bytes(), &opts, part_lines).unwrap_or_else(|e| {
                    panic!("program {i}, {method} {format:?} {controller:?}, {part_lines}: {e}")
                });
            }
        }
    }
}

#[test]
fn the_bundled_examples_in_parts_are_written_as_whole() {
    for text in [
        include_str!("../../../examples/pocket-corners.ngc"),
        include_str!("../../../examples/rhombus.ngc"),
    ] {
        for (method, format, controller) in CONFIGS {
            let opts = options(method, format, controller);
            same_in_parts(text.as_bytes(), &opts, 1)
                .unwrap_or_else(|e| panic!("{method} {format:?} {controller:?}: {e}"));
        }
    }
}

/// Where parts start: before a rapid with its own G0, or at a feed change
/// in a program without `/` lines; never inside a spline block.
#[test]
fn parts_start_before_rapids_and_at_feed_changes() {
    let first_lines = |text: &str, block_delete: bool| -> Vec<usize> {
        let mut r = PartReader::new(text.as_bytes(), &ParseOptions::default(), 1, block_delete);
        let mut firsts = Vec::new();
        while let Some(p) = r.next_part().unwrap() {
            firsts.push(p.first_number());
            assert!(!p.lines().is_empty());
        }
        firsts
    };
    let text = OWN[0];
    // Line 3 `G0 X0 Y0`; 4 the first feed move after it; 6 `X20 Y10
    // F600`; 8 `G0 Z5`; 9 `G0 X30 Y0`; 10 `G1 Z0 F300`; 13 `G1 X60 F900`;
    // 15 `X70 Y20 F1200`; 20 `G0 X0 Y0`; 21 the feed move after it.
    assert_eq!(
        first_lines(text, false),
        [1, 3, 4, 6, 8, 9, 10, 13, 15, 20, 21]
    );
    assert_eq!(first_lines(text, true), [1, 3, 8, 9, 20]);
    // The facts say whether a program has `/` lines.
    let facts = read_facts(OWN[2].as_bytes(), &ParseOptions::default())
        .unwrap()
        .unwrap();
    assert!(facts.block_delete);
    assert_eq!(first_lines(OWN[2], true), [1, 2, 8]);
    // The spline block (lines 4 to 8) is never cut.
    let spline = first_lines(OWN[3], false);
    assert!(spline.iter().all(|&l| !(5..=8).contains(&l)), "{spline:?}");
}

#[test]
fn facts_read_as_a_stream_are_those_of_the_whole_reading() {
    for text in OWN {
        let streamed = read_facts(text.as_bytes(), &ParseOptions::default())
            .unwrap()
            .unwrap();
        assert_eq!(streamed, ProgramFacts::of(&parse(text.as_bytes()).unwrap()));
    }
    // A program with o-words is read whole.
    let o = "o100 sub\nG1 X1 F100\no100 endsub\nG0 X0\no100 call\nM2\n";
    assert!(read_facts(o.as_bytes(), &ParseOptions::default())
        .unwrap()
        .is_none());
}

/// Every shared program: the facts, and the job in parts of one line for
/// each configuration.
#[test]
#[ignore = "corpus: every shared program (run by .ci/run)"]
fn every_shared_program_in_parts_is_written_as_whole() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    // The programs on every core, each checked whole by one worker; each
    // text once.
    let files = common::distinct_texts(common::files_under(&dir));
    let checked = fairpath::pipeline::par_map(files.len(), |i| check_in_parts(&files[i]));
    let compared: usize = checked.iter().map(|c| c.0).sum();
    let failures: Vec<String> = checked.into_iter().flat_map(|c| c.1).collect();
    assert!(compared > 400, "only {compared} compared");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The corpus check of one program (smaller than 100 kB, that reads): its
/// facts read as a stream against the whole reading's, and three of the
/// configurations (the corpus is large) in parts of one line against the
/// whole job: a corner method in arcs, one in G1 for LinuxCNC (G64 around
/// every run), and auto (the slowest) on the smaller programs. The number
/// of configurations compared and the failures.
fn check_in_parts(f: &std::path::Path) -> (usize, Vec<String>) {
    let mut failures = Vec::new();
    let mut compared = 0;
    let text = std::fs::read(f).unwrap();
    if text.len() > 100_000 {
        return (0, failures);
    }
    let Ok(program) = parse(&text) else {
        return (0, failures);
    };
    if let Some(facts) = read_facts(&text, &ParseOptions::default()).unwrap() {
        if facts != ProgramFacts::of(&program) {
            failures.push(format!("{}: facts differ", f.display()));
        }
    }
    for (method, format, controller) in [CONFIGS[0], CONFIGS[2], CONFIGS[5]] {
        if method == "auto" && text.len() > 10_000 {
            continue;
        }
        let opts = options(method, format, controller);
        compared += 1;
        if let Err(e) = same_in_parts(&text, &opts, 1) {
            failures.push(format!("{} {method} {format:?}: {e}", f.display()));
        }
    }
    (compared, failures)
}
