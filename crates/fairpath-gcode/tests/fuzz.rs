//! Seeded mutational fuzzing: bad input never panics.
//!
//! Inputs are mutations ([`mutate`]) of the small reference programs under
//! `shared/paths` (read in place) and of JSON documents `write_json` makes
//! of them; each goes through the reader, `read_json`, smoothing, the
//! writers and a re-read ([`exercise`]). Any panic fails the test; the
//! input is written under the target directory and its seed and index are
//! printed, so `FAIRPATH_FUZZ_INPUT=FILE` replays it.
//!
//! Environment:
//! * `FAIRPATH_FUZZ_SEED` (decimal or `0x` hex): the seed (default
//!   [`DEFAULT_SEED`]; the same seed gives the same inputs).
//! * `FAIRPATH_FUZZ_SECONDS`: run for this long instead of
//!   [`DEFAULT_COUNT`] inputs (`scripts/fuzz.sh` runs it in release).
//! * `FAIRPATH_FUZZ_COUNT`: the number of inputs.
//! * `FAIRPATH_FUZZ_INPUT`: a file to run alone (G-code, or JSON when it
//!   starts with `{`).

use crate::common;
#[path = "fuzz/exercise.rs"]
mod exercise;
#[path = "fuzz/mutate.rs"]
mod mutate;
#[path = "fuzz/rng.rs"]
mod rng;

use exercise::{exercise_gcode, exercise_json, Outcome};
use fairpath::choose::Auto;
use fairpath::path::Piece;
use fairpath::smooth::Smoother;
use fairpath_gcode::{parse, write_json, Program};
use rng::Rng;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The seed of the CI run.
const DEFAULT_SEED: u64 = 0x5EED_F00D;
/// Inputs tried in CI (well under a minute in the test profile).
const DEFAULT_COUNT: u64 = 2000;
/// Reference programs up to this size are seeds: small ones keep each
/// input fast and the mutations dense.
const MAX_SEED_BYTES: u64 = 4096;
/// An input running longer than this is reported as a hang and the test
/// process exits (a stuck thread cannot be stopped otherwise).
const HANG_SECONDS: u64 = 60;

/// The seed inputs: G-code programs, and JSON documents with the program
/// each was written from.
struct Seeds {
    gcode: Vec<Vec<u8>>,
    json: Vec<(String, Program)>,
}

/// Small built-in programs, used alongside the shared ones (and alone when
/// `shared/paths` is missing): arcs in three planes, a helix, splines.
const BUILTIN: &[&str] = &[
    "G21 G90 G17\nG0 X0 Y0\nG1 X1 Y0.1 F600\nG1 X2 Y0\nG1 X3 Y0.2\nG2 X5 Y0 I1 J0\nG1 X6 Y1\nM2\n",
    "G20 G91\nG1 X0.1 F10\nY0.1\nX-0.1\nG3 X0 Y0 R0.5 Z0.1\nG18 G2 X0.1 Z0 K0.05\nM30\n",
    "G21\nG1 X0 Y0 F100\nG5.2 X1 Y0 P1 L3\nX2 Y1 P2\nX3 Y0 P1\nX4 Y0 P1\nG5.3\nG1 X5 Y0\nM2\n",
    "G21\nG1 X0 Y0 F100\nG6.2 P4 K0 X0 Y0 R1\nK0 X1 Y1 R1\nK0 X2 Y0 R1\nK0 X3 Y1 R1\nK1\nK1\nK1\nK1\nG1 X4\nM2\n",
    "G21\nG1 X0 Y0 F100\nG5 I1 J0 P1 Q-1 X2 Y0\nG5.1 I1 J1 X3 Y0\nG1 X4\nM2\n",
];

fn seeds() -> Seeds {
    let mut gcode: Vec<Vec<u8>> = BUILTIN.iter().map(|s| s.as_bytes().to_vec()).collect();
    if let Some(dir) = common::shared_paths() {
        for f in common::files_under(&dir) {
            if std::fs::metadata(&f).is_ok_and(|m| m.len() <= MAX_SEED_BYTES) {
                gcode.push(std::fs::read(&f).unwrap());
            }
        }
    }
    let mut json = Vec::new();
    for g in &gcode {
        let Ok(p) = parse(g) else { continue };
        if p.moves().len() > exercise::MAX_SMOOTHED_MOVES {
            continue;
        }
        // Both the smoothed curves and the program's own pieces (arcs are
        // written as rational quadratics and cubic approximations).
        let method = Auto::default();
        let smoothed: Vec<Vec<Piece>> = p
            .runs()
            .iter()
            .map(|r| {
                method
                    .smooth_run(r, exercise::TOLERANCE_MM - exercise::CHORD_MM)
                    .map_or_else(|_| r.pieces.clone(), |s| s.pieces)
            })
            .collect();
        let own: Vec<Vec<Piece>> = p.runs().into_iter().map(|r| r.pieces).collect();
        for pieces in [smoothed, own] {
            if let Ok(j) = write_json(&p, &pieces) {
                json.push((j, p.clone()));
            }
        }
        if json.len() >= 40 {
            break;
        }
    }
    Seeds { gcode, json }
}

