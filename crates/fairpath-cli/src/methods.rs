//! The smoothing methods as command-line values: the names are the
//! library's (`fairpath::choose::METHODS`, `Method::named`), each shown in
//! `--help` with one line on what it does.

use clap::builder::{PossibleValue, PossibleValuesParser};
use fairpath::choose::{Method, METHODS};

/// One line on what `method` does, for `--help`. A match on the library's
/// enum: a method added there does not compile here until it has its line.
pub fn help(method: &Method) -> &'static str {
    match method {
        Method::ArcFit(_) => {
            "the fewest arcs and lines within the tolerance (for LinuxCNC's block-capped planners)"
        }
        Method::Auto(_) => {
            "per run and section, the candidate that plans fastest on the machine (the default)"
        }
        Method::BsplineCorner(_) => "cubic B-spline transitions at the corners (seed 000)",
        Method::BsplineFit(_) => "least-squares B-splines through dense runs (seed 002)",
        Method::Ctm(_) => "Bezier corner transitions, constant coefficient (seed 001)",
        Method::Fair(_) => "B-splines faired inside the tolerance tube (seed 003)",
        Method::Lotm(_) => "Bezier corner transitions, optimised coefficient (seed 001)",
        Method::None => "every run as it is, through the same checks (the baseline)",
    }
}

/// The values `--method` takes: every name of the library's registry with
/// its help.
pub fn parser() -> PossibleValuesParser {
    PossibleValuesParser::new(METHODS.iter().map(|&name| {
        let value = PossibleValue::new(name);
        match Method::named(name) {
            Some(m) => value.help(help(&m)),
            None => value,
        }
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_has_its_line() {
        for name in METHODS {
            let m = Method::named(name).unwrap();
            assert!(!help(&m).is_empty(), "{name}");
        }
    }
}
