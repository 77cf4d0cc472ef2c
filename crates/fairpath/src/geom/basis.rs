//! The one B-spline basis of the crate (Piegl and Tiller, The NURBS Book,
//! 2nd ed., A2.2 BasisFuns and A2.3 DersBasisFuns), in fixed arrays (no
//! allocation per point): [`super::Nurbs`] evaluates with it, and the cubic
//! fits of [`super::fit`] build their systems with it.

/// Highest degree supported (see [`super::Nurbs::MAX_DEGREE`]).
pub const MAX_DEGREE: usize = 7;

/// Length of the basis-function arrays: one per control point a span
/// depends on at the highest degree.
pub const BASIS_LEN: usize = MAX_DEGREE + 1;

/// Piegl-Tiller A2.2: the `degree + 1` non-zero basis functions
/// `N_{span-p..=span, p}` at `t` in span `span` of `knots`, with `0/0 = 0`
/// (empty spans). `degree <= MAX_DEGREE`.
///
/// Each degree runs the one algorithm compiled for it (loops unrolled,
/// arrays of the degree's size). A degree above [`MAX_DEGREE`], which no
/// curve built by [`super::Nurbs::new`] has, gets zeros (debug builds
/// stop there).
pub fn basis_funs(knots: &[f64], degree: usize, span: usize, t: f64) -> [f64; BASIS_LEN] {
    match degree {
        0 => widen(basis_funs_n::<1>(knots, span, t)),
        1 => widen(basis_funs_n::<2>(knots, span, t)),
        2 => widen(basis_funs_n::<3>(knots, span, t)),
        3 => widen(basis_funs_n::<4>(knots, span, t)),
        4 => widen(basis_funs_n::<5>(knots, span, t)),
        5 => widen(basis_funs_n::<6>(knots, span, t)),
        6 => widen(basis_funs_n::<7>(knots, span, t)),
        7 => widen(basis_funs_n::<8>(knots, span, t)),
        _ => {
            debug_assert!(degree <= MAX_DEGREE, "degree {degree} above {MAX_DEGREE}");
            [0.0; BASIS_LEN]
        }
    }
}

/// `x` in the first `N` entries of a basis array, zeros after.
#[inline(always)]
fn widen<const N: usize>(x: [f64; N]) -> [f64; BASIS_LEN] {
    let mut out = [0.0f64; BASIS_LEN];
    out[..N].copy_from_slice(&x);
    out
}

/// [`basis_funs`] at degree `N - 1`.
#[inline(always)]
fn basis_funs_n<const N: usize>(knots: &[f64], span: usize, t: f64) -> [f64; N] {
    basis_triangle(knots, span, t, |_, _| {})
}

/// A2.2's triangle at degree `N - 1`: the basis functions, with each row
/// of lower degree `j` (`N_{span-j..=span, j}` in `n[..=j]`) shown to
/// `row` as it is completed.
#[inline(always)]
fn basis_triangle<const N: usize>(
    knots: &[f64],
    span: usize,
    t: f64,
    mut row: impl FnMut(usize, &[f64; N]),
) -> [f64; N] {
    let p = N - 1;
    let u = &knots[span + 1 - p..=span + p];
    // u[span + k] is u[k + p - 1] here.
    let mut n = [0.0f64; N];
    let mut left = [0.0f64; N];
    let mut right = [0.0f64; N];
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = t - u[p - j];
        right[j] = u[j + p - 1] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let den = right[r + 1] + left[j - r];
            let temp = if den != 0.0 { n[r] / den } else { 0.0 };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
        row(j, &n);
    }
    n
}

