//! Knot insertion and the decomposition of a B-spline or NURBS into its
//! (rational) Bezier spans (Piegl and Tiller, The NURBS Book, 2nd ed.:
//! A5.1 CurveKnotIns, Boehm's algorithm, applied to the homogeneous control
//! points; section 5.3 for the decomposition).
//!
//! A writer needs this when a controller fixes the knot vector itself
//! (LinuxCNC's G5.2 builds a uniform one from the number of points): each
//! span, written on its own, is the same curve whatever knots it gets.

use super::{Nurbs, Vec3};
use alloc::vec;
use alloc::vec::Vec;

/// Homogeneous control point `(w x, w y, w z, w)`.
type Hom = [f64; 4];

fn to_hom(n: &Nurbs) -> Vec<Hom> {
    n.points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let w = n.weights.as_ref().map_or(1.0, |w| w[i]);
            [p.x * w, p.y * w, p.z * w, w]
        })
        .collect()
}

fn blend(a: Hom, b: Hom, alpha: f64) -> Hom {
    // alpha a + (1 - alpha) b
    let mut o = [0.0; 4];
    for k in 0..4 {
        o[k] = alpha * a[k] + (1.0 - alpha) * b[k];
    }
    o
}

/// Inserts `u` once into `knots`/`pw` (degree `p`); `u` must lie in
/// `[knots[p], knots[n+1]]`.
fn insert_once(p: usize, knots: &mut Vec<f64>, pw: &mut Vec<Hom>, u: f64) {
    let n = pw.len() - 1;
    // Span k: the last knot at or before u (knots[k] <= u < knots[k+1]
    // whenever u is below the last knot, which insertion never reaches:
    // there the multiplicity already exceeds the degree).
    let k = knots
        .iter()
        .rposition(|&t| t <= u)
        .unwrap_or(0)
        .clamp(p, knots.len() - 2);
    let s = knots.iter().filter(|&&t| t == u).count();
    let mut q: Vec<Hom> = Vec::with_capacity(n + 2);
    for i in 0..=n + 1 {
        let v = if i + p <= k {
            pw[i]
        } else if i + s > k {
            pw[i - 1]
        } else {
            let alpha = (u - knots[i]) / (knots[i + p] - knots[i]);
            blend(pw[i], pw[i - 1], alpha)
        };
        q.push(v);
    }
    knots.insert(k + 1, u);
    *pw = q;
}

impl Nurbs {
    /// The same curve with `u` inserted `times` more times into the knot
    /// vector (multiplicity capped at the degree; `u` outside the domain
    /// is ignored). Evaluates identically up to rounding.
    pub fn insert_knot(&self, u: f64, times: usize) -> Nurbs {
        if self.validate().is_err() {
            // A struct literal that breaks the invariants: nothing sound to
            // insert into.
            return self.clone();
        }
        let (a, b) = super::ParamCurve::domain(self);
        let p = self.degree;
        let mut knots = self.knots.clone();
        let mut pw = to_hom(self);
        if (a..=b).contains(&u) {
            for _ in 0..times {
                if knots.iter().filter(|&&t| t == u).count() >= p {
                    break;
                }
                insert_once(p, &mut knots, &mut pw, u);
            }
        }
        from_hom(p, knots, &pw, self.weights.is_some())
    }

    /// The curve as one (rational) Bezier curve per non-empty knot span, in
    /// order: span `[t0, t1]` becomes a curve of the same degree with knots
    /// `t0` and `t1` each repeated `degree + 1` times, equal to this curve
    /// on `[t0, t1]` at the same parameters (up to rounding). Built by
    /// raising every breakpoint, the domain ends included, to multiplicity
    /// `degree` by knot insertion; clamped or not.
    /// Empty for a curve that fails [`Nurbs::validate`].
    pub fn bezier_spans(&self) -> Vec<Nurbs> {
        if self.validate().is_err() {
            return Vec::new();
        }
        let p = self.degree;
        let breaks = self.breakpoints();
        let mut knots = self.knots.clone();
        let mut pw = to_hom(self);
        for &t in &breaks {
            while knots.iter().filter(|&&k| k == t).count() < p {
                insert_once(p, &mut knots, &mut pw, t);
            }
        }
        let rational = self.weights.is_some();
        let mut out = Vec::with_capacity(breaks.len().saturating_sub(1));
        for w in breaks.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            // The last knot equal to t0: the span starts there.
            let j = match knots.iter().rposition(|&k| k == t0) {
                Some(j) if j >= p => j,
                _ => continue,
            };
            let mut kv = vec![t0; p + 1];
            kv.extend(core::iter::repeat_n(t1, p + 1));
            out.push(from_hom(p, kv, &pw[j - p..=j], rational));
        }
        out
    }
}

fn from_hom(p: usize, knots: Vec<f64>, pw: &[Hom], rational: bool) -> Nurbs {
    let points = pw
        .iter()
        .map(|h| {
            if rational {
                Vec3::new(h[0] / h[3], h[1] / h[3], h[2] / h[3])
            } else {
                Vec3::new(h[0], h[1], h[2])
            }
        })
        .collect();
    let weights = rational.then(|| pw.iter().map(|h| h[3]).collect());
    Nurbs {
        degree: p,
        knots,
        points,
        weights,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::ParamCurve;

    fn sample() -> Nurbs {
        Nurbs::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.3, 1.1, 2.0, 2.0, 2.0, 2.0],
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 2.0, 0.5),
                Vec3::new(3.0, 2.5, 1.0),
                Vec3::new(4.0, 0.0, 0.0),
                Vec3::new(6.0, -1.0, 2.0),
                Vec3::new(7.0, 1.0, 1.0),
                Vec3::new(9.0, 0.0, 0.0),
            ],
            Some(vec![1.0, 0.7, 2.0, 1.0, 0.5, 1.3, 1.0]),
        )
        .unwrap()
    }

    #[test]
    fn spans_reproduce_the_curve() {
        for rational in [true, false] {
            let mut c = sample();
            if !rational {
                c.weights = None;
            }
            let spans = c.bezier_spans();
            assert_eq!(spans.len(), 3);
            for s in &spans {
                let (t0, t1) = s.domain();
                for i in 0..=50 {
                    let t = t0 + (t1 - t0) * i as f64 / 50.0;
                    assert!(s.eval(t).dist(c.eval(t)) < 1e-12, "{t}");
                }
            }
            assert_eq!(spans[0].points[0], c.points[0]);
            assert!(spans[2].points[3].dist(c.points[6]) < 1e-15);
        }
    }

    #[test]
    fn unclamped_curve_splits_too() {
        let c = Nurbs::new(
            2,
            (0..8).map(|i| i as f64).collect(),
            (0..5)
                .map(|i| Vec3::new(i as f64, (i % 2) as f64, 0.0))
                .collect(),
            None,
        )
        .unwrap();
        let spans = c.bezier_spans();
        assert_eq!(spans.len(), 3);
        for s in &spans {
            let (t0, t1) = s.domain();
            for i in 0..=20 {
                let t = t0 + (t1 - t0) * i as f64 / 20.0;
                assert!(s.eval(t).dist(c.eval(t)) < 1e-12);
            }
        }
    }

    #[test]
    fn insertion_keeps_the_curve() {
        let c = sample();
        let d = c.insert_knot(0.7, 2);
        assert_eq!(d.points.len(), c.points.len() + 2);
        for i in 0..=40 {
            let t = 2.0 * i as f64 / 40.0;
            assert!(d.eval(t).dist(c.eval(t)) < 1e-12);
        }
    }
}
