//! `smooth --method none`: the program back through the whole verified
//! pipeline with its geometry unchanged, a parameterised program expanded
//! into plain moves.

use std::path::Path;
use std::process::Command;

fn smooth_none(input: &Path, output: &Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_fairpath"))
        .args([
            "smooth",
            input.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ])
        .args(["--tolerance", "0.05mm", "--method", "none"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The feed and rapid moves of a program: (curve, rapid, feed).
fn moves(text: &[u8]) -> Vec<(fairpath::geom::Curve, bool, Option<f64>)> {
    fairpath_gcode::parse(text)
        .unwrap()
        .moves()
        .iter()
        .map(|m| (m.piece.curve.clone(), m.piece.rapid, m.piece.feed))
        .collect()
}

#[test]
fn none_writes_every_move_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for name in ["pocket-corners.ngc", "rhombus.ngc", "zigzag.ngc"] {
        let input = examples.join(name);
        let out = dir.path().join(name);
        smooth_none(&input, &out);
        let (a, b) = (std::fs::read(&input).unwrap(), std::fs::read(&out).unwrap());
        assert_eq!(moves(&a), moves(&b), "{name}");
    }
}

#[test]
fn none_expands_a_parameterised_program() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("loop.ngc");
    std::fs::write(
        &input,
        "G21 G90 G17\nG0 X0 Y0 Z1\nG1 Z0 F600\n#1 = 0\no100 while [#1 LT 5]\n\
         G1 X[#1 * 2 + 1] Y[#1 MOD 2]\n#1 = [#1 + 1]\no100 endwhile\nG0 Z1\nM2\n",
    )
    .unwrap();
    let out = dir.path().join("out.ngc");
    smooth_none(&input, &out);
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(!written.to_lowercase().contains("o100"), "{written}");
    assert!(!written.contains('#'), "{written}");
    let feeds: Vec<_> = moves(written.as_bytes())
        .into_iter()
        .filter(|m| !m.1)
        .collect();
    // The plunge and the five moves of the loop.
    assert_eq!(feeds.len(), 6, "{written}");
    assert_eq!(
        moves(written.as_bytes()),
        moves(&std::fs::read(&input).unwrap()),
        "{written}"
    );
}

/// `--window-lines`: a long run cut into windows is written back, with
/// `none`, as the program wrote it, and the summary counts it as the one
/// run it is; 0 cuts no run.
#[test]
fn none_in_windows_writes_the_program_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("raster.ngc");
    let mut text = String::from("G21 G90 G17\nG0 X0 Y0 Z1\nG1 Z0 F2000\n");
    for i in 1..=2000 {
        let x = (i % 100) as f64 * 1.5;
        text += &format!("X{x:.3} Y{:.3} Z{:.4}\n", (i / 100) as f64, (x * 0.3).sin());
    }
    text += "G0 Z5\nM2\n";
    std::fs::write(&input, &text).unwrap();
    let out = dir.path().join("out.ngc");
    let run = |window: &str| {
        Command::new(env!("CARGO_BIN_EXE_fairpath"))
            .args([
                "smooth",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args([
                "--tolerance",
                "0.05mm",
                "--method",
                "none",
                "--window-lines",
                window,
            ])
            .output()
            .unwrap()
    };
    let o = run("300");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = String::from_utf8_lossy(&o.stdout);
    assert!(summary.contains("2001 feed moves in 1 runs"), "{summary}");
    // (The curves hold each cut line as its two halves: the run was cut.)
    let pieces: usize = summary
        .lines()
        .find_map(|l| l.trim().strip_prefix("curves:"))
        .and_then(|l| l.split_whitespace().next()?.parse().ok())
        .unwrap();
    assert!(pieces > 2001 + 3, "{summary}");
    let written = std::fs::read_to_string(&out).unwrap();
    let body: Vec<&str> = written
        .lines()
        .filter(|l| !l.starts_with("(smoothed"))
        .collect();
    assert_eq!(body, text.lines().collect::<Vec<_>>());
    let whole = run("0");
    assert!(whole.status.success());
    let summary = String::from_utf8_lossy(&whole.stdout);
    assert!(
        summary.contains("curves:          2001 pieces"),
        "{summary}"
    );
}
