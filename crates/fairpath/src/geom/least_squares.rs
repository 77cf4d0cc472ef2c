//! Symmetric positive definite banded systems with vector right-hand sides:
//! the normal equations of B-spline least squares.
//!
//! A cubic B-spline has four non-zero basis functions at any parameter, so
//! `N^T N` (and the Gram matrix of their second derivatives) has entries only
//! where `|j - k| <= 3`: half bandwidth [`HALF_BAND`]. Banded Cholesky
//! (Golub and Van Loan, Matrix Computations, 4th ed., algorithm 4.3.5,
//! "band Cholesky") factors it in `O(n w^2)` and solves in `O(n w)`, so a fit
//! costs time linear in the number of control points.

use super::Vec3;
use crate::math;
use alloc::vec;
use alloc::vec::Vec;

/// Half bandwidth of the normal equations of a cubic B-spline fit.
pub const HALF_BAND: usize = 3;

/// A symmetric matrix with `a[i][j] = 0` for `|i - j| > HALF_BAND`, stored
/// by its lower band: `low[i][k] = a[i][i - k]`.
#[derive(Clone, Debug, PartialEq)]
pub struct BandedSpd {
    low: Vec<[f64; HALF_BAND + 1]>,
}

/// Why a banded system could not be solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BandedError {
    /// A pivot was not positive: the matrix is singular or indefinite (for a
    /// fit: too few data per control point and no smoothing term).
    NotPositiveDefinite { row: usize },
}

impl BandedSpd {
    /// The `n x n` zero matrix.
    pub fn zeros(n: usize) -> BandedSpd {
        BandedSpd {
            low: vec![[0.0; HALF_BAND + 1]; n],
        }
    }

    pub fn len(&self) -> usize {
        self.low.len()
    }
    pub fn is_empty(&self) -> bool {
        self.low.is_empty()
    }

    /// Adds `v` to `a[i][j]` and, by symmetry, `a[j][i]` (once when `i == j`).
    /// Entries outside the band are a caller's bug.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let (r, c) = if i >= j { (i, j) } else { (j, i) };
        debug_assert!(r - c <= HALF_BAND, "entry outside the band");
        self.low[r][r - c] += v;
    }

    /// Adds `w b_j b_k` to `a[i0 + j][i0 + k]` (and its mirror) for every
    /// `k <= j < 4` with `b_j != 0`: the outer product of four basis values
    /// whose rows are all in the matrix (`i0 + 4 <= len`). Each entry gets
    /// `(w * b_j) * b_k`, as [`BandedSpd::add`] of that value would give.
    #[inline(always)]
    pub fn add_outer4(&mut self, i0: usize, b: &[f64; 4], w: f64) {
        let rows: &mut [[f64; HALF_BAND + 1]; 4] =
            (&mut self.low[i0..i0 + 4]).try_into().expect("four rows");
        for j in 0..4 {
            if b[j] == 0.0 {
                continue;
            }
            let wb = w * b[j];
            for k in 0..=j {
                rows[j][j - k] += wb * b[k];
            }
        }
    }

    /// `a[i][j]`.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (r, c) = if i >= j { (i, j) } else { (j, i) };
        if r - c > HALF_BAND {
            0.0
        } else {
            self.low[r][r - c]
        }
    }

    /// Factors the matrix in place into `L L^T` (band Cholesky; `L` keeps
    /// the band). A pivot at or below `rel_pivot` times the diagonal entry it
    /// came from counts as zero: the matrix is then reported singular rather
    /// than solved with a meaningless result.
    pub fn cholesky(mut self, rel_pivot: f64) -> Result<CholeskyBand, BandedError> {
        let n = self.low.len();
        for i in 0..n {
            // Off-diagonal entries of row i: l[i][j] for j in i-w..i.
            let j0 = i.saturating_sub(HALF_BAND);
            for j in j0..i {
                let mut s = self.low[i][i - j];
                let k0 = j0.max(j.saturating_sub(HALF_BAND));
                for k in k0..j {
                    s -= self.low[i][i - k] * self.low[j][j - k];
                }
                self.low[i][i - j] = s / self.low[j][0];
            }
            let d0 = self.low[i][0];
            let mut d = d0;
            for k in j0..i {
                d -= self.low[i][i - k] * self.low[i][i - k];
            }
            if d.is_nan() || d <= rel_pivot * d0 || !d.is_finite() {
                return Err(BandedError::NotPositiveDefinite { row: i });
            }
            self.low[i][0] = math::sqrt(d);
        }
        Ok(CholeskyBand { l: self.low })
    }
}

/// The factor `L` of a [`BandedSpd`] matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct CholeskyBand {
    l: Vec<[f64; HALF_BAND + 1]>,
}

impl CholeskyBand {
    /// Solves `L L^T x = b` in place (`b` becomes `x`), one solve per
    /// coordinate.
    pub fn solve(&self, b: &mut [Vec3]) {
        let n = self.l.len();
        assert_eq!(b.len(), n, "right-hand side of the wrong size");
        for i in 0..n {
            let lo = i.saturating_sub(HALF_BAND);
            let mut s = b[i];
            for (k, bk) in b.iter().enumerate().take(i).skip(lo) {
                s -= *bk * self.l[i][i - k];
            }
            b[i] = s / self.l[i][0];
        }
        for i in (0..n).rev() {
            let hi = (i + HALF_BAND + 1).min(n);
            let mut s = b[i];
            for (k, bk) in b.iter().enumerate().take(hi).skip(i + 1) {
                s -= *bk * self.l[k][k - i];
            }
            b[i] = s / self.l[i][0];
        }
    }
}
