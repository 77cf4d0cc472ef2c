//! The habits of G-code tools (issue 22, item 3), one test per habit,
//! through the built binary: `-` for stdin and stdout, a default output
//! name, no overwriting the input, value enums in `--help`, tolerances
//! with units, exit codes, `check`'s worst place, continuity named C0/C1/C2,
//! errors with the source line and a caret.

use crate::common;
use common::{bin, example};
use std::io::Write;
use std::path::Path;
use std::process::{Output, Stdio};

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts that the command succeeded, showing what it printed if not.
fn assert_ok(o: &Output, what: &str) {
    assert!(o.status.success(), "{what}: {}{}", stdout(o), stderr(o));
}

fn path_str(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn continuity_is_named_c0_c1_c2_not_g_words() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("z.ngc");
    let input = example("zigzag.ngc");
    let o = run(&[
        "smooth",
        path_str(&input),
        "-o",
        path_str(&out),
        "-t",
        "0.05",
    ]);
    assert_ok(&o, "smooth");
    let text = stdout(&o);
    let joints = text.lines().find(|l| l.contains("joints:")).unwrap();
    assert!(joints.contains(" C2 (curvature continuous)"), "{joints}");
    assert!(!joints.contains("G2") && !joints.contains("G0"), "{joints}");
    let o = run(&[
        "smooth",
        path_str(&input),
        "-o",
        path_str(&out),
        "-t",
        "0.05",
        "--json-summary",
    ]);
    assert_ok(&o, "smooth --json-summary");
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!(v["joints"]["C2"].as_u64().unwrap() > 0, "{v}");
    assert!(v["joints"].get("G2").is_none(), "{v}");
    let o = run(&[
        "compare",
        path_str(&input),
        "-t",
        "0.05",
        "--methods",
        "ctm",
        "--format",
        "json",
    ]);
    assert_ok(&o, "compare");
    let rows: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!(rows[1]["c2"].as_u64().unwrap() > 0, "{rows}");
    assert!(rows[1].get("g2").is_none(), "{rows}");
    let o = run(&[
        "compare",
        path_str(&input),
        "-t",
        "0.05",
        "--methods",
        "ctm",
    ]);
    assert_ok(&o, "compare");
    assert!(stdout(&o).contains("C2/C1/C0/gap"), "{}", stdout(&o));
}

/// Runs `args` with `input` on standard input.
fn run_stdin(args: &[&str], input: &[u8]) -> Output {
    let mut child = bin()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // A command that refuses its arguments exits before reading.
    let _ = child.stdin.take().unwrap().write_all(input);
    child.wait_with_output().unwrap()
}

/// A square whose second side the "smoothed" copy moves 0.1 mm out at its
/// middle (line 4 of the original is that side).
const SQUARE: &str = "G21 G90 G17\nG0 X0 Y0\nG1 X10 Y0 F600\nG1 X10 Y10\nG1 X0 Y10\nG1 X0 Y0\nM2\n";
const SQUARE_BENT: &str =
    "G21 G90 G17\nG0 X0 Y0\nG1 X10 Y0 F600\nG1 X10.1 Y5\nG1 X10 Y10\nG1 X0 Y10\nG1 X0 Y0\nM2\n";
/// The square in inches.
const SQUARE_INCH: &str = "G20 G90 G17\nG0 X0 Y0\nG1 X1 Y0 F20\nG1 X1 Y1\nG1 X0 Y1\nG1 X0 Y0\nM2\n";

