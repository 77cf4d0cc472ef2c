//! LinuxCNC's language (parameters, expressions, o-word control flow, polar
//! words) against LinuxCNC's own interpreter (`rs274 -g FILE`): fairpath's
//! reader sees the same canonical moves (straight traverse, straight feed,
//! arc end points) as rs274 on every shared program that uses the language
//! and on the small programs below, and `fairpath smooth` writes a program
//! (expanded, with its header, for o-word programs) that rs274 runs with the
//! moves fairpath meant.
//!
//! Without `rs274` the test is skipped with a message, unless
//! `FAIRPATH_REQUIRE_RS274` is set. The G6.2 programs of
//! `linuxcnc-nurbs/G6` need LinuxCNC master's interpreter
//! (`~/lcnc-master`, or `FAIRPATH_LCNC_MASTER`), and are skipped without it.

use crate::common;
use common::rs274::{have_rs274, master, rs274_of, same, Canon};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The moves fairpath's reader sees, in the program's units at each move.
fn ours(bytes: &[u8]) -> Result<Vec<Canon>, fairpath_gcode::GcodeError> {
    let p = fairpath_gcode::parse(bytes)?;
    Ok(p.moves()
        .iter()
        // rs274 -g prints spline blocks as NURBS calls without end points
        // (fairpath-gcode's tests/splines_rs274.rs compares them).
        .filter(|m| m.kind != fairpath_gcode::MoveKind::Spline)
        .map(|m| {
            let units = p.lines()[m.line - 1].units.mm_per_unit();
            let e = m.piece.end();
            let e = [e.x / units, e.y / units, e.z / units];
            match (&m.piece.curve, m.piece.rapid) {
                (fairpath::Curve::Arc(_), _) => Canon::Arc(e),
                (_, true) => Canon::Traverse(e),
                _ => Canon::Feed(e),
            }
        })
        .collect())
}

/// The text of a program outside its comments.
fn code(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let mut depth = false;
        for c in line.chars() {
            match c {
                ';' if !depth => break,
                '(' => depth = true,
                ')' => depth = false,
                _ if !depth => out.push(c),
                _ => {}
            }
        }
        out.push('\n');
    }
    out
}

/// Uses parameters, expressions, o-words or polar words.
fn uses_language(text: &str) -> bool {
    let c = code(text);
    c.contains('#')
        || c.contains('[')
        || c.contains('@')
        || c.contains('^')
        || c.lines().any(fairpath_gcode::lang::flow::looks_like_oword)
}