/// Piegl-Tiller A2.3: the non-zero basis functions and their derivatives
/// up to order `nd` (at most 2) at `t` in span `span` of `knots`;
/// `ders[k][j]` is the k-th derivative of `N_{span-p+j, p}`, with `0/0 = 0`
/// (empty spans). `degree <= MAX_DEGREE`.
///
/// As [`basis_funs`], each degree runs the one algorithm compiled for it,
/// and a degree above [`MAX_DEGREE`] gets zeros. Degree 3, the degree of
/// the fits and transitions, takes the derivatives from A2.2's lower rows
/// instead (P&T eq. 2.9, six reciprocals of knot differences: the same
/// values to rounding).
pub fn ders_basis_funs(
    knots: &[f64],
    degree: usize,
    span: usize,
    t: f64,
    nd: usize,
) -> [[f64; BASIS_LEN]; 3] {
    match degree {
        0 => widen3(ders_basis_funs_n::<1>(knots, span, t, nd)),
        1 => widen3(ders_basis_funs_n::<2>(knots, span, t, nd)),
        2 => widen3(ders_basis_funs_n::<3>(knots, span, t, nd)),
        3 => widen3(ders_basis_funs_cubic(knots, span, t, nd)),
        4 => widen3(ders_basis_funs_n::<5>(knots, span, t, nd)),
        5 => widen3(ders_basis_funs_n::<6>(knots, span, t, nd)),
        6 => widen3(ders_basis_funs_n::<7>(knots, span, t, nd)),
        7 => widen3(ders_basis_funs_n::<8>(knots, span, t, nd)),
        _ => {
            debug_assert!(degree <= MAX_DEGREE, "degree {degree} above {MAX_DEGREE}");
            [[0.0; BASIS_LEN]; 3]
        }
    }
}

#[inline(always)]
fn widen3<const N: usize>(d: [[f64; N]; 3]) -> [[f64; BASIS_LEN]; 3] {
    [widen(d[0]), widen(d[1]), widen(d[2])]
}

/// [`ders_basis_funs`] at degree 3, the degree of every fit and corner
/// transition: the values by A2.2's triangle exactly as [`basis_funs`]
/// computes them (to the bit), keeping its degree 1 and 2 rows, and the
/// derivatives from those rows by the derivative formula of a B-spline
/// basis function (Piegl and Tiller, eq. 2.9:
/// `N'_{j,p} = p N_{j,p-1} / (u_{j+p} - u_j) - p N_{j+1,p-1} / (u_{j+p+1} - u_{j+1})`,
/// applied once for the first derivative and twice for the second, with
/// `0/0 = 0`). Six reciprocals of knot differences instead of A2.3's
/// divisions inside its loops: the same values to rounding, about a third
/// of the work where curves are sampled densely (rendering, speed caps).
#[inline(always)]
fn ders_basis_funs_cubic(knots: &[f64], span: usize, t: f64, nd: usize) -> [[f64; 4]; 3] {
    const P: usize = 3;
    // u[k] is the knot u_{span - 2 + k}.
    let u = &knots[span + 1 - P..=span + P];
    // The rows of degree 1 and 2: N_{span-1..=span, 1}, N_{span-2..=span, 2}.
    let mut n1 = [0.0f64; 2];
    let mut n2 = [0.0f64; 3];
    let n = basis_triangle::<4>(knots, span, t, |j, n| match j {
        1 => n1.copy_from_slice(&n[..2]),
        2 => n2.copy_from_slice(&n[..3]),
        _ => {}
    });
    let mut ders = [n, [0.0; 4], [0.0; 4]];
    let nd = nd.min(2);
    if nd == 0 {
        return ders;
    }
    let inv = |d: f64| if d != 0.0 { 1.0 / d } else { 0.0 };
    // 3 / (u_{j+3} - u_j) for j = span-2, span-1, span.
    let d3 = [
        3.0 * inv(u[3] - u[0]),
        3.0 * inv(u[4] - u[1]),
        3.0 * inv(u[5] - u[2]),
    ];
    // eq. 2.9 from a row of degree 2 (`m[k]` for j = span-2+k; the
    // functions of that degree outside the span are zero).
    let from_degree_2 = |m: [f64; 3]| {
        let a = [m[0] * d3[0], m[1] * d3[1], m[2] * d3[2]];
        [-a[0], a[0] - a[1], a[1] - a[2], a[2]]
    };
    ders[1] = from_degree_2(n2);
    if nd == 2 {
        // The derivatives of the degree 2 row, from the degree 1 row.
        let b = [
            2.0 * n1[0] * inv(u[3] - u[1]),
            2.0 * n1[1] * inv(u[4] - u[2]),
        ];
        ders[2] = from_degree_2([-b[0], b[0] - b[1], b[1]]);
    }
    ders
}