#[test]
fn dash_is_standard_input_and_output() {
    let text = std::fs::read(example("zigzag.ngc")).unwrap();
    // smooth - -o -: the program alone on stdout, the summary on stderr.
    let o = run_stdin(&["smooth", "-", "-o", "-", "-t", "0.05mm"], &text);
    assert_ok(&o, "smooth - -o -");
    let written = stdout(&o);
    assert!(
        written.contains("G1") || written.contains("G2"),
        "{written}"
    );
    assert!(!written.contains("fairpath smooth:"), "{written}");
    assert!(
        stderr(&o).contains("fairpath smooth: <stdin> -> <stdout>"),
        "{}",
        stderr(&o)
    );
    // What came out reads back and checks against the input, the smoothed
    // program read from stdin.
    let dir = tempfile::tempdir().unwrap();
    let original = dir.path().join("zigzag.ngc");
    std::fs::write(&original, &text).unwrap();
    let o = run_stdin(
        &["check", path_str(&original), "-", "-t", "0.05mm"],
        written.as_bytes(),
    );
    assert_ok(&o, "check ORIGINAL -");
    assert!(stdout(&o).contains("PASS"), "{}", stdout(&o));
    // A stdin input without -o goes to stdout; no file named - appears.
    let o = run_stdin(&["smooth", "-", "-t", "0.05mm"], &text);
    assert_ok(&o, "smooth -");
    assert!(stdout(&o).contains("G1"), "{}", stdout(&o));
    assert!(!Path::new("-").exists());
    // simulate and compare read stdin.
    let o = run_stdin(&["simulate", "-", "--format", "json"], &text);
    assert_ok(&o, "simulate -");
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!(v["time_s"].as_f64().unwrap() > 0.0, "{v}");
    let o = run_stdin(
        &[
            "compare",
            "-",
            "-t",
            "0.05mm",
            "--methods",
            "ctm",
            "--format",
            "json",
        ],
        &text,
    );
    assert_ok(&o, "compare -");
    // Both check inputs on stdin is a usage error.
    let o = run_stdin(&["check", "-", "-", "-t", "0.05"], &text);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // --in-place on stdin is a usage error.
    let o = run_stdin(&["smooth", "-", "--in-place", "-t", "0.05"], &text);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// `simulate --profile -` and `--segments -` write their CSV to standard
/// output, alone (the summary goes to standard error), and no file named
/// `-` appears; both on standard output is a usage error.
#[test]
fn simulate_csv_to_standard_output() {
    let zigzag = example("zigzag.ngc");
    let z = path_str(&zigzag);
    for (flag, header) in [("--profile", "t,s,v,a,j,x,y,z"), ("--segments", "s0,")] {
        let dir = tempfile::tempdir().unwrap();
        let o = bin()
            .current_dir(dir.path())
            .args(["simulate", z, flag, "-"])
            .output()
            .unwrap();
        assert_ok(&o, flag);
        let out = stdout(&o);
        assert!(out.starts_with(header), "{flag}: {out}");
        assert!(!out.contains("fairpath simulate:"), "{flag}: {out}");
        assert!(stderr(&o).contains("fairpath simulate:"), "{}", stderr(&o));
        assert!(
            !dir.path().join("-").exists(),
            "{flag} wrote a file named -"
        );
    }
    let o = run(&["simulate", z, "--profile", "-", "--segments", "-"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn default_output_is_beside_the_input_with_its_extension() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("part.ngc");
    std::fs::copy(example("zigzag.ngc"), &input).unwrap();
    let o = run(&["smooth", path_str(&input), "-t", "0.05"]);
    assert_ok(&o, "smooth without -o");
    let out = dir.path().join("part.smoothed.ngc");
    assert!(out.exists(), "{}", stdout(&o));
    assert!(stdout(&o).contains(path_str(&out)), "{}", stdout(&o));
    let o = run(&["smooth", path_str(&input), "-t", "0.05", "--format", "json"]);
    assert_ok(&o, "smooth --format json without -o");
    let out = dir.path().join("part.smoothed.json");
    assert!(out.exists(), "{}", stdout(&o));
    let nc = dir.path().join("part.nc");
    std::fs::copy(&input, &nc).unwrap();
    assert_ok(&run(&["smooth", path_str(&nc), "-t", "0.05"]), "part.nc");
    assert!(dir.path().join("part.smoothed.nc").exists());
}

#[test]
fn the_input_is_not_overwritten_without_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("part.ngc");
    std::fs::copy(example("zigzag.ngc"), &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    // The same file through another path.
    let other = sub.join("..").join("part.ngc");
    for o in [&input, &other] {
        let out = run(&["smooth", path_str(&input), "-o", path_str(o), "-t", "0.05"]);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        let e = stderr(&out);
        assert!(e.contains("--in-place") && e.contains("refusing"), "{e}");
        assert_eq!(std::fs::read(&input).unwrap(), before);
    }
    let out = run(&["smooth", path_str(&input), "--in-place", "-t", "0.05"]);
    assert_ok(&out, "--in-place");
    assert_ne!(std::fs::read(&input).unwrap(), before);
}

#[test]
fn methods_formats_and_other_values_are_listed_in_help() {
    let o = run(&["smooth", "--help"]);
    assert_ok(&o, "smooth --help");
    let help = stdout(&o);
    for name in fairpath::choose::METHODS {
        assert!(help.contains(&format!("- {name}:")), "{name}: {help}");
    }
    for value in [
        "- arcs:",
        "- g6.2:",
        "- json:",
        "- linuxcnc:",
        "- thesis:",
        "- half:",
    ] {
        assert!(help.contains(value), "{value}: {help}");
    }
    assert!(help.contains("program's units"), "{help}");
    assert!(help.contains("Exit status:"), "{help}");
    let o = run(&["compare", "--help"]);
    assert!(stdout(&o).contains("- bspline-fit:"), "{}", stdout(&o));
    // An unknown method is a parse error that lists the names.
    let o = run(&["smooth", "x.ngc", "-t", "0.05", "-m", "bogus"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("bspline-corner"), "{}", stderr(&o));
}

#[test]
fn tolerance_takes_units_and_defaults_to_the_programs() {
    let dir = tempfile::tempdir().unwrap();
    let inch = dir.path().join("inch.ngc");
    std::fs::write(&inch, SQUARE_INCH).unwrap();
    let out = dir.path().join("o.ngc");
    let summary = |tol: &str| {
        let o = run(&[
            "smooth",
            path_str(&inch),
            "-o",
            path_str(&out),
            "-t",
            tol,
            "--json-summary",
        ]);
        assert_ok(&o, tol);
        let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
        v["tolerance_mm"].as_f64().unwrap()
    };
    // A bare number in a G20 program is inches.
    assert!((summary("0.002") - 0.0508).abs() < 1e-12);
    assert!((summary("0.002in") - 0.0508).abs() < 1e-12);
    assert_eq!(summary("0.05mm"), 0.05);
    let o = run(&[
        "smooth",
        path_str(&inch),
        "-o",
        path_str(&out),
        "-t",
        "0.002",
    ]);
    let first = stdout(&o).lines().next().unwrap().to_string();
    assert!(first.contains("0.0508 mm = 0.002 in"), "{first}");
    // A bare number in a G21 program is mm.
    let mm = dir.path().join("mm.ngc");
    std::fs::write(&mm, SQUARE).unwrap();
    let o = run(&["smooth", path_str(&mm), "-o", path_str(&out), "-t", "0.05"]);
    let first = stdout(&o).lines().next().unwrap().to_string();
    assert!(first.contains("tolerance 0.05 mm)"), "{first}");
    // Negative and zero: an error naming the option and the value, exit 2,
    // no parser tip about `--`.
    for bad in ["-0.05", "0", "-0.002in"] {
        let o = run(&["smooth", path_str(&mm), "-o", path_str(&out), "-t", bad]);
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains("--tolerance") && e.contains(bad), "{e}");
        assert!(e.contains("positive") && !e.contains("tip:"), "{e}");
    }
}

#[test]
fn usage_errors_exit_2_failures_to_verify_3_other_errors_1() {
    let dir = tempfile::tempdir().unwrap();
    let square = dir.path().join("square.ngc");
    std::fs::write(&square, SQUARE).unwrap();
    let bent = dir.path().join("bent.ngc");
    std::fs::write(&bent, SQUARE_BENT).unwrap();
    let out = dir.path().join("o.ngc");
    let (s, b, o) = (path_str(&square), path_str(&bent), path_str(&out));
    let code = |args: &[&str]| run(args).status.code();
    // Usage: found by clap, and found after parsing.
    for args in [
        &["smooth", s, "-o", o][..],
        &["smooth", s, "-o", o, "-t", "abc"],
        &["smooth", s, "-o", o, "-t", "5000mm"],
        &["smooth", s, "-o", o, "-t", "0.05", "--chord", "1"],
        &["smooth", s, "-o", o, "-t", "0.05", "--step-share", "-1"],
        &["smooth", s, "-o", o, "-t", "0.05", "--max-feed", "-5"],
        &[
            "smooth", s, "-o", o, "-t", "0.05", "-m", "ctm", "--lambda", "0.5",
        ],
        &["smooth", s, "-o", s, "-t", "0.05"],
        &["check", s, b, "-t", "5000mm"],
        &["compare", s, "-t", "0.05", "--methods", "bogus"],
        &["simulate", s, "--acc", "-1"],
    ] {
        assert_eq!(code(args), Some(2), "{args:?}");
    }
    // Failures to verify: check and compare 3.
    assert_eq!(code(&["check", s, b, "-t", "0.05"]), Some(3));
    assert_eq!(code(&["check", s, b, "-t", "0.2"]), Some(0));
    // Other errors: 1.
    let missing = dir.path().join("missing.ngc");
    assert_eq!(
        code(&["smooth", path_str(&missing), "-o", o, "-t", "0.05"]),
        Some(1)
    );
    let bad = dir.path().join("bad.ngc");
    std::fs::write(&bad, "G1 X1 Q\n").unwrap();
    assert_eq!(
        code(&["smooth", path_str(&bad), "-o", o, "-t", "0.05"]),
        Some(1)
    );
    let help = stdout(&run(&["--help"]));
    assert!(
        help.contains("Exit status:") && help.contains("  2  usage"),
        "{help}"
    );
}

#[test]
fn check_says_where_the_worst_place_is() {
    let dir = tempfile::tempdir().unwrap();
    let square = dir.path().join("square.ngc");
    std::fs::write(&square, SQUARE).unwrap();
    let bent = dir.path().join("bent.ngc");
    std::fs::write(&bent, SQUARE_BENT).unwrap();
    let o = run(&["check", path_str(&square), path_str(&bent), "-t", "0.05"]);
    assert_eq!(o.status.code(), Some(3));
    let text = stdout(&o);
    let worst = text.lines().find(|l| l.contains("worst place:")).unwrap();
    assert!(
        worst.contains("line 4 of") && worst.contains("G1 X10 Y10"),
        "{text}"
    );
    assert!(worst.contains("0.100000 mm"), "{text}");
    assert!(text.contains("at X10.1000 Y5.0000 Z0.0000 mm"), "{text}");
    let o = run(&[
        "check",
        path_str(&square),
        path_str(&bent),
        "-t",
        "0.05",
        "--format",
        "json",
    ]);
    assert_eq!(o.status.code(), Some(3));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["pass"], false, "{v}");
    assert_eq!(v["worst"]["original_line"], 4, "{v}");
    assert_eq!(v["worst"]["at_mm"][0], 10.1, "{v}");
    assert!(
        (v["worst"]["deviation_mm"].as_f64().unwrap() - 0.1).abs() < 1e-9,
        "{v}"
    );
    assert!(v["max_deviation_mm"].as_f64().unwrap() >= 0.1, "{v}");
}

#[test]
fn reader_errors_show_the_line_with_a_caret_and_a_hint() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.ngc");
    std::fs::write(&bad, "G21 G90\nG1 X1 Y2 F100\nG1 X2 Y3 Q\n").unwrap();
    let out = dir.path().join("o.ngc");
    let o = run(&["smooth", path_str(&bad), "-o", path_str(&out), "-t", "0.05"]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    let lines: Vec<&str> = e.lines().collect();
    let first = lines.iter().position(|l| l.starts_with("error: ")).unwrap();
    assert!(lines[first].contains("bad.ngc:3:10: "), "{e}");
    assert_eq!(lines[first + 2], "3 | G1 X2 Y3 Q", "{e}");
    // The caret under column 10 (the Q).
    assert_eq!(lines[first + 3], format!("  | {}^", " ".repeat(9)), "{e}");
    assert!(lines[first + 4].contains("hint:"), "{e}");
    assert!(!out.exists());
}
