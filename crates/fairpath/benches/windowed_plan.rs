//! What planning a long run's time window by window
//! (`fairpath::feed::windowed`) costs against planning it whole: the same
//! time to the bit where the windows are the whole plan (not always:
//! the module docs), in a window's memory, for the overlap planned twice
//! (twice the pieces planned with the default windows) and the segments
//! each window keeps. A zigzag raster of 0.5 mm moves over a bumpy
//! surface, smoothed by `bspline-corner`, of about 40,000 to 400,000
//! pieces. Run with `cargo bench -p fairpath --bench windowed_plan`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_time_shaped, Corners, PlanOptions, RunEnds};
use fairpath::feed::shaping::Shaping;
use fairpath::feed::windowed::{plan_time_windowed, PlanWindows};
use fairpath::geom::Vec3;
use fairpath::path::{Piece, Run};
use fairpath::smooth::{BsplineCorner, Smoother};

/// A raster of `rows` passes of 100 mm, 0.5 mm moves, rounded to 1 um.
fn raster(rows: usize) -> Vec<Vec3> {
    let r = |x: f64| (x * 1000.0).round() / 1000.0;
    let mut pts = Vec::new();
    for row in 0..rows {
        let y = row as f64 * 1.5;
        for k in 0..=200 {
            let s = k as f64 * 0.5;
            let x = if row % 2 == 0 { s } else { 100.0 - s };
            let z = 2.0 * (x * 0.3).sin() + (y * 0.2).cos();
            pts.push(Vec3::new(r(x), r(y), r(z)));
        }
    }
    pts
}

fn pieces(rows: usize) -> Vec<Piece> {
    let run = Run::polyline(&raster(rows), Some(4000.0));
    BsplineCorner::default()
        .smooth_run(&run, 0.05)
        .unwrap()
        .pieces
}

fn bench(c: &mut Criterion) {
    let po = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: false,
        window: None,
        ends: RunEnds::AtRest,
    };
    let mut g = c.benchmark_group("windowed plan");
    g.sample_size(10);
    for rows in [100, 1000] {
        let pieces = pieces(rows);
        let n = pieces.len();
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("whole", n), &pieces, |b, p| {
            b.iter(|| plan_time_shaped(p, &po, &Shaping::none(), Corners::Blended).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("windowed", n), &pieces, |b, p| {
            b.iter(|| plan_time_windowed(p, &po, Corners::Blended, PlanWindows::DEFAULT).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
