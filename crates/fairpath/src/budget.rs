//! One place that hands out the user's tolerance.
//!
//! The promise is: every point of the written feed path lies within
//! `total` mm (3D) of the original feed path. Three things spend it, one
//! after the other, and their shares add up to `total`:
//!
//! | share | who spends it | bounded by |
//! |---|---|---|
//! | [`ToleranceBudget::smoothing`] | the smoothing method: its curves stay this close to the original | the verifier, on the curves |
//! | [`ToleranceBudget::output`] | writing the curves as the output format can say them: G1 chords, G2/G3 arcs, spline blocks, and the rounding of written coordinates (the writer takes its share of rounding out of this, see `fairpath_gcode::write_decimals`) | the verifier, on the written text read back |
//! | [`ToleranceBudget::blend`] | the controller's own corner blending of what is written, when fairpath writes a blending mode for it (LinuxCNC `G64 P<blend> Q0`); 0 otherwise | the controller |
//!
//! So the curves are within `smoothing`, the written path within
//! `smoothing + output` (checked on the re-read text), and what a blending
//! controller runs within `total`.

/// Default share of the output approximation: a tenth of the tolerance.
pub const OUTPUT_SHARE: f64 = 0.1;

/// Smallest tolerance or share accepted (mm): 1 nm, below any machine's
/// resolution and the f64 rounding of metre-sized parts.
pub const MIN_SHARE_MM: f64 = 1e-6;

/// Largest tolerance accepted (mm).
pub const MAX_TOLERANCE_MM: f64 = 1000.0;

/// How the tolerance is shared (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToleranceBudget {
    /// The user's tolerance.
    pub total: f64,
    /// Writing the curves in the output format, rounding included.
    pub output: f64,
    /// The controller's blending of corners of what is written.
    pub blend: f64,
}

/// A budget that cannot be made.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum BudgetError {
    #[error("the tolerance must be a number of mm from 1e-6 to 1000, got {0}")]
    Tolerance(f64),
    #[error(
        "the output share ({output} mm) must be positive and at most half the tolerance ({half} mm)"
    )]
    Output { output: f64, half: f64 },
    #[error("the blending share must be a number of mm >= 0, got {0}")]
    Blend(f64),
    #[error(
        "the tolerance {total} mm leaves {left:e} mm for smoothing after the output ({output} mm) \
         and blending ({blend} mm) shares; at least 1e-6 mm is needed"
    )]
    NothingLeft {
        total: f64,
        output: f64,
        blend: f64,
        left: f64,
    },
}

impl ToleranceBudget {
    /// The budget for `total` mm: `output` mm for writing the curves
    /// (default [`OUTPUT_SHARE`] of the tolerance) and `blend` mm for the
    /// controller's blending (0 when fairpath writes no blending mode).
    pub fn new(total: f64, output: Option<f64>, blend: f64) -> Result<Self, BudgetError> {
        if !(total.is_finite() && (MIN_SHARE_MM..=MAX_TOLERANCE_MM).contains(&total)) {
            return Err(BudgetError::Tolerance(total));
        }
        let output = output.unwrap_or(OUTPUT_SHARE * total);
        let half = 0.5 * total;
        if !(output.is_finite() && output > 0.0 && output <= half) {
            return Err(BudgetError::Output { output, half });
        }
        if !(blend.is_finite() && blend >= 0.0) {
            return Err(BudgetError::Blend(blend));
        }
        let b = ToleranceBudget {
            total,
            output,
            blend,
        };
        let left = b.smoothing();
        if left.is_nan() || left < MIN_SHARE_MM {
            return Err(BudgetError::NothingLeft {
                total,
                output,
                blend,
                left,
            });
        }
        Ok(b)
    }

    /// What the smoothing method may use: the rest.
    pub fn smoothing(&self) -> f64 {
        self.total - self.output - self.blend
    }

    /// What the written path may deviate from the original, as read back
    /// (the controller's blending comes on top, within `blend`).
    pub fn written(&self) -> f64 {
        self.total - self.blend
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shares_add_up_to_the_tolerance() {
        let b = ToleranceBudget::new(0.05, None, 0.0025).unwrap();
        assert!((b.output - 0.005).abs() < 1e-15);
        assert_eq!(b.smoothing() + b.output + b.blend, 0.05);
        assert_eq!(b.written(), 0.05 - 0.0025);
    }

    #[test]
    fn bad_budgets_are_errors() {
        for t in [0.0, -1.0, f64::NAN, 2000.0, 1e-7] {
            assert!(matches!(
                ToleranceBudget::new(t, None, 0.0),
                Err(BudgetError::Tolerance(_))
            ));
        }
        assert!(matches!(
            ToleranceBudget::new(0.05, Some(0.03), 0.0),
            Err(BudgetError::Output { .. })
        ));
        assert!(matches!(
            ToleranceBudget::new(0.05, None, -1.0),
            Err(BudgetError::Blend(_))
        ));
        assert!(matches!(
            ToleranceBudget::new(0.05, Some(0.025), 0.025),
            Err(BudgetError::NothingLeft { .. })
        ));
    }
}
