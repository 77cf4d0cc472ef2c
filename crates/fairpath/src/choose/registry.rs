//! Every method, typed with its options, and by the name the command line
//! uses. Options are validated once, at the front door ([`Method::validate`]),
//! with errors naming the method, the option and the value.

use super::auto::Auto;
use super::auto_options::AutoOptions;
use super::judged_fair::JudgedFair;
use super::objective::{fair_on, Objective, PlannedTime};
use crate::smooth::{
    ArcFit, ArcFitOptions, BsplineCorner, BsplineCornerOptions, BsplineFit, BsplineFitOptions, Ctm,
    CtmOptions, Fair, FairOptions, Lotm, LotmOptions, NoSmoothing, OptionError, Smoother,
};
use alloc::boxed::Box;
use alloc::sync::Arc;

/// A smoothing method with its options.
#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    /// `arc-fit`: the fewest arcs and lines within the tolerance.
    ArcFit(ArcFitOptions),
    /// `auto`: per run and section, the candidate its objective ranks first.
    Auto(AutoOptions),
    /// `bspline-corner`: cubic B-spline corner transitions (seed 000).
    BsplineCorner(BsplineCornerOptions),
    /// `bspline-fit`: least-squares B-spline fits of dense runs (seed 002).
    BsplineFit(BsplineFitOptions),
    /// `ctm`: Bezier corner transitions, constant coefficient (seed 001).
    Ctm(CtmOptions),
    /// `fair`: B-splines faired inside the tolerance tube (seed 003); runs
    /// of lines fitted first (seed 002).
    Fair(FairOptions),
    /// `lotm`: Bezier corner transitions, optimised coefficient (seed 001).
    Lotm(LotmOptions),
    /// `none`: every run as it is (the baseline; expands a parameterised
    /// program through the verified pipeline).
    None,
}

/// Names of the methods, as the command line spells them.
pub const METHODS: &[&str] = &[
    "arc-fit",
    "auto",
    "bspline-corner",
    "bspline-fit",
    "ctm",
    "fair",
    "lotm",
    "none",
];

impl Method {
    /// The method called `name`, with its default options.
    pub fn named(name: &str) -> Option<Method> {
        Some(match name {
            "arc-fit" => Method::ArcFit(ArcFitOptions::default()),
            "auto" => Method::Auto(AutoOptions::default()),
            "bspline-corner" => Method::BsplineCorner(BsplineCornerOptions::default()),
            "bspline-fit" => Method::BsplineFit(BsplineFitOptions::default()),
            "ctm" => Method::Ctm(CtmOptions::default()),
            "fair" => Method::Fair(FairOptions::default()),
            "lotm" => Method::Lotm(LotmOptions::default()),
            "none" => Method::None,
            _ => return None,
        })
    }

    /// The method called `name` with the options `options` deserializes
    /// to (fields left out keep their defaults; unknown fields are errors).
    #[cfg(feature = "serde")]
    pub fn named_with<'de, D: serde::Deserializer<'de>>(
        name: &str,
        options: D,
    ) -> Result<Option<Method>, D::Error> {
        use serde::Deserialize;
        Ok(Some(match name {
            "arc-fit" => Method::ArcFit(ArcFitOptions::deserialize(options)?),
            "auto" => Method::Auto(AutoOptions::deserialize(options)?),
            "bspline-corner" => Method::BsplineCorner(BsplineCornerOptions::deserialize(options)?),
            "bspline-fit" => Method::BsplineFit(BsplineFitOptions::deserialize(options)?),
            "ctm" => Method::Ctm(CtmOptions::deserialize(options)?),
            "fair" => Method::Fair(FairOptions::deserialize(options)?),
            "lotm" => Method::Lotm(LotmOptions::deserialize(options)?),
            "none" => {
                <serde::de::IgnoredAny as Deserialize>::deserialize(options)?;
                Method::None
            }
            _ => return Ok(None),
        }))
    }

    /// The command-line name.
    pub fn name(&self) -> &'static str {
        match self {
            Method::ArcFit(_) => "arc-fit",
            Method::Auto(_) => "auto",
            Method::BsplineCorner(_) => "bspline-corner",
            Method::BsplineFit(_) => "bspline-fit",
            Method::Ctm(_) => "ctm",
            Method::Fair(_) => "fair",
            Method::Lotm(_) => "lotm",
            Method::None => "none",
        }
    }

    /// Checks every option's range.
    pub fn validate(&self) -> Result<(), OptionError> {
        match self {
            Method::ArcFit(o) => o.validate(),
            Method::Auto(o) => o.validate(),
            Method::BsplineCorner(o) => o.validate(),
            Method::BsplineFit(o) => o.validate(),
            Method::Ctm(o) => o.validate(),
            Method::Fair(o) => o.validate(),
            Method::Lotm(o) => o.validate(),
            Method::None => Ok(()),
        }
    }

    /// The smoother, `auto` ranking its candidates by `objective` (the
    /// other methods have no use for it).
    pub fn smoother(&self, objective: Arc<dyn Objective>) -> Box<dyn Smoother> {
        match *self {
            Method::ArcFit(options) => Box::new(ArcFit { options }),
            Method::Auto(options) => Box::new(Auto::new(options, objective)),
            Method::BsplineCorner(options) => Box::new(BsplineCorner { options }),
            Method::BsplineFit(options) => Box::new(BsplineFit { options }),
            Method::Ctm(options) => Box::new(Ctm { options }),
            Method::Fair(options) => Box::new(JudgedFair {
                fair: Fair {
                    options: fair_on(options, objective.as_ref()),
                },
                objective,
            }),
            Method::Lotm(options) => Box::new(Lotm { options }),
            Method::None => Box::new(NoSmoothing),
        }
    }
}

/// The method called `name` on the command line, with default options
/// (`auto` ranking by [`PlannedTime::default`]: use [`method`] to give it
/// the user's machine).
pub fn by_name(name: &str) -> Option<Box<dyn Smoother>> {
    method(name, Arc::new(PlannedTime::default()))
}

/// The method called `name` with default options, `auto` ranking its
/// candidates by `objective`.
pub fn method(name: &str, objective: Arc<dyn Objective>) -> Option<Box<dyn Smoother>> {
    Method::named(name).map(|m| m.smoother(objective))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_is_a_method_with_valid_defaults() {
        for &name in METHODS {
            let m = Method::named(name).unwrap();
            assert_eq!(m.name(), name);
            assert_eq!(m.validate(), Ok(()));
            assert_eq!(by_name(name).unwrap().name(), name);
        }
        assert!(Method::named("none-such").is_none());
    }

    #[test]
    fn a_bad_option_names_method_option_and_value() {
        let m = Method::BsplineCorner(BsplineCornerOptions {
            lambda: 1.5,
            ..BsplineCornerOptions::default()
        });
        let e = m.validate().unwrap_err();
        assert_eq!(
            (e.method, e.option, e.value.as_str()),
            ("bspline-corner", "lambda", "1.5")
        );
        let text = alloc::format!("{e}");
        assert!(text.contains("bspline-corner") && text.contains("lambda") && text.contains("1.5"));
    }
}
