//! The habits of G-code tools (issue 22, item 3), one test per habit,
//! through the built binary: `-` for stdin and stdout, a default output
//! name, no overwriting the input, value enums in `--help`, tolerances
//! with units, exit codes, `check`'s worst place, continuity named C0/C1/C2,
//! errors with the source line and a caret.

mod common;
use common::{bin, example};
use std::path::Path;
use std::process::Output;

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
