//! G and M codes classified by modal group (LinuxCNC's groups).

use super::{err, FeedMode};
use crate::cycles;
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::{LexedLine, Word};
use crate::program::{MotionMode, Units};
use fairpath::controller::Plane;

/// Group-0 (non-modal) codes that matter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum NonModal {
    Dwell,
    G10,
    G28,
    G28_1,
    G30,
    G30_1,
    G52,
    G53,
    G92,
    G92_1,
    G92_2,
    G92_3,
}

impl NonModal {
    pub(super) fn uses_axes(self) -> bool {
        matches!(
            self,
            NonModal::G10 | NonModal::G28 | NonModal::G30 | NonModal::G52 | NonModal::G92
        )
    }
}

/// A classified G code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum G {
    Motion(MotionMode),
    Plane(Plane),
    Units(Units),
    Incremental(bool),
    ArcIncremental(bool),
    FeedMode(FeedMode),
    CutterComp(bool),
    ToolLength(bool),
    CoordSystem(u16),
    PathControl(u16),
    /// G98 (false) or G99 (true: retract to R).
    ReturnMode(bool),
    SpindleMode(u16),
    LatheRadius,
    Cancel(u16),
    NonModal(NonModal),
    /// G5.3: closes a G5.2 block (LinuxCNC modal group 0).
    SplineEnd,
}

impl G {
    pub(super) fn group(self) -> &'static str {
        match self {
            G::Motion(_) => "motion",
            G::Plane(_) => "plane",
            G::Units(_) => "units",
            G::Incremental(_) => "distance mode",
            G::ArcIncremental(_) => "arc distance mode",
            G::FeedMode(_) => "feed mode",
            G::CutterComp(_) => "cutter compensation",
            G::ToolLength(_) => "tool length offset",
            G::CoordSystem(_) => "coordinate system",
            G::PathControl(_) => "path control",
            G::ReturnMode(_) => "canned cycle return",
            G::SpindleMode(_) => "spindle speed mode",
            G::LatheRadius => "lathe diameter mode",
            G::Cancel(10) => "polar coordinates",
            G::Cancel(_) => "rotation",
            G::NonModal(_) | G::SplineEnd => "non-modal",
        }
    }
}

/// Classifies `G<code/10>`.
fn classify_g(code: u16, text: &str) -> Result<G, ErrorKind> {
    let unsupported = |what: &'static str| Err(ErrorKind::Unsupported(what));
    Ok(match code {
        0 => G::Motion(MotionMode::Rapid),
        10 => G::Motion(MotionMode::Linear),
        20 => G::Motion(MotionMode::ArcCw),
        30 => G::Motion(MotionMode::ArcCcw),
        40 => G::NonModal(NonModal::Dwell),
        50 => G::Motion(MotionMode::CubicSpline),
        51 => G::Motion(MotionMode::QuadSpline),
        52 => G::Motion(MotionMode::Nurbs),
        53 => G::SplineEnd,
        62 => G::Motion(MotionMode::NurbsG6),
        60 | 61 | 63 => return unsupported("LinuxCNC master's G6, G6.1 and G6.3"),
        70 => return unsupported("lathe diameter mode G7"),
        80 => G::LatheRadius,
        100 => G::NonModal(NonModal::G10),
        150 => G::Cancel(10),
        160 => return unsupported("polar coordinates G16"),
        170 => G::Plane(Plane::Xy),
        180 => G::Plane(Plane::Zx),
        190 => G::Plane(Plane::Yz),
        171 | 181 | 191 => return unsupported("UVW planes (G17.1, G18.1, G19.1)"),
        200 => G::Units(Units::Inch),
        210 => G::Units(Units::Mm),
        280 => G::NonModal(NonModal::G28),
        281 => G::NonModal(NonModal::G28_1),
        300 => G::NonModal(NonModal::G30),
        301 => G::NonModal(NonModal::G30_1),
        330 => G::Motion(MotionMode::Thread),
        331 => G::Motion(MotionMode::RigidTap),
        382..=385 | 310 => G::Motion(MotionMode::Probe(code)),
        400 => G::CutterComp(false),
        410 | 411 | 420 | 421 => G::CutterComp(true),
        430..=432 => G::ToolLength(true),
        490 => G::ToolLength(false),
        520 => G::NonModal(NonModal::G52),
        530 => G::NonModal(NonModal::G53),
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => G::CoordSystem(code),
        610 | 611 | 640 => G::PathControl(code),
        680 => return unsupported("coordinate rotation G68"),
        690 => G::Cancel(69),
        510 => return unsupported("scaling G51"),
        700 | 710 | 720 => return unsupported("G70/G71/G72 (lathe cycles or legacy units)"),
        c if cycles::is_cycle(c) => G::Motion(MotionMode::Cycle(c)),
        760 => return unsupported("the G76 threading cycle"),
        870 | 880 => {
            return unsupported("canned cycles G87 (back boring) and G88 (manual retract)")
        }
        800 => G::Motion(MotionMode::None),
        900 => G::Incremental(false),
        910 => G::Incremental(true),
        901 => G::ArcIncremental(false),
        911 => G::ArcIncremental(true),
        930 => G::FeedMode(FeedMode::InverseTime),
        940 => G::FeedMode(FeedMode::PerMinute),
        950 => G::FeedMode(FeedMode::PerRev),
        920 => G::NonModal(NonModal::G92),
        921 => G::NonModal(NonModal::G92_1),
        922 => G::NonModal(NonModal::G92_2),
        923 => G::NonModal(NonModal::G92_3),
        960 | 970 => G::SpindleMode(code),
        980 | 990 => G::ReturnMode(code == 990),
        _ => return Err(ErrorKind::UnknownGCode(text.to_string())),
    })
}