/// [`ders_basis_funs`] at degree `N - 1`.
#[inline(always)]
fn ders_basis_funs_n<const N: usize>(
    knots: &[f64],
    span: usize,
    t: f64,
    nd: usize,
) -> [[f64; N]; 3] {
    let p = N - 1;
    let u = &knots[span + 1 - p..=span + p];
    let mut ndu = [[0.0f64; N]; N];
    let mut left = [0.0f64; N];
    let mut right = [0.0f64; N];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - u[p - j];
        right[j] = u[j + p - 1] - t;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = if ndu[j][r] != 0.0 {
                ndu[r][j - 1] / ndu[j][r]
            } else {
                0.0
            };
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = [[0.0f64; N]; 3];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let nd = nd.min(p).min(2);
    if nd == 0 {
        return ders;
    }
    let mut a = [[0.0f64; N]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0] = [0.0; N];
        a[0][0] = 1.0;
        for k in 1..=nd {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rk = rk as usize;
                a[s2][0] = if ndu[pk + 1][rk] != 0.0 {
                    a[s1][0] / ndu[pk + 1][rk]
                } else {
                    0.0
                };
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = if ndu[pk + 1][idx] != 0.0 {
                    (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx]
                } else {
                    0.0
                };
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = if ndu[pk + 1][r] != 0.0 {
                    -a[s1][k - 1] / ndu[pk + 1][r]
                } else {
                    0.0
                };
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            core::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut f = p as f64;
    for (k, row) in ders.iter_mut().enumerate().take(nd + 1).skip(1) {
        for v in row.iter_mut().take(p + 1) {
            *v *= f;
        }
        f *= (p - k) as f64;
    }
    ders
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A clamped knot vector of degree `p` from the gaps (some zero: empty
    /// spans and multiple knots), with a span index and a parameter in it.
    fn knots_span_t() -> impl Strategy<Value = (Vec<f64>, usize, usize, f64)> {
        knots_span_t_of(0usize..=MAX_DEGREE)
    }

    /// [`knots_span_t`] of a degree drawn from `degrees`.
    fn knots_span_t_of(
        degrees: impl Strategy<Value = usize>,
    ) -> impl Strategy<Value = (Vec<f64>, usize, usize, f64)> {
        (degrees, 1usize..12)
            .prop_flat_map(|(p, inner)| {
                let gaps = proptest::collection::vec(
                    prop_oneof![3 => 0.001f64..10.0, 1 => Just(0.0)],
                    inner + 1,
                );
                (Just(p), gaps, 0.0f64..=1.0, any::<prop::sample::Index>())
            })
            .prop_map(|(p, gaps, x, idx)| {
                let mut k = alloc::vec![0.0; p + 1];
                let mut at = 0.0;
                for g in &gaps[..gaps.len() - 1] {
                    at += g;
                    k.push(at);
                }
                at += gaps[gaps.len() - 1].max(0.5);
                k.extend(core::iter::repeat_n(at, p + 1));
                // Spans p..k.len()-p-1; pick one, and t inside it (or at its ends).
                let last = k.len() - p - 2;
                let span = p + idx.index(last - p + 1);
                let t = k[span] + x * (k[span + 1] - k[span]);
                (k, p, span, t)
            })
    }

    /// Cox-de Boor's recursion (P&T eqs. 2.5 and 2.9), written out from
    /// the definition as a check independent of A2.2/A2.3: `N_{i,q}(t)` on
    /// the half-open spans, `0/0 = 0`, and its derivatives of order `k`
    /// from those of degree `q - 1`.
    fn cox_de_boor(u: &[f64], i: usize, q: usize, t: f64, span: usize, k: usize) -> f64 {
        let frac = |a: f64, b: f64| if b != 0.0 { a / b } else { 0.0 };
        if k > 0 {
            if q == 0 {
                return 0.0;
            }
            let qf = q as f64;
            return qf * frac(cox_de_boor(u, i, q - 1, t, span, k - 1), u[i + q] - u[i])
                - qf * frac(
                    cox_de_boor(u, i + 1, q - 1, t, span, k - 1),
                    u[i + q + 1] - u[i + 1],
                );
        }
        if q == 0 {
            // The span the point is taken in (its end included).
            return if i == span { 1.0 } else { 0.0 };
        }
        frac(t - u[i], u[i + q] - u[i]) * cox_de_boor(u, i, q - 1, t, span, 0)
            + frac(u[i + q + 1] - t, u[i + q + 1] - u[i + 1])
                * cox_de_boor(u, i + 1, q - 1, t, span, 0)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// At degree 3 the derivatives from the triangle's lower rows
        /// (eq. 2.9) are A2.3's to rounding: within a few ulps of the
        /// largest derivative of the span, on clamped knots with empty
        /// and multiple spans; the values are the same to the bit.
        #[test]
        fn cubic_derivatives_equal_a2_3(
            (k, _, span, t) in knots_span_t_of(Just(3)),
        ) {
            let fast = ders_basis_funs_cubic(&k, span, t, 2);
            let a23 = ders_basis_funs_n::<4>(&k, span, t, 2);
            prop_assert_eq!(fast[0].map(f64::to_bits), a23[0].map(f64::to_bits));
            for order in 1..=2 {
                let m = a23[order].iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for j in 0..4 {
                    prop_assert!(
                        (fast[order][j] - a23[order][j]).abs() <= 1e-13 * m.max(1e-300),
                        "N^({})[{}] {} vs A2.3 {}", order, j, fast[order][j], a23[order][j]
                    );
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Each degree's basis and its first two derivatives equal Cox-de
        /// Boor's recursion (to rounding, scaled by the knot spacing for
        /// the derivatives), on clamped knots with empty spans; in a
        /// non-empty span the values sum to 1 and the derivatives to 0.
        #[test]
        fn the_basis_equals_cox_de_boor(
            (k, p, span, t) in knots_span_t(),
            nd in 0usize..=2,
        ) {
            let n = basis_funs(&k, p, span, t);
            let d = ders_basis_funs(&k, p, span, t, nd);
            let h = (k[span + 1] - k[span]).max(1e-3);
            for j in 0..=p {
                let i = span - p + j;
                let want = cox_de_boor(&k, i, p, t, span, 0);
                prop_assert!((n[j] - want).abs() <= 1e-12, "N[{}] {} vs {}", j, n[j], want);
                prop_assert_eq!(d[0][j].to_bits(), n[j].to_bits());
                for (order, row) in d.iter().enumerate().take(nd.min(p) + 1).skip(1) {
                    let want = cox_de_boor(&k, i, p, t, span, order);
                    let scale = 1.0 / h.powi(order as i32);
                    prop_assert!(
                        (row[j] - want).abs() <= 1e-9 * scale.max(want.abs()).max(1.0),
                        "N^({})[{}] {} vs {}", order, j, row[j], want
                    );
                }
            }
            // (In an empty span every function is 0/0 = 0 somewhere.)
            if k[span] == k[span + 1] {
                return Ok(());
            }
            let sum: f64 = n[..=p].iter().sum();
            prop_assert!((sum - 1.0).abs() <= 1e-12);
            for (order, row) in d.iter().enumerate().take(nd.min(p) + 1).skip(1) {
                let s: f64 = row[..=p].iter().sum();
                let m = row[..=p].iter().fold(1.0f64, |a, x| a.max(x.abs()));
                prop_assert!(s.abs() <= 1e-9 * m, "derivatives of order {} sum to {}", order, s);
            }
        }
    }
}
