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
        let (knots, pw) = raise_breakpoints(p, &self.knots, &to_hom(self), &breaks);
        let rational = self.weights.is_some();
        let mut out = Vec::with_capacity(breaks.len().saturating_sub(1));
        // The last knot equal to each span's start, found moving on (the
        // breakpoints and the knots both increase).
        let mut j = 0usize;
        for w in breaks.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            while j + 1 < knots.len() && knots[j + 1] <= t0 {
                j += 1;
            }
            if knots[j] != t0 || j < p {
                continue;
            }
            let mut kv = vec![t0; p + 1];
            kv.extend(core::iter::repeat_n(t1, p + 1));
            out.push(from_hom(p, kv, &pw[j - p..=j], rational));
        }
        out
    }
}

impl Nurbs {
    /// A polynomial cubic's Bezier spans as control points, with its
    /// breakpoints (`breaks.len() == spans.len() + 1`): the points of
    /// [`Nurbs::bezier_spans`] (the same knot insertions) without a
    /// [`Nurbs`] per span. `None` for a rational curve, another degree, a
    /// curve that fails [`Nurbs::validate`], or knots that leave a span out.
    pub fn cubic_bezier_points(&self) -> Option<(Vec<f64>, Vec<[Vec3; 4]>)> {
        if self.degree != 3 || self.weights.is_some() || self.validate().is_err() {
            return None;
        }
        let breaks = self.breakpoints();
        let (knots, pw) = raise_breakpoints(3, &self.knots, &to_hom(self), &breaks);
        let point = |h: &Hom| Vec3::new(h[0], h[1], h[2]);
        let mut out = Vec::with_capacity(breaks.len().saturating_sub(1));
        let mut j = 0usize;
        for &t0 in &breaks[..breaks.len() - 1] {
            while j + 1 < knots.len() && knots[j + 1] <= t0 {
                j += 1;
            }
            if knots[j] != t0 || j < 3 {
                return None;
            }
            let q = &pw[j - 3..=j];
            out.push([point(&q[0]), point(&q[1]), point(&q[2]), point(&q[3])]);
        }
        Some((breaks, out))
    }
}