/// M-code modal group (LinuxCNC), or 0 for codes without a group.
fn m_group(code: i64) -> u8 {
    match code {
        0 | 1 | 2 | 30 | 60 => 4,
        6 | 61 => 6,
        3..=5 => 7,
        7..=9 => 8,
        48..=53 => 9,
        _ => 0,
    }
}

/// The G and M codes of one line, in the order written, at most one per
/// modal group.
pub(super) struct LineCodes<'a> {
    pub(super) gs: Vec<(G, &'a Word)>,
    pub(super) ms: Vec<(i64, &'a Word)>,
}

impl<'a> LineCodes<'a> {
    /// Classifies the G and M words of line `ln`: unknown G codes and two
    /// codes of one modal group are errors.
    pub(super) fn of(lx: &'a LexedLine, ln: usize) -> Result<LineCodes<'a>, GcodeError> {
        let mut gs: Vec<(G, &Word)> = Vec::new();
        let mut ms: Vec<(i64, &Word)> = Vec::new();
        for w in &lx.words {
            match w.letter {
                'G' => {
                    let tenths = w.value * 10.0;
                    let code = tenths.round();
                    if (tenths - code).abs() > 1e-6 || !(0.0..=9999.0).contains(&code) {
                        return Err(err(
                            ln,
                            w.column,
                            ErrorKind::UnknownGCode(w.text.to_string()),
                        ));
                    }
                    let g = classify_g(code as u16, &w.text).map_err(|k| err(ln, w.column, k))?;
                    // G80 beside another motion code (`G0 G80`, common in
                    // headers): the other code wins, as on Fanuc controls.
                    let cancel = G::Motion(MotionMode::None);
                    if let Some(k) = gs.iter().position(|(o, _)| o.group() == g.group()) {
                        if gs[k].0 == cancel && g.group() == "motion" {
                            gs[k] = (g, w);
                            continue;
                        } else if g == cancel {
                            continue;
                        }
                        return Err(err(ln, w.column, ErrorKind::ConflictingGCodes(g.group())));
                    }
                    gs.push((g, w));
                }
                'M' => {
                    if w.value.fract() != 0.0 || !(0.0..=1.0e6).contains(&w.value) {
                        return Err(err(ln, w.column, ErrorKind::BadValue('M')));
                    }
                    let code = w.value as i64;
                    let grp = m_group(code);
                    if grp != 0 && ms.iter().any(|(c, _)| m_group(*c) == grp) {
                        return Err(err(ln, w.column, ErrorKind::ConflictingMCodes));
                    }
                    ms.push((code, w));
                }
                _ => {}
            }
        }
        Ok(LineCodes { gs, ms })
    }

    /// The motion code (group 1).
    pub(super) fn motion(&self) -> Option<(MotionMode, &'a Word)> {
        self.gs.iter().find_map(|(g, w)| match g {
            G::Motion(m) => Some((*m, *w)),
            _ => None,
        })
    }

    /// The group-0 code.
    pub(super) fn nonmodal(&self) -> Option<(NonModal, &'a Word)> {
        self.gs.iter().find_map(|(g, w)| match g {
            G::NonModal(n) => Some((*n, *w)),
            _ => None,
        })
    }

    /// The G5.3 that closes a G5.2 block.
    pub(super) fn spline_end(&self) -> Option<&'a Word> {
        self.gs
            .iter()
            .find(|(g, _)| *g == G::SplineEnd)
            .map(|(_, w)| *w)
    }

    /// M2 or M30: the program ends after this line.
    pub(super) fn ends_program(&self) -> bool {
        self.ms.iter().any(|(c, _)| *c == 2 || *c == 30)
    }
}
