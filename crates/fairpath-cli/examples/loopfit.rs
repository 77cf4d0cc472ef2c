// scratch
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::geom::{Curve, Line};
use fairpath::smooth::{by_name, BsplineFit, BsplineFitOptions, SectionOptions, Smoother};
use fairpath::{Piece, Run, Vec3};
fn main() {
    let p = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
    let pts = vec![
        p(170.73483, 19.86847, 0.49686),
        p(186.0, 19.86847, 0.49686),
        p(193.40333, 19.86847, 0.49686),
        p(194.30136, 19.86847, 0.86884),
        p(194.67333, 19.86847, 1.76686),
        p(195.13791, 20.4863, 2.88769),
        p(195.18549, 22.04913, 3.00167),
        p(194.67401, 22.86847, 1.76686),
        p(194.3018, 22.86847, 0.86859),
        p(193.40333, 22.86847, 0.49686),
        p(186.7, 22.86847, 0.50403),
        p(170.04786, 22.86847, 0.50403),
    ];
    let run = Run::new(
        pts.windows(2)
            .map(|w| Piece {
                curve: Curve::Line(Line::new(w[0], w[1])),
                rapid: false,
                source_lines: (1, 1),
                feed: None,
            })
            .collect(),
    );
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: true,
        window: None,
    };
    let through = BsplineFitOptions {
        sections: SectionOptions {
            max_segment: 1e6,
            max_turn: 2.5,
            chord_error_per_tol: 1e6,
            ..SectionOptions::default()
        },
        ..BsplineFitOptions::default()
    };
    let jt = BsplineFitOptions {
        jerk_fairness: 3e4,
        ..through
    };
    for (name, r) in [
        (
            "through",
            BsplineFit { options: through }.smooth_run(&run, 0.045),
        ),
        (
            "through-jerk",
            BsplineFit { options: jt }.smooth_run(&run, 0.045),
        ),
        ("fit", BsplineFit::default().smooth_run(&run, 0.045)),
        (
            "corner",
            by_name("bspline-corner").unwrap().smooth_run(&run, 0.045),
        ),
        ("lotm", by_name("lotm").unwrap().smooth_run(&run, 0.045)),
    ] {
        let r = r.unwrap();
        let plan = plan_run(&r.pieces, &opts).unwrap();
        let t = plan.time;
        let it = fairpath::feed::interpolate::interpolate(&r.pieces, &plan, 0.001, 0.0);
        let inloop: Vec<_> = it.samples.iter().filter(|s| s.p.x > 193.0).collect();
        let lt = inloop.len() as f64 * 0.001;
        let vmin = inloop.iter().map(|s| s.v).fold(f64::INFINITY, f64::min);
        let vmax = inloop.iter().map(|s| s.v).fold(0.0, f64::max);
        if name == "through" || name == "corner" {
            use fairpath::ParamCurve;
            let mut line = String::new();
            for pc in &r.pieces {
                let (a, b) = pc.curve.domain();
                for k in 0..=400 {
                    let t = a + (b - a) * k as f64 / 400.0;
                    let q = pc.curve.eval(t);
                    if q.x > 193.3 && k % 4 == 0 {
                        line += &format!("{:.2} ", pc.curve.curvature(t));
                    }
                }
            }
            println!("{name} kappa: {line}");
        }
        println!(
            "{name}: {} pieces, time {t:.4}; x>193: {lt:.3}s v {vmin:.1}..{vmax:.1}",
            r.pieces.len()
        );
    }
}