/// `knots`/`pw` (degree `p`) with each of `breaks` (increasing, in the
/// domain) inserted until its multiplicity is `p`: the result of
/// [`insert_once`] applied breakpoint after breakpoint, with the same
/// arithmetic (so bit for bit the same points), in time linear in the
/// size of the curve. An insertion at `u` changes only the points of the
/// span of `u` and shifts those after it; the breakpoints increase, so the
/// knots and points are moved from the input to the output as the
/// insertions reach them, and each insertion edits the output's last
/// `p + 1` points and `p + 2` knots. (Inserting into the whole vectors,
/// each insertion copied every point: on the fits' pieces of 64 spans,
/// 9% of `auto`'s time on `surface-raster-large.ngc`.)
fn raise_breakpoints(
    p: usize,
    src_knots: &[f64],
    src_pw: &[Hom],
    breaks: &[f64],
) -> (Vec<f64>, Vec<Hom>) {
    let extra = p * breaks.len();
    let mut knots: Vec<f64> = Vec::with_capacity(src_knots.len() + extra);
    let mut pw: Vec<Hom> = Vec::with_capacity(src_pw.len() + extra);
    let (mut nk, mut np) = (0usize, 0usize);
    let mut blends: Vec<Hom> = Vec::with_capacity(p);
    for &u in breaks {
        loop {
            // The output holds every knot at or before `u` and `p + 2`
            // after it (where there are), as `insert_once` reads them.
            while nk < src_knots.len() && src_knots[nk] <= u {
                knots.push(src_knots[nk]);
                nk += 1;
            }
            let after = knots.iter().rev().take_while(|&&t| t > u).count();
            for _ in after..p + 2 {
                if nk == src_knots.len() {
                    break;
                }
                knots.push(src_knots[nk]);
                nk += 1;
            }
            let total = knots.len() + (src_knots.len() - nk);
            // As `insert_once`: the span of `u` and its multiplicity (the
            // knots equal to `u` are all in the output, and adjacent).
            let last = knots.iter().rposition(|&t| t <= u);
            let s = last.map_or(0, |l| {
                knots[..=l].iter().rev().take_while(|&&t| t == u).count()
            });
            if s >= p {
                break;
            }
            let k = last.unwrap_or(0).clamp(p, total - 2);
            while pw.len() <= k && np < src_pw.len() {
                pw.push(src_pw[np]);
                np += 1;
            }
            blends.clear();
            for i in k + 1 - p..=k - s {
                let alpha = (u - knots[i]) / (knots[i + p] - knots[i]);
                blends.push(blend(pw[i], pw[i - 1], alpha));
            }
            pw.splice(k + 1 - p..k - s, blends.drain(..));
            knots.insert(k + 1, u);
        }
    }
    knots.extend_from_slice(&src_knots[nk..]);
    pw.extend_from_slice(&src_pw[np..]);
    (knots, pw)
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
    use crate::seeded::Rng;

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

    /// The decomposition as it was first written: every breakpoint
    /// inserted into the whole vectors ([`insert_once`]), and each span's
    /// start looked up in all the knots.
    fn spans_by_whole_insertion(c: &Nurbs) -> Vec<Nurbs> {
        let p = c.degree;
        let breaks = c.breakpoints();
        let mut knots = c.knots.clone();
        let mut pw = to_hom(c);
        for &t in &breaks {
            while knots.iter().filter(|&&k| k == t).count() < p {
                insert_once(p, &mut knots, &mut pw, t);
            }
        }
        let mut out = Vec::new();
        for w in breaks.windows(2) {
            let j = match knots.iter().rposition(|&k| k == w[0]) {
                Some(j) if j >= p => j,
                _ => continue,
            };
            let mut kv = vec![w[0]; p + 1];
            kv.extend(core::iter::repeat_n(w[1], p + 1));
            out.push(from_hom(p, kv, &pw[j - p..=j], c.weights.is_some()));
        }
        out
    }

    /// A random valid curve: degree 1 to 5, clamped or not, knots of
    /// multiplicity up to the degree + 1 inside, rational or not.
    fn random_curve(rng: &mut Rng) -> Nurbs {
        loop {
            let p = 1 + rng.below(5);
            let n_points = p + 1 + rng.below(90);
            let n_knots = n_points + p + 1;
            let clamped = rng.next() < 0.7;
            let mut knots = Vec::with_capacity(n_knots);
            let mut t = 0.0;
            while knots.len() < n_knots {
                let inner = knots.len() > p && knots.len() + p + 1 < n_knots;
                let mult = if clamped && !inner {
                    p + 1
                } else {
                    1 + rng.below(p + 1)
                };
                for _ in 0..mult.min(n_knots - knots.len()) {
                    knots.push(t);
                }
                t += 0.01 + rng.next() * if rng.next() < 0.2 { 10.0 } else { 1.0 };
            }
            let points = (0..n_points)
                .map(|_| Vec3::new(rng.next() * 50.0, rng.next() * 50.0, rng.next() * 5.0))
                .collect();
            let weights =
                (rng.next() < 0.4).then(|| (0..n_points).map(|_| 0.2 + 2.0 * rng.next()).collect());
            if let Ok(c) = Nurbs::new(p, knots, points, weights) {
                return c;
            }
        }
    }

    /// The decomposition in linear time gives the same spans, bit for bit,
    /// as inserting every breakpoint into the whole curve.
    #[test]
    fn seeded_random_curves_split_as_by_whole_insertion() {
        let mut rng = Rng(0x5EED_0B5E);
        let mut compared = 0;
        for _ in 0..400 {
            let c = random_curve(&mut rng);
            let want = spans_by_whole_insertion(&c);
            assert!(!want.is_empty(), "{c:?}");
            assert_eq!(c.bezier_spans(), want, "{c:?}");
            compared += want.len();
        }
        assert!(compared > 2000, "{compared} spans");
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
