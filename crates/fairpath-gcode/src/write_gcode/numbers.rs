//! Numbers as written: how many decimals coordinates get (rounding within
//! its share of the chord tolerance) and fast fixed-point formatting.

use super::GcodeWriteOptions;

/// Most decimals [`write_decimals`] asks for (the fast formatting handles
/// up to 15).
pub(super) const MAX_DECIMALS: usize = 12;

/// Share of the output tolerance that the rounding of written coordinates
/// may take (more decimals are written until it fits), from the one ledger
/// of the tolerance ([`fairpath::budget`]).
pub use fairpath::budget::ROUNDING_SHARE;

/// How far rounding can move a written arc, in units of the rounding `rho`
/// of one point: start and end by `rho` each, the centre by `rho`, so the
/// radius by up to `2 rho` at either end and the angle by `2 rho / r` (a
/// chord of `2 rho` seen from the centre), so `rho + 2 rho + 2 rho`.
pub const ARC_ROUNDING_FACTOR: f64 = 5.0;

/// Decimals to write coordinates with in units of `mm_per_unit` mm, at
/// least `min`, and the largest distance (mm) rounding then moves a point:
/// each axis by at most half a unit of the last decimal, so
/// `sqrt(3) / 2 * 10^-decimals * mm_per_unit`. Decimals are added until that
/// is at most [`ROUNDING_SHARE`] of `chord_mm` (or `MAX_DECIMALS` are
/// reached); the curves are then sampled within `chord_mm` less the
/// rounding, so that the polyline as it reads back stays within
/// `chord_mm` of them (a segment between two moved points lies within the
/// larger move of the segment between the exact ones). Without this, 4
/// decimals (up to 0.087 um of rounding) on top of a chord error of 0.1 um
/// took LinuxCNC's `Cereal.ngc` smoothed at 0.001 mm to 0.001012 mm, and
/// `smooth` refused to write it. Writers of arcs pass `chord_mm /`
/// [`ARC_ROUNDING_FACTOR`].
pub fn write_decimals(chord_mm: f64, mm_per_unit: f64, min: usize) -> (usize, f64) {
    let d = decimals_within(min, mm_per_unit, ROUNDING_SHARE * chord_mm);
    (d, rounding_mm(d, mm_per_unit))
}

/// Decimals of coordinates written in units of `mm_per_unit` mm (at least
/// `min`) under `opts`, and the distance (mm) rounding then moves a point:
/// [`write_decimals`] of the chord (divided by [`ARC_ROUNDING_FACTOR`]
/// when arcs are written), more when [`GcodeWriteOptions::resolution_mm`]
/// asks for them.
pub fn output_decimals(opts: &GcodeWriteOptions, mm_per_unit: f64, min: usize) -> (usize, f64) {
    let factor = if opts.arcs.is_some() {
        ARC_ROUNDING_FACTOR
    } else {
        1.0
    };
    let (d, _) = write_decimals(opts.chord_mm / factor, mm_per_unit, min);
    let d = opts
        .resolution_mm
        .map_or(d, |r| decimals_within(d, mm_per_unit, r));
    (d, rounding_mm(d, mm_per_unit))
}

/// The largest distance (mm) rounding coordinates in units of
/// `mm_per_unit` mm to `decimals` decimals moves a point: each axis by at
/// most half a unit of the last decimal.
pub(super) fn rounding_mm(decimals: usize, mm_per_unit: f64) -> f64 {
    0.5 * 3f64.sqrt() * 10f64.powi(-(decimals as i32)) * mm_per_unit
}

/// The fewest decimals from `min` on whose rounding ([`rounding_mm`]) is
/// at most `limit_mm`, or [`MAX_DECIMALS`].
pub(super) fn decimals_within(min: usize, mm_per_unit: f64, limit_mm: f64) -> usize {
    let mut d = min;
    while d < MAX_DECIMALS && rounding_mm(d, mm_per_unit) > limit_mm {
        d += 1;
    }
    d
}

/// Formats `v` with `decimals` decimals, trailing zeros and a trailing point
/// removed, and no negative zero. Values are rounded to the nearest unit of
/// the last decimal through integer arithmetic (std's exact float formatting
/// is the slowest part of writing large programs otherwise).
pub(crate) fn fmt_fixed(v: f64, decimals: usize) -> String {
    let scale = 10f64.powi(decimals as i32);
    let scaled = (v * scale).round();
    if decimals > 15 || !scaled.is_finite() || scaled.abs() >= 9.0e15 {
        return fmt_fixed_slow(v, decimals);
    }
    let n = scaled as i64;
    let neg = n < 0;
    let mut digits = n.unsigned_abs();
    let mut frac = [0u8; 16];
    let mut nf = 0;
    // Fraction digits, dropping trailing zeros.
    let mut significant = false;
    for _ in 0..decimals {
        let d = (digits % 10) as u8;
        digits /= 10;
        if d != 0 || significant {
            significant = true;
            frac[nf] = b'0' + d;
            nf += 1;
        }
    }
    let mut s = String::with_capacity(24);
    if neg && (digits != 0 || nf != 0) {
        s.push('-');
    }
    s.push_str(itoa_u64(digits).as_str());
    if nf > 0 {
        s.push('.');
        for i in (0..nf).rev() {
            s.push(frac[i] as char);
        }
    }
    s
}

fn itoa_u64(v: u64) -> String {
    v.to_string()
}

fn fmt_fixed_slow(v: f64, decimals: usize) -> String {
    let mut s = format!("{:.*}", decimals, v);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".into();
    }
    s
}

#[cfg(test)]
mod fmt_tests {
    use super::{fmt_fixed, fmt_fixed_slow};

    #[test]
    fn fast_formatting_matches_std_within_half_a_unit() {
        for &v in &[
            0.0,
            -0.0,
            1.5,
            -1.25,
            0.00004,
            -0.00004,
            12.34565,
            99999.0,
            -3.0e-5,
            1.0e9,
            0.1 + 0.2,
        ] {
            for d in [3usize, 4, 5] {
                let a: f64 = fmt_fixed(v, d).parse().unwrap();
                let b: f64 = fmt_fixed_slow(v, d).parse().unwrap();
                assert!(
                    (a - b).abs() <= 10f64.powi(-(d as i32)) * 1.0001,
                    "{v} {d}: {a} {b}"
                );
                assert!((a - v).abs() <= 0.5 * 10f64.powi(-(d as i32)) * 1.0001);
            }
        }
        assert_eq!(fmt_fixed(-0.00001, 4), "0");
        assert_eq!(fmt_fixed(2.5, 4), "2.5");
        assert_eq!(fmt_fixed(-12.0, 4), "-12");
        assert_eq!(fmt_fixed(0.05, 4), "0.05");
    }
}
