//! The fit's kernels made faster give the bits they gave before: the
//! normal equations built from a data part shared between weights
//! (`FitData`) and summed with the four-free-points shortcut, and the span
//! bounds with each point's segment distances computed once. The
//! references below are the earlier implementations, kept here verbatim
//! in their arithmetic.

use fairpath::geom::fit::{
    averaged_knots, chord_params, cubic_basis_d2_at_ends, cubic_basis_values, eval_in_span,
    fit_cubic_weighted, span_errors, span_errors_within, EndCondition, FitData, FitSystem,
    FIT_DEGREE,
};
use fairpath::geom::least_squares::BandedSpd;
use fairpath::geom::{point_segment_distance, Nurbs, Vec3};
use proptest::prelude::*;

/// The pivot share of `geom::fit`.
const PIVOT_REL: f64 = 1e-12;

/// The fit as `FitSystem::new` and `solve` built it before `FitData`, the
/// data and the fixed control points taken relative to the start point (as
/// `FitData` solves them).
fn reference_fit(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    (start, end): (EndCondition, EndCondition),
    (lambda, mu): (f64, f64),
) -> Option<Nurbs> {
    let n = params.len();
    let h = knots.len() - FIT_DEGREE - 1;
    let (ua, ub) = (knots[FIT_DEGREE], knots[h]);
    let extra = |e: EndCondition| match e {
        EndCondition::Free => 0,
        EndCondition::Tangent(_) => 2,
    };
    let lo = 1 + extra(start);
    let hi = h - 1 - extra(end);
    if lo >= hi {
        return None;
    }
    let ends = (pts[0], pts[n - 1]);
    let mut ctrl = vec![Vec3::ZERO; h];
    ctrl[0] = ends.0;
    ctrl[h - 1] = ends.1;
    let greville = |i: usize| (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0;
    if let EndCondition::Tangent(d) = start {
        for (i, c) in ctrl.iter_mut().enumerate().take(3).skip(1) {
            *c = ends.0 + d * (greville(i) - ua);
        }
    }
    if let EndCondition::Tangent(d) = end {
        for (i, c) in ctrl.iter_mut().enumerate().skip(h - 3).take(2) {
            *c = ends.1 - d * (ub - greville(i));
        }
    }
    let origin = ends.0;
    let rel: Vec<Vec3> = ctrl.iter().map(|&c| c - origin).collect();
    let free = |i: usize| i >= lo && i < hi;
    let mut a = BandedSpd::zeros(hi - lo);
    let mut fixed_rhs = vec![Vec3::ZERO; hi - lo];
    let mut add_term = |s: usize, b: &[f64; 4], w: f64| {
        for j in 0..4 {
            let gj = s - 3 + j;
            if !free(gj) || b[j] == 0.0 {
                continue;
            }
            for k in 0..4 {
                let gk = s - 3 + k;
                let v = w * b[j] * b[k];
                if free(gk) {
                    if gk <= gj {
                        a.add(gj - lo, gk - lo, v);
                    }
                } else {
                    fixed_rhs[gj - lo] -= rel[gk] * v;
                }
            }
        }
    };
    let mut basis = Vec::with_capacity(n);
    let mut s = FIT_DEGREE;
    for &t in params {
        while s + 1 < h && knots[s + 1] <= t {
            s += 1;
        }
        let b = cubic_basis_values(knots, s, t);
        add_term(s, &b, 1.0);
        basis.push((s, b));
    }
    let spans = || {
        (FIT_DEGREE..h).filter_map(|s| {
            let len = knots[s + 1] - knots[s];
            (len > 0.0).then(|| (s, len, cubic_basis_d2_at_ends(knots, s)))
        })
    };
    if lambda > 0.0 {
        let g = 0.5 / 3f64.sqrt();
        for (s, len, (e0, e1)) in spans() {
            for x in [0.5 - g, 0.5 + g] {
                let b: [f64; 4] = core::array::from_fn(|k| e0[k] * (1.0 - x) + e1[k] * x);
                add_term(s, &b, lambda * 0.5 * len);
            }
        }
    }
    if mu > 0.0 {
        for (s, len, (e0, e1)) in spans() {
            let d3: [f64; 4] = core::array::from_fn(|k| (e1[k] - e0[k]) / len);
            add_term(s, &d3, mu * len);
        }
    }
    let chol = a.cholesky(PIVOT_REL).ok()?;
    let mut rhs = fixed_rhs;
    for (q, (s, b)) in pts.iter().zip(&basis) {
        for (j, &bj) in b.iter().enumerate() {
            let gj = s - 3 + j;
            if gj >= lo && gj < hi && bj != 0.0 {
                rhs[gj - lo] += (*q - origin) * bj;
            }
        }
    }
    chol.solve(&mut rhs);
    for (c, r) in ctrl[lo..hi].iter_mut().zip(&rhs) {
        *c = *r + origin;
    }
    if ctrl.iter().any(|p| !p.is_finite()) {
        return None;
    }
    Some(Nurbs {
        degree: FIT_DEGREE,
        knots: knots.to_vec(),
        points: ctrl,
        weights: None,
    })
}

/// `span_errors` as it was: every piece's end distances computed afresh.
fn reference_span_errors(c: &Nurbs, pts: &[Vec3], params: &[f64]) -> Vec<f64> {
    let h = c.points.len();
    let knots = &c.knots;
    let mut err = vec![0.0f64; h - FIT_DEGREE];
    let n = pts.len();
    let seg_dist = |g: usize, p: Vec3| point_segment_distance(p, pts[g], pts[g + 1]);
    let mut s = FIT_DEGREE;
    let mut at_a = eval_in_span(knots, &c.points, s, params[0]);
    let multiple = |s: usize| knots[s] == knots[s - 1];
    for i in 0..n - 1 {
        let (t0, t1) = (params[i], params[i + 1]);
        while s + 1 < h && knots[s + 1] <= t0 {
            s += 1;
            if multiple(s) {
                at_a = eval_in_span(knots, &c.points, s, t0);
            }
        }
        err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[i]));
        let mut a = t0;
        loop {
            let b = if s + 1 < h { knots[s + 1].min(t1) } else { t1 };
            let (ca, c2a) = at_a;
            let (cb, c2b) = eval_in_span(knots, &c.points, s, b);
            let sag = c2a.norm().max(c2b.norm()) * (b - a) * (b - a) / 8.0;
            let lo_g = i.saturating_sub(1);
            let hi_g = (i + 1).min(n - 2);
            let mut best = f64::INFINITY;
            for g in lo_g..=hi_g {
                best = best.min(seg_dist(g, ca).max(seg_dist(g, cb)));
            }
            let e = &mut err[s - FIT_DEGREE];
            *e = e.max(best + sag);
            at_a = (cb, c2b);
            if b >= t1 || s + 1 >= h {
                break;
            }
            a = b;
            s += 1;
            if multiple(s) {
                at_a = eval_in_span(knots, &c.points, s, a);
            }
        }
        if i == n - 2 {
            err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[n - 1]));
        }
    }
    err
}

