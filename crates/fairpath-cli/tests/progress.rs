//! The progress line: on a terminal's standard error (a pseudo-terminal
//! made by util-linux `script`), never in a pipe, never with `--quiet`, and
//! erased when the job ends. `FAIRPATH_PROGRESS_DELAY_MS=0` shows it at
//! once (a second's delay by default). Skipped without `script`.

use std::path::Path;
use std::process::Command;

const ERASE: &str = "\r\x1b[2K";

fn have_script() -> bool {
    Command::new("script")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs `fairpath smooth` on a large enough program with `extra` flags,
/// under a pseudo-terminal when `tty`; returns everything it printed.
fn run(tty: bool, extra: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    run_on(&root.join("examples/zigzag.ngc"), tty, extra)
}

/// [`run`] on `program`.
fn run_on(program: &Path, tty: bool, extra: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let cmd = format!(
        "{} smooth {} -t 0.05mm -m bspline-corner -o {} {extra}",
        env!("CARGO_BIN_EXE_fairpath"),
        program.display(),
        out.display()
    );
    let o = if tty {
        Command::new("script")
            .args(["-qec", &cmd, "/dev/null"])
            .env("FAIRPATH_PROGRESS_DELAY_MS", "0")
            .output()
            .unwrap()
    } else {
        Command::new("sh")
            .args(["-c", &cmd])
            .env("FAIRPATH_PROGRESS_DELAY_MS", "0")
            .output()
            .unwrap()
    };
    assert!(o.status.success());
    String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr)
}

#[test]
fn progress_shows_on_a_terminal_only_and_not_when_quiet() {
    if !have_script() {
        eprintln!("script (util-linux) not installed: skipped");
        return;
    }
    // The step names come from the library's clock, so a slow step of a
    // small program may still pass unseen: retried a few times.
    let shown = (0..5).any(|_| {
        let t = run(true, "");
        t.contains(ERASE) && t.contains("fairpath smooth:")
    });
    assert!(shown, "no progress line on a terminal");
    assert!(!run(true, "--quiet").contains(ERASE));
    assert!(!run(false, "").contains(ERASE));
}

/// A program processed in several parts gets a bar with the share of its
/// lines written.
#[test]
fn a_long_program_shows_a_bar_of_the_lines_written() {
    if !have_script() {
        eprintln!("script (util-linux) not installed: skipped");
        return;
    }
    // 300 passes of 20 moves, a rapid before each: about 6,600 lines,
    // several parts of fairpath_gcode::PART_LINES.
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("passes.ngc");
    let mut text = String::from("G21 G90\n");
    for pass in 0..300 {
        let y = pass as f64 * 0.5;
        text += &format!("G0 X0 Y{y}\nG1 X0.5 F3000\n");
        for k in 1..20 {
            text += &format!("G1 X{} Y{:.3}\n", k as f64 * 2.0, y + 0.2 * (k % 2) as f64);
        }
    }
    text += "M2\n";
    std::fs::write(&program, text).unwrap();
    let shown = (0..5).any(|_| run_on(&program, true, "").contains("% of 6302 lines"));
    assert!(shown, "no bar on a terminal");
}