fn env_u64(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    let v = v.trim();
    let parsed = match v.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => v.parse(),
    };
    Some(parsed.unwrap_or_else(|_| panic!("{name}={v} is not a number")))
}

/// Where failing inputs are written.
fn failure_dir() -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The input being run and when it started, for the watchdog.
type Current = Arc<Mutex<(Instant, String, Vec<u8>)>>;

/// Exits the process when one input runs longer than [`HANG_SECONDS`],
/// after writing it out. Stops when the fuzz run drops `current` (the
/// other tests of this binary go on after it).
fn watchdog(current: &Current) {
    let current = Arc::downgrade(current);
    std::thread::spawn(move || loop {
        std::thread::sleep(Duration::from_secs(1));
        let Some(current) = current.upgrade() else {
            break;
        };
        let cur = current.lock().unwrap();
        if cur.0.elapsed() > Duration::from_secs(HANG_SECONDS) {
            let path = failure_dir().join(format!("hang-{}", cur.1));
            std::fs::write(&path, &cur.2).unwrap();
            eprintln!(
                "fuzz: input {} ran for more than {HANG_SECONDS} s (in {}); written to {}",
                cur.1,
                exercise::current_stage(),
                path.display()
            );
            std::process::exit(2);
        }
    });
}

/// One generated input: its bytes, whether it is JSON, and the program a
/// JSON input was written from.
struct Input<'a> {
    bytes: Vec<u8>,
    json_of: Option<&'a Program>,
}

fn generate<'a>(rng: &mut Rng, seeds: &'a Seeds) -> Input<'a> {
    if !seeds.json.is_empty() && rng.below(10) < 3 {
        let (text, program) = rng.pick(&seeds.json);
        Input {
            bytes: mutate::mutate_json(rng, text),
            json_of: Some(program),
        }
    } else {
        let g = rng.pick(&seeds.gcode);
        Input {
            bytes: mutate::mutate_bytes(rng, g, &seeds.gcode),
            json_of: None,
        }
    }
}

fn run(input: &Input) -> Outcome {
    match input.json_of {
        Some(p) => exercise_json(&input.bytes, Some(p)),
        None => exercise_gcode(&input.bytes),
    }
}

