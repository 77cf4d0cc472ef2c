//! The options of the G-code writer: how arcs and NURBS are written,
//! decimals, the chord tolerance, G64 blending.

/// How NURBS pieces are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NurbsBlocks {
    /// Fanuc-style G6.2 blocks (3D) of degrees up to `max_degree`
    /// (Fanuc: 3, orders 2 to 4; see `pipeline::written::g6_2_max_degree`).
    G6_2Fanuc { max_degree: usize },
    /// LinuxCNC master's G6.2 blocks (in the plane the curve lies in).
    G6_2Linuxcnc,
    /// LinuxCNC G5.2/G5.3 blocks (in the plane the curve lies in).
    G5_2,
}

/// How arcs are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArcWords {
    /// Centre offsets I, J, K (absolute centre after G90.1).
    Ijk,
    /// Radius R (negative for more than half a circle); IJK for arcs of
    /// nearly half a circle, whose centre R leaves ill-defined, and for
    /// full circles.
    R,
}

/// Options of [`write_gcode`](super::write_gcode).
#[derive(Clone, Debug, PartialEq)]
pub struct GcodeWriteOptions {
    /// Largest distance (mm) between a smoothed curve and what is written
    /// for it, as the written text reads back: G1 chords of curves written
    /// as lines, and the rounding of written coordinates (see
    /// [`write_decimals`](super::write_decimals); at most
    /// [`ROUNDING_SHARE`](super::ROUNDING_SHARE) of it for any piece).
    pub chord_mm: f64,
    /// Fewest decimals of coordinates written in mm programs (4: 0.05 um
    /// rounding); more when `chord_mm` needs them
    /// ([`write_decimals`](super::write_decimals)).
    pub decimals_mm: usize,
    /// Fewest decimals of coordinates written in inch programs (5: 0.127
    /// um); more when `chord_mm` needs them.
    pub decimals_inch: usize,
    /// Write a `(smoothed by fairpath)` comment as the first line (after a
    /// leading `%` line).
    pub header: bool,
    /// Write arcs as G2/G3 in this form; `None`: as G1 chords.
    pub arcs: Option<ArcWords>,
    /// Write NURBS pieces as these blocks; `None`: as G1 chords.
    pub nurbs: Option<NurbsBlocks>,
    /// Always write a decimal point in numbers (`X5.`), whatever the input
    /// does: the controller requires it (Fanuc-family controls without
    /// decimal-point input read `X5` as 5 um). Without it the input's own
    /// style decides ([`NumberStyle::of`](super::NumberStyle::of): a
    /// program that always writes the point gets it in every number written
    /// for it, and leading zeros follow its habit).
    pub decimal_point: bool,
    /// The share of the tolerance (mm) the controller's blending may spend
    /// (LinuxCNC's `G64 P`). `G64 P<blend> Q0` (in the run's units, P
    /// rounded down) is written before each run that does not already run
    /// under it when [`GcodeWriteOptions::g64_always`] is set, or when the
    /// input's path control in force at the run blends beyond it
    /// ([`PathControl::exceeds`](super::PathControl::exceeds): a `G64` with
    /// a larger P, `G64 P0` or a bare `G64`; the input used LinuxCNC's
    /// syntax, so the output may too). After the run the input's own
    /// path-control command in force there is written back as the input
    /// wrote it (if the input set one: otherwise ours stays in force). `Q0`
    /// turns off LinuxCNC's merging of short blocks (`G64 P` alone sets Q =
    /// P, and arcs and lines within Q of a line are replaced by it). `None`:
    /// path control is left as the input has it.
    pub g64_blend_mm: Option<f64>,
    /// Write `G64 P<g64_blend_mm> Q0` before every run, even where the
    /// input set no path control or a tighter one (the controller is
    /// LinuxCNC, whose default blends without a tolerance).
    pub g64_always: bool,
    /// Largest distance (mm) rounding may move a written point, whatever
    /// the chord tolerance: the direction and curvature of a short piece
    /// come from its written coordinates, and a rounding error `rho` on a
    /// piece of length `L` tilts it by about `rho / L`. A jerk-limited
    /// controller passing pieces one interpolation period `Ts` long at
    /// jerk `J` needs `rho` of about `J Ts^3 / 4` (5 nm for 20000 mm/s^3 and
    /// 1 ms: 6 decimals in mm; with 4, arcs of a few um written for a tight
    /// corner of butterfly-80 re-read with kinks of 0.05 rad and planned
    /// far slower than the curves; measurements: docs/tuning.md,
    /// `GcodeWriteOptions::resolution_mm`). `None`: the chord alone decides.
    pub resolution_mm: Option<f64>,
    /// The controller's interpolation period `Ts` (s). A line of a
    /// rendered run ([`super::RunOutput::Rendered`]) shorter than `k = `
    /// [`super::FINE_PERIODS`] periods of travel at its planned speed `v`
    /// gets more decimals than the run's (up to 12): its rounding is scaled
    /// by `(L / (k v Ts))^2` for a line `L` long. Rounding by `rho` bends the
    /// blend circles at a short line's ends by up to `4 rho / L^2` of
    /// curvature; so scaled, a short line is bent, against the curvature
    /// step its speed allows, no more than a line `k` periods long with
    /// the run's decimals ([`GcodeWriteOptions::resolution_mm`] is made
    /// for lines one period long). Where a curve tightens to a crawl, the
    /// renderer keeps lines a micrometre long well into the faster stretch
    /// around it (equal lines until the spacing may change): those need it.
    /// An arc counts as a line the shorter of its chord and radius long:
    /// rounding turns its tangents by about `rho / r`, and by about
    /// `2 rho / chord` where the reader takes its rounded ends for a
    /// spiral. `None`: every piece gets the run's decimals.
    pub period_s: Option<f64>,
}

impl Default for GcodeWriteOptions {
    fn default() -> Self {
        GcodeWriteOptions {
            chord_mm: 0.001,
            decimals_mm: 4,
            decimals_inch: 5,
            header: true,
            arcs: None,
            nurbs: None,
            decimal_point: false,
            g64_blend_mm: None,
            g64_always: false,
            resolution_mm: None,
            period_s: None,
        }
    }
}