fn bits(c: &Nurbs) -> Vec<u64> {
    c.knots
        .iter()
        .map(|k| k.to_bits())
        .chain(
            c.points
                .iter()
                .flat_map(|p| [p.x, p.y, p.z].map(f64::to_bits)),
        )
        .collect()
}

/// A wavy polyline of `n` points with noise, some steps repeated in
/// length (equal chords give equal knots).
fn polyline() -> impl Strategy<Value = Vec<Vec3>> {
    (5usize..60, 0.05f64..3.0, 0.0f64..0.5, any::<u64>()).prop_map(|(n, step, amp, seed)| {
        let mut r = seed | 1;
        let mut rnd = move || {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            (r >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        (0..n)
            .map(|i| {
                let x = i as f64 * step;
                Vec3::new(x, amp * (x * 0.7).sin() + 0.01 * rnd(), 0.02 * rnd())
            })
            .collect()
    })
}

fn end_condition() -> impl Strategy<Value = Option<()>> {
    prop_oneof![Just(None), Just(Some(()))]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Fits and their span bounds, at several weights on one data part,
    /// are the earlier implementation's to the bit.
    #[test]
    fn fits_and_bounds_keep_their_bits(
        pts in polyline(),
        extra in 0usize..40,
        (tan_start, tan_end) in (end_condition(), end_condition()),
        lambda in prop_oneof![Just(0.0), 1e-6f64..10.0],
        mu in prop_oneof![Just(0.0), 1e-6f64..10.0],
    ) {
        let n = pts.len();
        let params = chord_params(&pts);
        let h = (4 + extra).min(2 * n + 8).max(8);
        let knots = averaged_knots(&params, h);
        let dir = |a: Vec3, b: Vec3| (b - a).normalized(0.0).unwrap();
        let start = tan_start.map_or(EndCondition::Free, |_| EndCondition::Tangent(dir(pts[0], pts[1])));
        let end = tan_end.map_or(EndCondition::Free, |_| EndCondition::Tangent(dir(pts[n - 2], pts[n - 1])));
        let ends = (start, end);
        let data = FitData::new(&params, &knots, ends, (pts[0], pts[n - 1]));
        for w in [(lambda, mu), (lambda * 4.0, mu * 4.0), (lambda / 16.0, mu / 16.0), (0.0, 0.0)] {
            let want = reference_fit(&pts, &params, &knots, ends, w);
            let got = fit_cubic_weighted(&pts, &params, &knots, start, end, w.0, w.1).ok();
            let shared = data.as_ref().ok().and_then(|d| d.system(w).ok()).and_then(|s| s.solve(&pts).ok());
            let fresh = FitSystem::new(&params, &knots, ends, (pts[0], pts[n - 1]), w)
                .ok()
                .and_then(|s| s.solve(&pts).ok());
            prop_assert_eq!(want.as_ref().map(bits), got.as_ref().map(bits));
            prop_assert_eq!(want.as_ref().map(bits), shared.as_ref().map(bits));
            prop_assert_eq!(want.as_ref().map(bits), fresh.as_ref().map(bits));
            if let Some(c) = &want {
                let a: Vec<u64> = span_errors(c, &pts, &params).iter().map(|e| e.to_bits()).collect();
                let b: Vec<u64> = reference_span_errors(c, &pts, &params).iter().map(|e| e.to_bits()).collect();
                prop_assert_eq!(a, b);
            }
        }
    }

    /// The span bounds judged against a limit: every bound, to the bit,
    /// where none exceeds it; else a bound above the limit and at most the
    /// largest (the same verdict as the largest bound's).
    #[test]
    fn span_bounds_judged_against_a_limit_give_the_same_verdict(
        pts in polyline(),
        extra in 0usize..40,
        share in 0.0f64..1.2,
    ) {
        let n = pts.len();
        let params = chord_params(&pts);
        let h = (4 + extra).min(n + 1).max(4);
        let knots = averaged_knots(&params, h);
        let free = (EndCondition::Free, EndCondition::Free);
        let Some(c) = reference_fit(&pts, &params, &knots, free, (0.0, 0.0)) else {
            return Ok(());
        };
        let all = span_errors(&c, &pts, &params);
        let max = all.iter().copied().fold(0.0, f64::max);
        let limit = share * max;
        match span_errors_within(&c, &pts, &params, limit) {
            Ok(errs) => {
                prop_assert!(max <= limit);
                let a: Vec<u64> = errs.iter().map(|e| e.to_bits()).collect();
                let b: Vec<u64> = all.iter().map(|e| e.to_bits()).collect();
                prop_assert_eq!(a, b);
            }
            Err(e) => {
                prop_assert!(max > limit);
                prop_assert!(e > limit && e <= max, "{} not in ({}, {}]", e, limit, max);
            }
        }
    }
}
