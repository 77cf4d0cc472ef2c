//! How the input writes its numbers, so that the numbers fairpath writes
//! for it read the same way on the same control.
//!
//! Fanuc-family controls without decimal-point input read `Z5` as 5 um
//! (the least input increment) and `Z5.` as 5 mm: a program written for
//! one with a decimal point in every dimension word must get one in every
//! number written for it.

use crate::lexer::Word;
use crate::program::Program;

/// Letters of dimension words: lengths and angles, whose integers a control
/// without decimal-point input reads in least input increments.
const DIMENSION_LETTERS: &str = "XYZABCUVWIJKR";

/// How numbers are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NumberStyle {
    /// Every number carries a decimal point (`X5.`, `X10.0`).
    pub decimal_point: bool,
    /// Numbers of magnitude below 1 have a zero before the point (`X0.5`);
    /// without it they are written `X.5`, `X-.5`.
    pub leading_zero: bool,
}

impl Default for NumberStyle {
    /// No forced decimal point, leading zeros: what fairpath writes for a
    /// program that shows no habit.
    fn default() -> Self {
        NumberStyle {
            decimal_point: false,
            leading_zero: true,
        }
    }
}

/// The counts [`NumberStyle::of`] decides by, gathered line by line (a
/// program read as a stream gives its interpreted lines' words here).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StyleCount {
    /// Whole numbers in dimension words written with a decimal point.
    with_point: usize,
    /// Nonzero whole numbers in dimension words written without one.
    integer: usize,
    /// Numbers below 1 written `0.5`, and written `.5`.
    zero_first: usize,
    point_first: usize,
}

impl StyleCount {
    /// Counts the words of one interpreted line.
    pub fn add(&mut self, words: &[Word]) {
        for w in words {
            let dimension = DIMENSION_LETTERS.contains(w.letter);
            if !(dimension || w.letter == 'F') {
                continue;
            }
            let digits = w.text.trim_start_matches(['+', '-']);
            if dimension && w.value.fract() == 0.0 {
                if digits.contains('.') {
                    self.with_point += 1;
                } else if w.value != 0.0 {
                    self.integer += 1;
                }
            }
            if digits.starts_with('.') && digits.len() > 1 {
                self.point_first += 1;
            } else if digits.starts_with("0.") && digits.len() > 2 {
                self.zero_first += 1;
            }
        }
    }

    /// The style these counts show ([`NumberStyle::of`]).
    pub fn style(&self) -> NumberStyle {
        NumberStyle {
            decimal_point: self.with_point > 0 && self.integer == 0,
            leading_zero: self.point_first <= self.zero_first,
        }
    }
}

impl NumberStyle {
    /// The style of `program`'s own words (of the lines it interprets):
    ///
    /// * decimal point: on when the program writes a whole number in at
    ///   least one dimension word (X Y Z A B C U V W I J K R) with a decimal
    ///   point (`Z5.`, `X10.0`, `Y0.`: the habit shows only on whole
    ///   numbers) and no nonzero whole number without one: a single `X5`
    ///   shows that the control reads integers as whole units (`X0` proves
    ///   nothing: it is zero either way). Feeds are not counted: Fanuc
    ///   programs write `F1000` beside `X5.` (F is not a dimension).
    /// * leading zero: what the majority of the program's numbers of
    ///   magnitude below 1 (dimension words and F) do; on a tie, or without
    ///   such numbers, on.
    pub fn of(program: &Program) -> NumberStyle {
        let mut count = StyleCount::default();
        for line in program.lines().iter().filter(|l| l.interpreted) {
            count.add(&line.words);
        }
        count.style()
    }

    /// `t` (a number as `fmt_fixed` writes it: no trailing point,
    /// a leading zero below 1) in this style.
    pub fn apply(&self, mut t: String) -> String {
        if self.decimal_point && !t.contains('.') {
            t.push('.');
        }
        if !self.leading_zero {
            let sign = usize::from(t.starts_with(['-', '+']));
            let rest = &t[sign..];
            if rest.starts_with("0.") && rest.len() > 2 {
                t.remove(sign);
            }
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::NumberStyle;
    use crate::parse;

    fn style(text: &str) -> NumberStyle {
        NumberStyle::of(&parse(text.as_bytes()).unwrap())
    }

    #[test]
    fn the_input_decides_the_decimal_point_and_the_leading_zero() {
        let s = style("G21 G90\nG0 X0 Y0\nG1 X5. Y.5 F1000\nG1 Z-.25\nM30\n");
        assert_eq!(
            s,
            NumberStyle {
                decimal_point: true,
                leading_zero: false
            }
        );
        assert_eq!(s.apply("5".into()), "5.");
        assert_eq!(s.apply("0.5".into()), ".5");
        assert_eq!(s.apply("-0.25".into()), "-.25");
        assert_eq!(s.apply("0".into()), "0.");
        assert_eq!(s.apply("10.05".into()), "10.05");
        // One nonzero integer without a point: integers are whole units.
        let s = style("G21 G90\nG0 X0 Y0\nG1 X5. Y2 F1000\nG1 Z0.5\nM30\n");
        assert_eq!(s, NumberStyle::default());
        assert_eq!(s.apply("5".into()), "5");
        // Nothing to go by (no whole number with a point): the default.
        assert_eq!(
            style("G21\nG0 X0\nG1 X1 F100\nM30\n"),
            NumberStyle::default()
        );
        assert_eq!(
            style("G21\nG0 X0\nG1 X0.5 Y1.25 F100\nM30\n"),
            NumberStyle::default()
        );
    }
}
