//! LinuxCNC's own interpreter as a client (`rs274 -g FILE`, from Debian's
//! `linuxcnc-uspace`): on the reference programs, fairpath's reader sees the
//! same moves as LinuxCNC, and LinuxCNC runs every program fairpath writes
//! and sees the moves fairpath meant.
//!
//! Without `rs274` the test is skipped with a message, unless
//! `FAIRPATH_REQUIRE_RS274` is set (`.ci/run` sets it after installing
//! the package), in which case its absence is a failure.

use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Canon {
    Traverse([f64; 3]),
    Feed([f64; 3]),
    Arc,
}

/// Motion calls printed by `rs274 -g`, or the error it reports.
fn rs274(path: &Path) -> Result<Vec<Canon>, String> {
    let out = Command::new("rs274")
        .arg("-g")
        .arg(path)
        .output()
        .map_err(|e| e.to_string())?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!(
            "{}{}",
            stderr.trim(),
            stdout.lines().last().unwrap_or("")
        ));
    }
    let mut v = Vec::new();
    for line in stdout.lines() {
        let args = |l: &str| -> [f64; 3] {
            let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
            let n: Vec<f64> = inner
                .split(',')
                .take(3)
                .map(|x| x.trim().parse().unwrap())
                .collect();
            [n[0], n[1], n[2]]
        };
        if line.contains("STRAIGHT_TRAVERSE(") {
            v.push(Canon::Traverse(args(line)));
        } else if line.contains("STRAIGHT_FEED(") {
            v.push(Canon::Feed(args(line)));
        } else if line.contains("ARC_FEED(") {
            v.push(Canon::Arc);
        }
    }
    Ok(v)
}

/// The moves fairpath's reader sees, in the program's units at each move.
fn ours(bytes: &[u8]) -> Vec<Canon> {
    let p = fairpath_gcode::parse(bytes).unwrap();
    p.moves()
        .iter()
        .map(|m| {
            let units = p.lines()[m.line - 1].units.mm_per_unit();
            let e = m.piece.end();
            let e = [e.x / units, e.y / units, e.z / units];
            match (&m.piece.curve, m.piece.rapid) {
                (fairpath::Curve::Arc(_), _) => Canon::Arc,
                (_, true) => Canon::Traverse(e),
                _ => Canon::Feed(e),
            }
        })
        .collect()
}

fn close(p: &[f64; 3], q: &[f64; 3]) -> bool {
    p.iter().zip(q).all(|(u, v)| (u - v).abs() <= 1.5e-4)
}

/// Walks both lists of motion calls together: matching calls advance both;
/// a straight move that ends within print resolution (1e-4) of the last
/// matched position is a zero-length move on that side only (rs274 emits one
/// for a bare `G0`; moves below its %.4f print resolution vanish) and is
/// skipped; anything else is a disagreement.
fn same(a: &[Canon], b: &[Canon]) -> Result<(), String> {
    let (mut i, mut j) = (0, 0);
    let mut last = [0.0f64; 3];
    let end = |c: &Canon| match c {
        Canon::Traverse(p) | Canon::Feed(p) => Some(*p),
        Canon::Arc => None,
    };
    while i < a.len() && j < b.len() {
        let (x, y) = (&a[i], &b[j]);
        let matched = match (x, y) {
            (Canon::Traverse(p), Canon::Traverse(q)) | (Canon::Feed(p), Canon::Feed(q)) => {
                close(p, q)
            }
            (Canon::Arc, Canon::Arc) => true,
            _ => false,
        };
        if matched {
            if let Some(p) = end(y) {
                last = p;
            }
            i += 1;
            j += 1;
        } else if end(x).is_some_and(|p| close(&p, &last)) {
            i += 1;
        } else if end(y).is_some_and(|p| close(&p, &last)) {
            j += 1;
        } else {
            return Err(format!(
                "motion {i} / {j} of {} / {}: {x:?} vs {y:?} (after {last:?})",
                a.len(),
                b.len()
            ));
        }
    }
    let rest_a = a[i..]
        .iter()
        .all(|c| end(c).is_some_and(|p| close(&p, &last)));
    let rest_b = b[j..]
        .iter()
        .all(|c| end(c).is_some_and(|p| close(&p, &last)));
    if rest_a && rest_b {
        Ok(())
    } else {
        Err(format!(
            "{} motion calls vs {} (stopped at {i} / {j})",
            a.len(),
            b.len()
        ))
    }
}

fn have_rs274() -> bool {
    Command::new("rs274")
        .arg("-g")
        .arg("/dev/null")
        .output()
        .is_ok()
}

fn programs() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/paths");
    let mut out = Vec::new();
    for sub in ["linuxcnc", "synthetic"] {
        let mut stack = vec![root.join(sub)];
        while let Some(d) = stack.pop() {
            let Ok(rd) = std::fs::read_dir(&d) else {
                continue;
            };
            for e in rd {
                let p = e.unwrap().path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|e| e == "ngc")
                    && !p.ends_with("surface-raster-large.ngc")
                {
                    out.push(p);
                }
            }
        }
    }
    out.sort();
    out
}

#[test]
fn linuxcnc_reads_what_we_read_and_runs_what_we_write() {
    if !have_rs274() {
        assert!(
            std::env::var_os("FAIRPATH_REQUIRE_RS274").is_none(),
            "rs274 is required (FAIRPATH_REQUIRE_RS274) but not installed"
        );
        eprintln!("rs274 (linuxcnc-uspace) not installed: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mut compared, mut written) = (0, 0);
    let mut skipped = Vec::new();
    for p in programs() {
        let bytes = std::fs::read(&p).unwrap();
        match fairpath_gcode::parse(&bytes) {
            Ok(prog) if !prog.pieces().is_empty() => {}
            _ => continue, // rejected by our reader, or nothing to smooth
        }
        let name = p.display().to_string();
        let reference = match rs274(&p) {
            Ok(r) => r,
            Err(e) => {
                skipped.push(format!("{name}: rs274 rejects the original: {e}"));
                continue;
            }
        };
        // Programs that move in machine coordinates or change offsets are
        // not modelled position by position by our reader (see its docs).
        let text = String::from_utf8_lossy(&bytes).to_uppercase();
        let offsets = [
            "G28", "G30", "G53", "G92", "G10", "G54", "G55", "G43", "G41", "G42", "G33", "G38",
            "G76",
        ]
        .iter()
        .any(|g| text.contains(g));
        if !offsets {
            same(&ours(&bytes), &reference)
                .unwrap_or_else(|e| panic!("{name}: reader disagrees with rs274: {e}"));
            compared += 1;
        }
        // What we write, LinuxCNC runs, and it sees the moves we meant.
        let out = dir.path().join("out.ngc");
        let o = Command::new(env!("CARGO_BIN_EXE_fairpath"))
            .args([
                "smooth",
                p.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--tolerance",
                "0.01",
            ])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let theirs =
            rs274(&out).unwrap_or_else(|e| panic!("{name}: rs274 rejects our output: {e}"));
        if !offsets {
            same(&ours(&std::fs::read(&out).unwrap()), &theirs)
                .unwrap_or_else(|e| panic!("{name}: rs274 reads our output differently: {e}"));
        }
        written += 1;
    }
    eprintln!("compared {compared} programs with rs274, {written} outputs run by rs274; skipped:");
    for s in &skipped {
        eprintln!("  {s}");
    }
    assert!(
        written > 50 && compared > 50,
        "compared {compared}, written {written}"
    );
}