#[test]
fn mutated_programs_and_json_never_panic() {
    if let Ok(path) = std::env::var("FAIRPATH_FUZZ_INPUT") {
        let bytes = std::fs::read(&path).unwrap();
        let is_json = bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
        let out = if is_json {
            exercise_json(&bytes, None)
        } else {
            exercise_gcode(&bytes)
        };
        println!(
            "fuzz: {path}: accepted {}, {:?}",
            out.accepted, out.anomalies
        );
        assert!(out.panic.is_none(), "{path}: {:?}", out.panic);
        return;
    }
    let seed = env_u64("FAIRPATH_FUZZ_SEED").unwrap_or(DEFAULT_SEED);
    let seconds = env_u64("FAIRPATH_FUZZ_SECONDS");
    let count = env_u64("FAIRPATH_FUZZ_COUNT").unwrap_or(DEFAULT_COUNT);
    let seeds = seeds();
    let readable = seeds.gcode.iter().filter(|g| parse(g).is_ok()).count();
    println!(
        "fuzz: seed {seed:#x} (FAIRPATH_FUZZ_SEED), {} G-code ({readable} readable) and {} JSON seed inputs, {}",
        seeds.gcode.len(),
        seeds.json.len(),
        match seconds {
            Some(s) => format!("for {s} s"),
            None => format!("{count} inputs"),
        }
    );
    let current: Current = Arc::new(Mutex::new((Instant::now(), String::new(), Vec::new())));
    watchdog(&current);
    let started = Instant::now();
    let mut panics: Vec<(String, String, PathBuf)> = Vec::new();
    let mut anomalies: Vec<(String, String, PathBuf)> = Vec::new();
    let (mut tried, mut accepted) = (0u64, 0u64);
    let mut slowest = (String::new(), 0.0, Vec::new());
    loop {
        let done = match seconds {
            Some(s) => started.elapsed() >= Duration::from_secs(s),
            None => tried >= count,
        };
        if done {
            break;
        }
        let mut rng = Rng::for_input(seed, tried);
        let input = generate(&mut rng, &seeds);
        let ext = if input.json_of.is_some() {
            "json"
        } else {
            "ngc"
        };
        let name = format!("{seed:x}-{tried}.{ext}");
        *current.lock().unwrap() = (Instant::now(), name.clone(), input.bytes.clone());
        let began = Instant::now();
        let out = run(&input);
        let took = began.elapsed().as_secs_f64();
        if took > slowest.1 {
            slowest = (name.clone(), took, input.bytes.clone());
        }
        tried += 1;
        accepted += u64::from(out.accepted);
        let save = |kind: &str| {
            let path = failure_dir().join(format!("{kind}-{name}"));
            std::fs::write(&path, &input.bytes).unwrap();
            path
        };
        if let Some(p) = out.panic {
            let where_ = format!("{} in {}", p.message, p.stage);
            // One input per distinct panic (location and stage).
            let key = where_.split(": ").next().unwrap_or("").to_string() + p.stage;
            if !panics.iter().any(|(k, _, _)| *k == key) {
                let path = save("panic");
                eprintln!("fuzz: PANIC {where_}\n      input {}", path.display());
                panics.push((key, where_, path));
            }
        }
        for a in out.anomalies {
            let key: String = a.chars().take(60).collect();
            if !anomalies.iter().any(|(k, _, _)| *k == key) && anomalies.len() < 20 {
                let path = save("anomaly");
                eprintln!("fuzz: anomaly {a}\n      input {}", path.display());
                anomalies.push((key, a, path));
            }
        }
    }
    println!(
        "fuzz: {tried} inputs tried in {:.1} s ({accepted} accepted by the reader), {} distinct panics, {} distinct anomalies",
        started.elapsed().as_secs_f64(),
        panics.len(),
        anomalies.len()
    );
    let stages: Vec<String> = exercise::stage_times()
        .iter()
        .map(|(s, t)| format!("{s} {t:.1}"))
        .collect();
    let slow_path = failure_dir().join(format!("slowest-{}", slowest.0));
    std::fs::write(&slow_path, &slowest.2).unwrap();
    println!(
        "fuzz: seconds per stage: {}; slowest input {:.2} s: {}",
        stages.join(", "),
        slowest.1,
        slow_path.display()
    );
    let list: Vec<String> = panics
        .iter()
        .map(|(_, w, p)| format!("{w}\n    input: {}", p.display()))
        .collect();
    assert!(panics.is_empty(), "panics:\n{}", list.join("\n"));
}

/// A JSON document of `program` (its own pieces) with its first NURBS
/// piece replaced by a straight NURBS of `degree` (`degree + 1` points,
/// clamped knots); the piece's index.
fn json_with_nurbs_of_degree(program: &str, degree: usize) -> (String, usize, Program) {
    let p = parse(program.as_bytes()).unwrap();
    let own: Vec<Vec<Piece>> = p.runs().into_iter().map(|r| r.pieces).collect();
    let json = write_json(&p, &own).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    let pieces = doc["pieces"].as_array_mut().unwrap();
    let index = pieces.iter().position(|q| q["type"] == "nurbs").unwrap();
    let q = &mut pieces[index];
    let (a, b) = (
        q["points"][0].clone(),
        q["points"].as_array().unwrap().last().unwrap().clone(),
    );
    let lerp = |k: usize| -> Vec<f64> {
        (0..3)
            .map(|i| {
                let (x, y) = (a[i].as_f64().unwrap(), b[i].as_f64().unwrap());
                x + (y - x) * k as f64 / degree.max(1) as f64
            })
            .collect()
    };
    q["degree"] = serde_json::json!(degree);
    q["points"] = serde_json::json!((0..=degree).map(lerp).collect::<Vec<_>>());
    let mut knots = vec![0.0; degree + 1];
    knots.extend(vec![1.0; degree + 1]);
    q["knots"] = serde_json::json!(knots);
    q["weights"] = serde_json::Value::Null;
    (doc.to_string(), index, p)
}

/// A program with an arc (written to JSON as a rational quadratic NURBS).
const ARC_PROGRAM: &str = "G21 G90\nG0 X0 Y0\nG1 X1 Y0 F600\nG3 X3 Y0 I1 J0\nG1 X4 Y0\nM2\n";

/// The known bug of issue 17: `fairpath check ORIGINAL SMOOTHED.json` with
/// a NURBS piece of degree 9 panicked in `ders_basis` (`assert!(p < 8)`).
/// `read_json` refuses it, naming the piece and the degree; the check's
/// steps on the document do not panic.
#[test]
fn check_of_degree_9_json_nurbs_is_an_error_not_a_panic() {
    let (json, index, program) = json_with_nurbs_of_degree(ARC_PROGRAM, 9);
    match fairpath_gcode::read_json(&json) {
        Err(fairpath_gcode::JsonError::Piece { index: i, message }) => {
            assert_eq!(i, index);
            assert!(message.contains("degree 9"), "{message}");
        }
        other => panic!("expected a piece error, got {other:?}"),
    }
    let out = exercise_json(json.as_bytes(), Some(&program));
    assert!(out.panic.is_none(), "{:?}", out.panic);
}

