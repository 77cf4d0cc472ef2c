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
pub fn basis_funs(knots: &[f64], degree: usize, span: usize, t: f64) -> [f64; BASIS_LEN] {
    let p = degree;
    let u = knots;
    let mut n = [0.0f64; BASIS_LEN];
    let mut left = [0.0f64; BASIS_LEN];
    let mut right = [0.0f64; BASIS_LEN];
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = t - u[span + 1 - j];
        right[j] = u[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let den = right[r + 1] + left[j - r];
            let temp = if den != 0.0 { n[r] / den } else { 0.0 };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}

/// Piegl-Tiller A2.3: the non-zero basis functions and their derivatives
/// up to order `nd` (at most 2) at `t` in span `span` of `knots`;
/// `ders[k][j]` is the k-th derivative of `N_{span-p+j, p}`, with `0/0 = 0`
/// (empty spans). `degree <= MAX_DEGREE`.
pub fn ders_basis_funs(
    knots: &[f64],
    degree: usize,
    span: usize,
    t: f64,
    nd: usize,
) -> [[f64; BASIS_LEN]; 3] {
    let p = degree;
    let u = knots;
    let mut ndu = [[0.0f64; BASIS_LEN]; BASIS_LEN];
    let mut left = [0.0f64; BASIS_LEN];
    let mut right = [0.0f64; BASIS_LEN];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - u[span + 1 - j];
        right[j] = u[span + j] - t;
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
    let mut ders = [[0.0f64; BASIS_LEN]; 3];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let nd = nd.min(p).min(2);
    if nd == 0 {
        return ders;
    }
    let mut a = [[0.0f64; BASIS_LEN]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0] = [0.0; BASIS_LEN];
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
