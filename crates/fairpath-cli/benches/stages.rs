//! The `smooth` job stage by stage (issue 19, item 6): read, smooth (per
//! method), verify the curves, plan the input and the curves, render and
//! write (with the writer's own read-back check), plan the written text,
//! and read back + check the written text on its own. On
//! `../shared/paths/synthetic/surface-raster.ngc` when present (read in
//! place, never copied), else on a raster generated here with the same
//! shape: one long run of short 3D moves between rapids. Run with
//! `cargo bench -p fairpath-cli --bench stages`; `scripts/scale.sh` times
//! whole jobs on the large programs.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use fairpath::path::Piece;
use fairpath::pipeline::verify_runs;
use fairpath::verify::VerifyOptions;
use fairpath_gcode::emit::emit;
use fairpath_gcode::pipeline::{
    compare_runs, plan_curves, plan_input, plan_text, smooth_curves, Phases, SmoothOptions,
};
use fairpath_gcode::{Controller, Program};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Methods benchmarked per stage: the baseline and the ones
/// `scripts/scale.sh` times.
fn parse_program(bytes: &[u8]) -> Result<Program, fairpath_gcode::GcodeError> {
    fairpath_gcode::parse(bytes)
}

const METHODS: &[&str] = &["none", "bspline-corner", "auto", "arc-fit"];

const TOLERANCE: f64 = 0.05;

/// A 3D raster of `rows` passes of `per_row` short moves over a smooth
/// surface, with a rapid between passes: the shape of the CAM finishing
/// programs the large-program targets are about.
fn raster(rows: usize, per_row: usize) -> String {
    let mut s = String::from("(generated raster)\nG21 G90 G17\nG0 Z10\n");
    for r in 0..rows {
        let y = r as f64 * 0.5;
        let _ = writeln!(s, "G0 X0 Y{y:.3}\nG1 Z0 F4000");
        for i in 1..=per_row {
            let x = i as f64 * 0.37;
            let z = 2.0 * (x * 0.05).sin() * (y * 0.1).cos();
            let _ = writeln!(s, "G1 X{x:.4} Y{y:.3} Z{z:.4}");
        }
        let _ = writeln!(s, "G0 Z10");
    }
    s.push_str("M30\n");
    s
}

/// The program benchmarked: its name, path (for messages) and bytes.
fn program() -> (String, PathBuf, Vec<u8>) {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/paths/synthetic/surface-raster.ngc");
    match std::fs::read(&shared) {
        Ok(bytes) => ("surface-raster".into(), shared, bytes),
        Err(_) => {
            eprintln!(
                "{} not found: benchmarking a generated raster",
                shared.display()
            );
            let text = raster(20, 1000);
            (
                "generated-raster".into(),
                PathBuf::from("raster.ngc"),
                text.into_bytes(),
            )
        }
    }
}

fn options(method: &str) -> SmoothOptions {
    SmoothOptions::new(TOLERANCE, None, method, None, Controller::Generic).unwrap()
}

fn bench(c: &mut Criterion) {
    let (name, _path, bytes) = program();
    let program = parse_program(&bytes).unwrap();
    let moves = program.moves().len() as u64;
    let mut g = c.benchmark_group(format!("stages/{name}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(moves));
    g.bench_function("read", |b| {
        b.iter(|| parse_program(&bytes).unwrap().moves().len())
    });
    let base = options("none");
    g.bench_function("plan input", |b| {
        b.iter(|| plan_input(&program, &base).unwrap().total)
    });
    for &method in METHODS {
        let opts = options(method);
        let runs = program.runs();
        // `auto` as `smooth` builds it for this program (ranking by what
        // is written); the others as named.
        let for_program = opts.method_for(&program);
        let smoother = for_program.as_deref().unwrap_or(opts.method());
        g.bench_function(format!("smooth {method}"), |b| {
            b.iter(|| {
                runs.iter()
                    .map(|r| {
                        smoother
                            .smooth_within(r, &opts.budget())
                            .unwrap()
                            .pieces
                            .len()
                    })
                    .sum::<usize>()
            })
        });
        let result = smooth_curves(&program, &opts, &mut Phases::new()).unwrap();
        let pairs: Vec<(&[Piece], &[Piece])> = result
            .runs
            .iter()
            .map(|r| (r.original.pieces.as_slice(), r.smoothed.pieces.as_slice()))
            .collect();
        g.bench_function(format!("verify curves {method}"), |b| {
            b.iter(|| verify_runs(&pairs, &VerifyOptions::new(opts.budget().smoothing())).len())
        });
        g.bench_function(format!("plan curves {method}"), |b| {
            b.iter(|| plan_curves(&program, &result, &opts).unwrap().0.total)
        });
        let (_, plans) = plan_curves(&program, &result, &opts).unwrap();
        let smoothed: Vec<Vec<Piece>> = result
            .runs
            .iter()
            .map(|r| r.smoothed.pieces.clone())
            .collect();
        let original = program.runs();
        let eo = opts.emit_options();
        g.bench_function(format!("render, write, check {method}"), |b| {
            b.iter(|| {
                emit(&program, &original, &smoothed, &plans, &eo)
                    .unwrap()
                    .1
                    .len()
            })
        });
        let text = emit(&program, &original, &smoothed, &plans, &eo).unwrap().1;
        g.bench_function(format!("re-read and check {method}"), |b| {
            b.iter_batched(
                || text.clone(),
                |text| {
                    let reread = parse_program(text.as_bytes()).unwrap().runs();
                    let original: Vec<_> = result.runs.iter().map(|r| r.original.clone()).collect();
                    compare_runs(&original, &reread, TOLERANCE).unwrap().within
                },
                BatchSize::LargeInput,
            )
        });
        g.bench_function(format!("plan written {method}"), |b| {
            b.iter(|| plan_text(&text, &opts).unwrap().total)
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
