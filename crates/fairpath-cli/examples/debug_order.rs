// TEMPORARY debugging aid (not committed).
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::lower_bound::{in_order_gates_of, piece_speed, BandPaths, BoundOptions};
use fairpath::geom::{flatten_params, ParamCurve};
use fairpath::verify::{follows_in_order, follows_in_order_within};
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let orig = std::fs::read(&a[1]).unwrap();
    let written = std::fs::read(&a[2]).unwrap();
    let (_, ro) = fairpath_gcode::read_motion(&orig).unwrap();
    let (_, rw) = fairpath_gcode::read_motion(&written).unwrap();
    let pairs = fairpath_gcode::pipeline::pair_runs(&ro, &rw).unwrap();
    let o = BoundOptions {
        paths: BandPaths::InOrder,
        ..BoundOptions::new(0.05)
    };
    let m = MachineLimits::thesis();
    for &(i, j) in &pairs {
        let g = in_order_gates_of(&ro[i].pieces, &o, &m, false);
        let acc = 0.05 * 1e-3;
        let plain = follows_in_order(&rw[j].pieces, &g.gates, acc);
        let within = follows_in_order_within(
            &rw[j].pieces,
            &g.gates,
            &g.caps,
            |p| piece_speed(p, &m, false),
            acc,
        );
        if plain && within {
            continue;
        }
        println!(
            "run {i}/{j}: plain {plain} within {within}, {} gates",
            g.gates.len()
        );
        // points of the written run
        let mut pts = Vec::new();
        for p in &rw[j].pieces {
            for t in flatten_params(&p.curve, 1e-4) {
                pts.push(p.curve.eval(t));
            }
        }
        let seg_d = |a: fairpath::geom::Vec3, b: fairpath::geom::Vec3, q: fairpath::geom::Vec3| {
            let ab = b - a;
            let l = ab.norm_sq();
            let t = if l > 0.0 {
                ((q - a).dot(ab) / l).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + ab * t).dist(q)
        };
        let mut k = 0usize;
        for (n, &(q, r)) in g.gates.iter().enumerate() {
            let start = k;
            while k + 1 < pts.len() && seg_d(pts[k], pts[k + 1], q) > r {
                k += 1;
            }
            if k + 1 >= pts.len() {
                let best = (start..pts.len() - 1)
                    .map(|i| seg_d(pts[i], pts[i + 1], q))
                    .fold(f64::INFINITY, f64::min);
                let best_all = (0..pts.len() - 1)
                    .map(|i| seg_d(pts[i], pts[i + 1], q))
                    .fold(f64::INFINITY, f64::min);
                println!("  gate {n} at {q:?} r {r}: not passed after segment {start} at {:?}; nearest after {best}, anywhere {best_all}", pts[start]);
                for w in n.saturating_sub(3)..(n + 3).min(g.gates.len()) {
                    println!(
                        "    gate {w}: {:?} r {} cap {}",
                        g.gates[w].0, g.gates[w].1, g.caps[w]
                    );
                }
                break;
            }
        }
        if plain {
            for (n, c) in g.caps.iter().enumerate() {
                if *c < 1e9 {
                    let _ = n;
                }
            }
            println!("  caps: {:?}", &g.caps[..g.caps.len().min(8)]);
            let speeds: Vec<f64> = rw[j]
                .pieces
                .iter()
                .map(|p| piece_speed(p, &m, false))
                .collect();
            println!("  written piece speeds (distinct): {:?}", {
                let mut s = speeds.clone();
                s.sort_by(f64::total_cmp);
                s.dedup();
                s
            });
            let mut cs = g.caps.clone();
            cs.sort_by(f64::total_cmp);
            cs.dedup();
            println!("  cap values: {cs:?}");
        }
    }
}