/// Every shared program that uses the language.
fn shared_programs() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/paths");
    let mut out = Vec::new();
    let mut stack = vec![root];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| {
                ["ngc", "nc", "gcode", "tap", "cnc"].contains(&e.to_str().unwrap_or(""))
            }) && std::fs::read(&p)
                .is_ok_and(|b| uses_language(&String::from_utf8_lossy(&b)))
            {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Small programs of the language, each run by rs274 and by fairpath.
const OWN: &[(&str, &str)] = &[
    (
        "params.ngc",
        "G21 G90 G17
#1 = 2.5
#<len> = [#1 * 4]
#<_glob> = 3
G0 X0 Y0 Z1
G1 Z-1 F300
G1 X#<len> Y[#1 + #<_glob>]
G1 X[#<len> / 2] Y[SQRT[16] + ABS[-1]]
G1 X[COS[60] * 10] Y[ATAN[1]/[1]]
G1 X[10 MOD 3] Y[2 ** 3]
G1 X[-7 MOD 3] Y[2 + 3 * 4 - 6 / 3 ** 2]
G1 X[#1 GT 2] Y[[1 EQ 1] + [2 LT 1] + [1 AND 0] + [1 OR 0] + [1 XOR 1]]
#2 = 1 #3 = #2 (#3 takes the old #2)
G1 X#3 Y#2
G1 X[FIX[2.7] + FUP[2.1] + ROUND[2.5]] Y[EXP[0] + LN[1]]
G1 X [ #2 + 1 ] Y 1 0.5
#4 = 2
G1 X##4 Y#[1 + 1]
G1 X[#<_x> + 1] Y[#5421 + 1] Z[#<_z> + 0.5]
G0 Z1
M2
",
    ),
    (
        "subs.ngc",
        "o<square> sub
  G1 X[#1 + #3] Y#2
  G1 X[#1 + #3] Y[#2 + #3]
  G1 X#1 Y[#2 + #3]
  G1 X#1 Y#2
o<square> endsub
o<twice> sub
  o<square> call [#1] [#2] [#3]
  o<square> call [#1 + 1] [#2 + 1] [#3 / 2]
  o<twice> return [#3 * 2]
o<twice> endsub
G21 G90
G0 X0 Y0 Z1
G1 Z-1 F200
o<twice> call [1] [2] [4]
G1 X#<_value> Y0
o<twice> call [10] [0] [2]
G1 X[#<_value> + 1] Y1
G1 X#1 Y#2 (the caller's #1 and #2 are back)
G0 Z1
M2
",
    ),
    (
        "loops.ngc",
        "G21 G90
G0 X0 Y0 Z1
G1 Z-1 F200
(do-while first: LinuxCNC 2.9 leaves the flag of a while loop's break set)
(and the next do-while then stops after one pass)
#2 = 0
o300 do
  G1 X[20 - #2] Y[#2 * 0.3]
  #2 = [#2 + 1]
o300 while [#2 LT 5]
#1 = 0
o100 while [#1 LT 10]
  #1 = [#1 + 1]
  o101 if [#1 EQ 3]
    o100 continue
  o101 elseif [#1 GT 7]
    o100 break
  o101 else
    G1 X#1 Y[#1 MOD 2]
  o101 endif
o100 endwhile
o200 repeat [4]
  G91 G1 X1 Y0.5
o200 endrepeat
G90
o400 repeat [0]
  G1 X100
o400 endrepeat
G0 Z1
M2
",
    ),
    (
        "polar.ngc",
        "G21 G90 G17
G0 X0 Y0 Z1
G1 Z-1 F200
G1 @10 ^0
G1 @10 ^30
G1 ^60
G1 @5
G91 G1 ^15
G91 G1 @2
G91 G1 @-1 ^-40
G90 G0 Z1
M2
",
    ),
    (
        "recursion.ngc",
        "o<count> sub
  #<depth> = #1
  G1 X#<depth> Y[#<depth> * 2]
  o1 if [#<depth> LT 5]
    o<count> call [#<depth> + 1]
  o1 endif
  G1 X[#<depth> + 0.5] Y#<depth> (the local survives the inner call)
o<count> endsub
G21 G90 G0 X0 Y0 Z0
G1 F100 X0
o<count> call [1]
G2 X[#<_x> + 2] Y#<_y> R1
M2
",
    ),
    (
        "inch_arcs.ngc",
        "G20 G90 G17
#<r> = 0.25
G0 X0 Y0 Z0.1
G1 Z-0.05 F20
o10 repeat [3]
  G91 G3 X[#<r> * 2] Y0 R#<r>
  G2 X[#<r> * 2] Y0 I#<r> J0
o10 endrepeat
G90 G0 Z0.1
M30
",
    ),
];

/// Runs `fairpath smooth` on `p` and returns the written program.
fn smooth(p: &Path, out: &Path) -> Result<String, String> {
    let o = Command::new(env!("CARGO_BIN_EXE_fairpath"))
        .args(["smooth", p.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(["--tolerance", "0.01mm"])
        .output()
        .unwrap();
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    Ok(std::fs::read_to_string(out).unwrap())
}

/// Compares the reading of `p` with `bin`'s, then runs what fairpath writes
/// of it through `bin`. Returns a line for the report, or the failure.
fn check(bin: &str, p: &Path, dir: &Path) -> Result<String, String> {
    let bytes = std::fs::read(p).unwrap();
    let name = p.display().to_string();
    let reference = match rs274_of(bin, p) {
        Ok(r) => r,
        Err(e) => return Ok(format!("{name}: skipped, rs274 rejects it: {e}")),
    };
    let read = fairpath_gcode::parse(&bytes);
    let prog = match read {
        Ok(p) => p,
        Err(e) if e.is_unsupported() => {
            return Ok(format!("{name}: skipped, unsupported: {e}"));
        }
        Err(e) => return Err(format!("{name}: fairpath rejects what rs274 reads: {e}")),
    };
    let mine = ours(&bytes).unwrap();
    same(&mine, &reference).map_err(|e| format!("{name}: reader disagrees with rs274: {e}"))?;
    if prog.is_empty() {
        return Ok(format!("{name}: no moves, as rs274 (nothing to write)"));
    }
    let out = dir.join("out.ngc");
    let written = smooth(p, &out).map_err(|e| format!("{name}: smooth fails: {e}"))?;
    if prog.expanded() != written.contains(fairpath_gcode::write_gcode::EXPANDED_HEADER) {
        return Err(format!(
            "{name}: expanded = {} but header presence differs",
            prog.expanded()
        ));
    }
    let theirs =
        rs274_of(bin, &out).map_err(|e| format!("{name}: rs274 rejects our output: {e}"))?;
    let again = ours(written.as_bytes())
        .map_err(|e| format!("{name}: fairpath rejects its output: {e}"))?;
    same(&again, &theirs)
        .map_err(|e| format!("{name}: rs274 reads our output differently: {e}"))?;
    Ok(format!(
        "{name}: same {} moves as rs274{}; output runs",
        mine.len(),
        if prog.expanded() { " (expanded)" } else { "" }
    ))
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn linuxcnc_reads_the_language_as_we_do() {
    if !have_rs274() {
        assert!(
            std::env::var_os("FAIRPATH_REQUIRE_RS274").is_none(),
            "rs274 is required (FAIRPATH_REQUIRE_RS274) but not installed"
        );
        eprintln!("rs274 (linuxcnc-uspace) not installed: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut report = Vec::new();
    let mut failures = Vec::new();
    let mut matched = 0;
    for (name, text) in OWN {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        match check("rs274", &p, dir.path()) {
            Ok(r) if r.contains("skipped") => failures.push(format!("own program {r}")),
            Ok(r) => {
                matched += 1;
                report.push(r)
            }
            Err(e) => failures.push(e),
        }
    }
    let master = master();
    let mut shared = 0;
    for p in shared_programs() {
        let g6 = p.components().any(|c| c.as_os_str() == "G6");
        let bin = match (&master, g6) {
            (_, false) => "rs274",
            (Some(m), true) => m.as_str(),
            (None, true) => {
                report.push(format!("{}: skipped, needs LinuxCNC master", p.display()));
                continue;
            }
        };
        match check(bin, &p, dir.path()) {
            Ok(r) => {
                if !r.contains("skipped") {
                    shared += 1;
                }
                report.push(r)
            }
            Err(e) => failures.push(e),
        }
    }
    eprintln!("{matched} own programs and {shared} shared programs match rs274:");
    for r in &report {
        eprintln!("  {r}");
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(matched, OWN.len());
    assert!(shared >= 10, "only {shared} shared programs compared");
}