/// Degrees around the supported range: 0 and above
/// `Nurbs::MAX_DEGREE` are piece errors, 1 to the maximum read and
/// evaluate (through the check's steps) without panicking.
#[test]
fn json_nurbs_degrees_0_to_12_read_or_are_piece_errors() {
    for degree in 0..=12 {
        let (json, index, program) = json_with_nurbs_of_degree(ARC_PROGRAM, degree);
        let r = fairpath_gcode::read_json(&json);
        if (1..=fairpath::geom::Nurbs::MAX_DEGREE).contains(&degree) {
            assert!(r.is_ok(), "degree {degree}: {r:?}");
        } else {
            assert!(
                matches!(&r, Err(fairpath_gcode::JsonError::Piece { index: i, .. }) if *i == index),
                "degree {degree}: {r:?}"
            );
        }
        let out = exercise_json(json.as_bytes(), Some(&program));
        assert!(out.panic.is_none(), "degree {degree}: {:?}", out.panic);
    }
}

/// Fuzz input 5eedf00d-122 (seed 0x5eedf00d): a JSON cubic with weights
/// from 1e-12 to 1e308 read, and the check's arc length ran for hours on
/// its NaN derivatives. 1e308 times a coordinate overflows: it is now a
/// piece error.
#[test]
fn fuzz_json_122_extreme_weights_are_a_piece_error() {
    let (json, index, _) = json_with_nurbs_of_degree(ARC_PROGRAM, 3);
    let mut doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    doc["pieces"][index]["weights"] = serde_json::json!([8.02131094460001, 1e-12, 3.0, 1e308]);
    let r = fairpath_gcode::read_json(&doc.to_string());
    assert!(
        matches!(&r, Err(fairpath_gcode::JsonError::Piece { index: i, message }) if *i == index && message.contains("weighted coordinate")),
        "{r:?}"
    );
}

/// A JSON line whose ends are finite but whose length is not (1e308 to
/// -1e308) is a piece error.
#[test]
fn json_line_from_1e308_to_minus_1e308_is_a_piece_error() {
    let (json, _, _) = json_with_nurbs_of_degree(ARC_PROGRAM, 2);
    let mut doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    let i = doc["pieces"]
        .as_array()
        .unwrap()
        .iter()
        .position(|q| q["type"] == "line")
        .unwrap();
    doc["pieces"][i]["p0"] = serde_json::json!([1e308, 0.0, 0.0]);
    doc["pieces"][i]["p1"] = serde_json::json!([-1e308, 0.0, 0.0]);
    let r = fairpath_gcode::read_json(&doc.to_string());
    assert!(
        matches!(&r, Err(fairpath_gcode::JsonError::Piece { index, .. }) if *index == i),
        "{r:?}"
    );
}

/// Fuzz input 5eedf00d-85 (seed 0x5eedf00d, from a shared program with a
/// very long digit string inserted): a G1 to X2.9e297 parses, and smoothing
/// its run then runs for hours: the verifier's `Refine::refine`
/// (`fairpath/src/smooth/verify.rs`, outside this branch) bisects a curve
/// that long to depth 48 (2^48 spans) because its bound never falls below
/// the accuracy. Not a panic. The reader now refuses such values
/// (`lexer::MAX_WORD_MAGNITUDE`); the fuzzer still skips smoothing
/// programs beyond `exercise::MAX_SMOOTHED_EXTENT_MM`.
#[test]
fn fuzz_85_g1_to_x2_9e297_is_refused_at_its_column() {
    let program = "G21 G90 G64 G40 G17\nG0 Z3.0\nM3 S10000\nG0 X1.75781 Y0.5\n\
        G1 F100.0 Z-2.0\nG1 F1200.0 X5.95508 Y20.54297\nG1 X10.07031\n\
        G1 X6.58398 Y3.84961\nG1 X16.7832\nG1 X30\nX2.9e297\nM2\n";
    // The exponent form is how the digits read; the fuzz input had all 298.
    let program = program.replace("2.9e297", &format!("29{}", "0".repeat(296)));
    // The reader refuses values beyond MAX_WORD_MAGNITUDE where they are
    // written, before any smoothing (which spent hours refining a curve
    // 1e297 mm long against a 0.045 mm tolerance).
    let e = parse(program.as_bytes()).unwrap_err();
    assert_eq!((e.line, e.column), (11, 1), "{e}");
    assert_eq!(e.kind, fairpath_gcode::ErrorKind::NumberOutOfRange('X'));
}
