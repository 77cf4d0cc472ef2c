//! Fitting speed of `bspline-fit` in points per second: one dense section
//! (a 3D curve like a finishing-raster row, points 0.9 mm apart in x,
//! rounded to 1 um) of 1,000 to 100,000 points fitted within 0.05 mm, by
//! the search alone (`fit_polyline`) and by the whole method
//! (`BsplineFit::smooth_run`: detection, fit, piece output). Time should
//! grow about linearly with the size. Run with
//! `cargo bench -p fairpath --bench fit`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fairpath::geom::fit::EndCondition;
use fairpath::geom::Vec3;
use fairpath::path::Run;
use fairpath::smooth::{fit_polyline, BsplineFit, Smoother, BAND_USE};

/// `n` points of a wavy 3D curve, 0.9 mm apart in x, rounded to 1 um.
fn wavy(n: usize) -> Vec<Vec3> {
    let r = |x: f64| (x * 1000.0).round() / 1000.0;
    (0..n)
        .map(|i| {
            let x = i as f64 * 0.9;
            let y = 3.0 * (x / 40.0).sin();
            let z = 5.0 * (x / 12.0).sin() + 1.5 * (x / 5.0 + 0.3).cos();
            Vec3::new(r(x), r(y), r(z))
        })
        .collect()
}

fn run_of(pts: &[Vec3]) -> Run {
    Run::polyline(pts, Some(4000.0))
}

fn bench(c: &mut Criterion) {
    let tol = 0.05;
    let mut g = c.benchmark_group("bspline-fit");
    g.sample_size(10);
    for n in [1_000, 10_000, 100_000] {
        let pts = wavy(n);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("fit_polyline", n), &pts, |b, pts| {
            b.iter(|| {
                let f = fit_polyline(
                    pts,
                    EndCondition::Free,
                    EndCondition::Free,
                    tol * BAND_USE,
                    1.0,
                )
                .unwrap();
                f.curve.points.len()
            })
        });
        let run = run_of(&pts);
        g.bench_with_input(BenchmarkId::new("smooth_run", n), &run, |b, run| {
            b.iter(|| {
                BsplineFit::default()
                    .smooth_run(run, tol)
                    .unwrap()
                    .pieces
                    .len()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
