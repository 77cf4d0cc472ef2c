//! End-to-end smoothing throughput: read, smooth (`auto`, the default),
//! verify the curves, write G-code, read it back and verify it, on
//! `../shared/paths/synthetic/surface-raster-large.ngc` (138,803 segments)
//! at 0.05 mm; and feed planning speed on the smoothed path. Run with
//! `cargo bench -p fairpath-cli`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use fairpath_cli::smooth;
use fairpath_cli::{Controller, Format};
use fairpath_gcode::SmoothOptions;
use std::path::Path;

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/paths/synthetic/surface-raster-large.ngc");
    let Ok(bytes) = std::fs::read(&path) else {
        eprintln!("{} not found: benchmark skipped", path.display());
        return;
    };
    let program = fairpath_gcode::parse(&bytes).unwrap();
    let segments: usize = program.runs().iter().map(|r| r.pieces.len()).sum();
    let mut g = c.benchmark_group("surface-raster-large");
    g.sample_size(10);
    g.throughput(Throughput::Elements(segments as u64));
    let dir = tempfile::tempdir().unwrap();
    for format in [Format::Arcs, Format::G1] {
        g.bench_function(
            format!("end-to-end smooth 0.05 mm ({})", format.name()),
            |b| {
                b.iter(|| {
                    let opts =
                        SmoothOptions::new(0.05, None, "auto", Some(format), Controller::Generic)
                            .unwrap();
                    let out = dir.path().join("out.ngc");
                    let summary = smooth::smooth_file(&path, &out, &opts).unwrap();
                    summary.e.lines_out
                })
            },
        );
    }
    for method in ["bspline-corner", "bspline-fit", "auto"] {
        g.bench_function(
            format!("smooth only, {method} (no verification, no output)"),
            |b| {
                let runs = program.runs();
                let m = fairpath::choose::by_name(method).unwrap();
                b.iter(|| {
                    runs.iter()
                        .map(|r| m.smooth_run(r, 0.045).unwrap().pieces.len())
                        .sum::<usize>()
                })
            },
        );
    }
    g.finish();

    // Feed planning speed, in pieces per second: the smoothed raster
    // (lines and corner transitions) on the thesis machine.
    let m = fairpath::choose::by_name("bspline-corner").unwrap();
    let smoothed: Vec<_> = program
        .runs()
        .iter()
        .map(|r| m.smooth_run(r, 0.045).unwrap().pieces)
        .collect();
    let pieces: usize = smoothed.iter().map(|p| p.len()).sum();
    let mut g = c.benchmark_group("feed planning");
    g.sample_size(10);
    g.throughput(Throughput::Elements(pieces as u64));
    let opts = fairpath::feed::plan::PlanOptions {
        limits: fairpath::feed::limits::MachineLimits::thesis(),
        override_feed: true,
        window: None,
        ends: Default::default(),
    };
    g.bench_function("plan smoothed surface-raster-large (pieces)", |b| {
        b.iter(|| {
            smoothed
                .iter()
                .map(|p| fairpath::feed::plan::plan_run(p, &opts).unwrap().time)
                .sum::<f64>()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
