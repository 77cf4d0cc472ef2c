//! Lengths on the command line (`--tolerance`, `--chord`): a number with
//! an optional unit, `0.05mm`, `0.002in` or a bare `0.05`, which is in the
//! program's units (G20: inches, G21: mm), as every other length in the
//! program is.

use fairpath_gcode::Units;
use std::fmt;
use std::str::FromStr;

/// A positive length as typed: its number and the unit written after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Length {
    pub value: f64,
    /// `None`: a bare number, in the program's units.
    pub unit: Option<Units>,
}

/// The unit's name as printed (`mm`, `in`).
pub fn unit_name(u: Units) -> &'static str {
    match u {
        Units::Mm => "mm",
        Units::Inch => "in",
    }
}

impl Length {
    /// The length in mm, a bare number taken in `program` units.
    pub fn mm(self, program: Units) -> f64 {
        self.value * self.unit.unwrap_or(program).mm_per_unit()
    }
}

impl fmt::Display for Length {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.unit {
            Some(u) => write!(f, "{}{}", self.value, unit_name(u)),
            None => write!(f, "{}", self.value),
        }
    }
}

/// Units accepted after the number (lower case, as typed).
const SUFFIXES: &[(&str, Units)] = &[
    ("mm", Units::Mm),
    ("inch", Units::Inch),
    ("in", Units::Inch),
    ("\"", Units::Inch),
];

impl FromStr for Length {
    type Err = String;

    /// A positive, finite number with an optional unit (`mm`, `in`,
    /// `inch`, `"`); zero and negative lengths are errors that say why.
    fn from_str(s: &str) -> Result<Length, String> {
        let lower = s.trim().to_ascii_lowercase();
        let (number, unit) = SUFFIXES
            .iter()
            .find_map(|&(suffix, u)| lower.strip_suffix(suffix).map(|n| (n, Some(u))))
            .unwrap_or((lower.as_str(), None));
        let value: f64 = number.trim().parse().map_err(|_| {
            "not a length: give a number with an optional unit, e.g. 0.05, 0.05mm or 0.002in"
                .to_string()
        })?;
        if !value.is_finite() {
            return Err("the length must be a finite number, e.g. 0.05mm".into());
        }
        if value <= 0.0 {
            return Err(format!(
                "the length must be positive (how far the path may move), got {value}: \
                 give e.g. 0.05mm or 0.002in"
            ));
        }
        Ok(Length { value, unit })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_with_and_without_units() {
        let mm = |s: &str, u| s.parse::<Length>().unwrap().mm(u);
        assert_eq!(mm("0.05", Units::Mm), 0.05);
        assert_eq!(mm("0.05mm", Units::Inch), 0.05);
        assert_eq!(mm("0.002in", Units::Mm), 0.002 * 25.4);
        assert_eq!(mm("0.002 IN", Units::Mm), 0.002 * 25.4);
        assert_eq!(mm("0.002inch", Units::Mm), 0.002 * 25.4);
        assert_eq!(mm("0.002", Units::Inch), 0.002 * 25.4);
        assert_eq!(mm("1e-3mm", Units::Inch), 1e-3);
    }

    #[test]
    fn zero_negative_and_garbage_are_errors() {
        for s in [
            "0", "-0.05", "-0.002in", "0mm", "abc", "mm", "", "inf", "NaN", "0.05ft",
        ] {
            assert!(s.parse::<Length>().is_err(), "{s}");
        }
        let e = "-0.05".parse::<Length>().unwrap_err();
        assert!(e.contains("positive") && e.contains("-0.05"), "{e}");
    }
}
