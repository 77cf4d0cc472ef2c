//! `fairpath`: smooth CNC tool paths within a tolerance, and check the result.

use anyhow::Result;
use clap::{Parser, Subcommand};
use fairpath_cli::length::Length;
use fairpath_cli::usage::{self, usage, EXIT_CODES_HELP};
use fairpath_cli::{check, output, read, smooth, Controller, Format};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "fairpath",
    version,
    about = "Curvature-continuous smoothing of CNC tool paths within a tolerance",
    after_help = EXIT_CODES_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// bspline-corner's error target when a transition must shrink.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Band {
    /// The whole band, e = epsilon: lower peak curvature (the default).
    Full,
    /// The paper's e* = delta / 2.
    Half,
}

/// What caps the speed on curves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum TimeModel {
    /// Centripetal acceleration and jerk (centripetal jerk, curvature
    /// change): the default.
    Full,
    /// Centripetal acceleration only, as the thesis' simulation (seed 003,
    /// eq. 4-1).
    Thesis,
}

impl TimeModel {
    fn jerk_on_curves(self) -> bool {
        self == TimeModel::Full
    }
}

/// The speed every run starts and ends at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum RunEndsArg {
    /// At rest (the default).
    Rest,
    /// At the speed cap there (the feed on a straight), as seed 003's
    /// simulation (section 4.5).
    Cap,
}

/// How a report is printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum TextOrJson {
    /// Lines for a person to read.
    Text,
    /// One JSON object, for scripts.
    Json,
}

/// How the table of `compare` is printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum TableFormat {
    /// Aligned columns.
    Text,
    /// An array of objects, the written programs under `written`.
    Json,
    /// A header row, then one row per method.
    Csv,
}

/// The help of `--tolerance` (smooth, compare, check).
const TOLERANCE_HELP: &str = "Largest distance of the output feed path from the original: \
a number with a unit (0.05mm, 0.002in) or a bare number in the program's units \
(inches in a G20 program, mm in a G21 one)";

/// The machine times are planned for.
#[derive(clap::Args, Clone, Debug)]
struct MachineArgs {
    /// Machine file (TOML: max_feed [mm/min], acc, normal_acc, jerk,
    /// period, chord_error, junction_deviation, axis_feed, axis_acc,
    /// jerk_on_curves, block_time).
    #[arg(long)]
    machine: Option<PathBuf>,
    /// Maximum feed, mm/min (default 24000).
    #[arg(long)]
    max_feed: Option<f64>,
    /// Acceleration, mm/s^2 (default 4000).
    #[arg(long)]
    acc: Option<f64>,
    /// Jerk, mm/s^3 (default 20000).
    #[arg(long)]
    jerk: Option<f64>,
    /// Interpolation period, s (default 0.001).
    #[arg(long)]
    period: Option<f64>,
    /// Junction deviation for corners of G1 moves, mm (default 0.01).
    #[arg(long)]
    junction_deviation: Option<f64>,
    /// Least time the control spends on a block, s (default 0: none; a
    /// control that takes one block per interpolation period has the
    /// period, one of 1,000 blocks a second 0.001).
    #[arg(long)]
    block_time: Option<f64>,
    /// Run every feed move at the machine's maximum feed.
    #[arg(long)]
    override_feed: bool,
    /// Time model: `full` caps the speed on curves by the centripetal
    /// acceleration and the jerk (centripetal jerk, curvature change;
    /// the default), `thesis` by the centripetal acceleration only, as
    /// the thesis' simulation (seed 003, eq. 4-1).
    #[arg(long, value_enum)]
    time_model: Option<TimeModel>,
}

impl MachineArgs {
    fn limits(&self) -> Result<fairpath::feed::limits::MachineLimits> {
        fairpath_cli::machine::machine(
            self.machine.as_deref(),
            fairpath_cli::machine::MachineFlags {
                max_feed: self.max_feed,
                acc: self.acc,
                jerk: self.jerk,
                period: self.period,
                junction_deviation: self.junction_deviation,
                block_time: self.block_time,
                jerk_on_curves: self.time_model.map(TimeModel::jerk_on_curves),
            },
        )
    }
}

#[derive(Subcommand)]
enum Command {
    /// Replace the feed moves of a program with a curvature-continuous path
    /// within the tolerance.
    #[command(after_help = EXIT_CODES_HELP, allow_negative_numbers = true)]
    Smooth {
        /// Input G-code program; - reads standard input.
        input: PathBuf,
        /// Output file (written only when the result verifies; it keeps the
        /// permissions of the file it replaces); - writes standard output
        /// (the summary then goes to standard error). Default: NAME.smoothed.EXT
        /// beside the input (NAME.smoothed.json for --format json), standard
        /// output when the input is standard input. The input itself,
        /// under any name, only with --in-place.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Replace the input program (atomically, keeping its permissions)
        /// with the result; -o may then be left out.
        #[arg(long)]
        in_place: bool,
        #[arg(short, long, help = TOLERANCE_HELP, value_name = "LENGTH", allow_hyphen_values = true)]
        tolerance: Length,
        /// Smoothing method (default: the controller's: arc-fit for
        /// linuxcnc, whose planners cap the speed per block; auto for the
        /// others).
        #[arg(short, long, value_parser = fairpath_cli::methods::parser())]
        method: Option<String>,
        /// The method's options from a TOML file: the fields of its options
        /// struct (e.g. for bspline-fit `fairness = 1e-4` and a
        /// `[sections]` table); fields left out keep their defaults, unknown
        /// fields and values out of range are errors.
        #[arg(long, value_name = "FILE.toml")]
        options: Option<PathBuf>,
        /// The controller the program is for: picks the default format and
        /// the dialect (LinuxCNC: G64 P<blend> Q0 around smoothed runs;
        /// Fanuc: a decimal point in every number). For every controller
        /// numbers follow the input's style (a decimal point in every
        /// number when the input always writes one, its leading zeros),
        /// and runs where the input's own G64 blends beyond the blending
        /// share get G64 P<blend> Q0, with the input's G64 after them.
        #[arg(long, value_enum, default_value_t = Controller::Generic)]
        controller: Controller,
        /// Output format (default: the controller's: arcs for generic and
        /// linuxcnc, g6.2 for fanuc; g6.2 for generic too when the program
        /// holds G6.2 NURBS).
        #[arg(short, long, value_enum)]
        format: Option<Format>,
        /// Share of the tolerance for writing the curves in the output
        /// format (chords, arcs, rounding; LinuxCNC's blending comes out of
        /// it too), with a unit or in the program's units as --tolerance.
        /// Default: a tenth of the tolerance; a fiftieth for g6.2, which
        /// writes the smoothed B-splines exactly.
        #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
        chord: Option<Length>,
        /// How much curvature step a joint of written pieces may take, as a
        /// share of what the planned speed passes without slowing down
        /// (`J Ts / v^2`): 0.5 (default) keeps the curves' speed; a run
        /// written as arcs or G1 is also rendered at half the share, and
        /// where that gains at a quarter, and gets the faster at every
        /// feed; larger writes fewer, longer arcs or lines
        /// that slow the machine at their joints; `inf` leaves only the
        /// tolerance.
        #[arg(long, default_value_t = fairpath::render::arcs::STEP_SHARE)]
        step_share: f64,
        #[command(flatten)]
        machine: MachineArgs,
        /// bspline-corner: error target when a transition must shrink:
        /// `full` uses the whole band (e = epsilon, the default: lower peak
        /// curvature), `half` is the paper's e* = delta / 2.
        /// [default: full]
        #[arg(long, value_enum)]
        band: Option<Band>,
        /// bspline-corner: overlap-avoidance ratio lambda in [0, 1) (paper eq. 8)
        /// [default: 0].
        #[arg(long)]
        lambda: Option<f64>,
        /// Cut runs of more than N lines into windows of about N lines, at
        /// the middle of lines of 1 mm or more, smoothed, written and
        /// checked one after the other: memory grows with a window, not
        /// with the run (a one-run raster of 3.7 MB: 38 MB with `none`,
        /// against 194 MB whole). Near each cut the path keeps the cut
        /// line straight; the times are the whole file's. Where fairpath
        /// writes its own G64 around the runs it rewrites (LinuxCNC, or a
        /// program whose G64 blends beyond the blending share), it goes
        /// before a cut run's first window and the program's after its
        /// last. 0: runs are not cut.
        #[arg(long, value_name = "N", default_value_t = fairpath_gcode::RunWindows::DEFAULT.lines as u32)]
        window_lines: u32,
        /// Print the summary as JSON.
        #[arg(long)]
        json_summary: bool,
        /// No progress line (it is shown on a terminal's standard error
        /// when the job takes more than a second).
        #[arg(short, long)]
        quiet: bool,
    },
    /// Plan a jerk-limited feed along a program (G-code or JSON) and report
    /// the machining time.
    #[command(after_help = EXIT_CODES_HELP, allow_negative_numbers = true)]
    Simulate {
        /// G-code program or fairpath JSON path; - reads standard input.
        program: PathBuf,
        #[command(flatten)]
        machine: MachineArgs,
        /// Bounded look-ahead of N segments, as a real-time controller runs
        /// it (default: the whole run); also reports the full scan's time.
        #[arg(long)]
        lookahead: Option<usize>,
        /// The speed every run starts and ends at: `rest` (the default), or
        /// `cap`, the speed cap there (the feed on a straight): with
        /// `--time-model thesis --override-feed` and the thesis' machine,
        /// the simulation of seed 003 (section 4.5), which starts and ends
        /// its paths at the maximum feed.
        #[arg(long, value_enum, default_value = "rest")]
        run_ends: RunEndsArg,
        /// Write the profile sampled every period as CSV (t,s,v,a,j,x,y,z);
        /// `-` writes it to standard output (the summary then goes to
        /// standard error).
        #[arg(long)]
        profile: Option<PathBuf>,
        /// Write one row per planned segment as CSV, with the constraint
        /// that limits it (s0,length,cap,constraint,v_in,v_out,time); `-`
        /// as for --profile.
        #[arg(long)]
        segments: Option<PathBuf>,
        #[arg(long, value_enum, default_value_t = TextOrJson::Text)]
        format: TextOrJson,
    },
    /// Write the planned, jerk-limited motion of a program as one position
    /// per servo period (X Y Z in mm, one line per period), as LinuxCNC's
    /// halstreamer plays it; smoothed first with --tolerance.
    #[command(after_help = EXIT_CODES_HELP, allow_negative_numbers = true)]
    Stream {
        /// G-code program, or a fairpath JSON path (streamed as it is).
        program: PathBuf,
        /// Output stream file.
        #[arg(short, long)]
        output: PathBuf,
        /// Smooth the program first (default method) within this distance
        /// of its path (a unit, 0.05mm or 0.002in, or a bare number in the
        /// program's units); without it the program's own moves are
        /// streamed (every corner then passed nearly at rest).
        #[arg(short, long, value_name = "LENGTH", allow_hyphen_values = true)]
        tolerance: Option<Length>,
        #[command(flatten)]
        machine: MachineArgs,
        /// Also stream the moves before the first feed move and after the
        /// last (by default the stream starts where the first feed move
        /// starts and ends where the last one ends).
        #[arg(long)]
        lead_rapids: bool,
    },
    /// Run every smoothing method (and the untouched program) on one program
    /// and print one table: deviation, joints, length, peak curvature,
    /// curvature variation energy, planned time and its ratio to the
    /// original, smoothing time. Exit status 3 if a method fails to verify.
    #[command(after_help = EXIT_CODES_HELP, allow_negative_numbers = true)]
    Compare {
        /// G-code program; - reads standard input.
        program: PathBuf,
        #[arg(short, long, help = TOLERANCE_HELP, value_name = "LENGTH", allow_hyphen_values = true)]
        tolerance: Length,
        #[command(flatten)]
        machine: MachineArgs,
        /// Methods to run, comma-separated (default: all but none).
        #[arg(long, value_delimiter = ',', value_parser = fairpath_cli::methods::parser())]
        methods: Option<Vec<String>>,
        /// The controller whose dialect the written programs use.
        #[arg(long, value_enum, default_value_t = Controller::Generic)]
        controller: Controller,
        /// Formats to write and plan for each method, comma-separated
        /// (default: the format `smooth` writes by default: the
        /// controller's, g6.2 on generic for a program that holds G6.2).
        #[arg(long, value_enum, value_delimiter = ',')]
        formats: Option<Vec<Format>>,
        #[arg(long, value_enum, default_value_t = TableFormat::Text)]
        format: TableFormat,
    },
    /// Write one self-contained HTML page with the path and its tolerance
    /// band before and after (zoomable), curvature along the path, the
    /// planned feed against time and arc length (coloured by what limits
    /// it), and the summary of each method: what a machinist looks at to
    /// decide.
    #[command(after_help = EXIT_CODES_HELP, allow_negative_numbers = true)]
    Report {
        /// The program; - reads standard input.
        program: PathBuf,
        #[arg(short, long, help = TOLERANCE_HELP, value_name = "LENGTH", allow_hyphen_values = true)]
        tolerance: Length,
        #[command(flatten)]
        machine: MachineArgs,
        /// Methods to show, comma-separated (default: the controller's
        /// default method).
        #[arg(long, value_delimiter = ',', value_parser = fairpath_cli::methods::parser())]
        methods: Option<Vec<String>>,
        /// The controller whose dialect the written programs use.
        #[arg(long, value_enum, default_value_t = Controller::Generic)]
        controller: Controller,
        /// Output format of the written programs (default: the format
        /// `smooth` writes by default: the controller's, g6.2 on generic
        /// for a program that holds G6.2).
        #[arg(short, long, value_enum)]
        format: Option<Format>,
        /// The HTML file to write (- : standard output).
        #[arg(short, long)]
        output: PathBuf,
        /// No progress line (it is shown on a terminal's standard error
        /// when the job takes more than a second).
        #[arg(short, long)]
        quiet: bool,
    },
    /// Verify a smoothed program (G-code or JSON) against its original and
    /// say where it is farthest from it. Exit status 3 if it is not within
    /// the tolerance.
    #[command(after_help = EXIT_CODES_HELP, allow_negative_numbers = true)]
    Check {
        /// The original G-code program; - reads standard input.
        original: PathBuf,
        /// The smoothed program (G-code or fairpath JSON); - reads standard
        /// input (one of the two at most).
        smoothed: PathBuf,
        /// Largest allowed distance of the smoothed feed path from the
        /// original: a number with a unit (0.05mm, 0.002in) or a bare
        /// number in the original's units (inches in a G20 program).
        #[arg(short, long, value_name = "LENGTH", allow_hyphen_values = true)]
        tolerance: Length,
        #[arg(long, value_enum, default_value_t = TextOrJson::Text)]
        format: TextOrJson,
    },
}

/// The method with the options of `--options FILE.toml` or of the flags
/// `--band`/`--lambda` (bspline-corner's), validated once here; `None`
/// when none of them is given (the method's defaults). Options that do
/// not apply to the method are errors, not ignored.
fn method_with_options(
    method: &str,
    file: Option<&std::path::Path>,
    band: Option<Band>,
    lambda: Option<f64>,
) -> anyhow::Result<Option<fairpath::choose::Method>> {
    use anyhow::Context;
    use fairpath::choose::Method;
    let flags = band.is_some() || lambda.is_some();
    if flags && method != "bspline-corner" {
        return Err(usage(format!(
            "--band and --lambda are options of bspline-corner, not of method {method}: \
             leave them out or pass --method bspline-corner"
        )));
    }
    if flags && file.is_some() {
        return Err(usage(
            "give bspline-corner's options either in --options or as --band/--lambda, not both",
        ));
    }
    let m = if let Some(path) = file {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("--options: reading {}", path.display()))?;
        Method::named_with(method, toml::Deserializer::new(&text))
            .map_err(|e| {
                usage(format!(
                    "--options {}: method {method}: {e}",
                    path.display()
                ))
            })?
            .ok_or_else(|| usage(format!("unknown method {method:?}")))?
    } else if flags {
        Method::BsplineCorner(fairpath::smooth::BsplineCornerOptions {
            target: match band.unwrap_or(Band::Full) {
                Band::Full => fairpath::smooth::ErrorTarget::FullBand,
                Band::Half => fairpath::smooth::ErrorTarget::HalfBand,
            },
            lambda: lambda.unwrap_or(0.0),
            ..Default::default()
        })
    } else {
        return Ok(None);
    };
    m.validate().map_err(usage)?;
    Ok(Some(m))
}

/// Arenas glibc's malloc may use. By default it gives threads arenas of
/// their own, up to eight per core, and memory freed in one stays there:
/// a long job whose steps run on fresh threads on all cores (each part of
/// a program, `fairpath_gcode::smooth_in_parts`) then holds its peak in
/// every arena it touched. With two, the process holds little more than
/// what is live, at the same speed (measurements: docs/tuning.md,
/// `MALLOC_ARENAS`; `docs/performance.md`).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MALLOC_ARENAS: i32 = 2;

fn main() -> ExitCode {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets a tuning parameter of glibc's allocator;
    // called first thing, before any thread is started.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, MALLOC_ARENAS);
    }
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            if usage::is_usage(&e) {
                eprintln!("\nFor more information, try '--help'.");
            }
            ExitCode::from(usage::exit_status(&e))
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Smooth {
            input,
            output,
            in_place,
            tolerance,
            method,
            options,
            controller,
            format,
            chord,
            step_share,
            machine,
            band,
            lambda,
            window_lines,
            json_summary,
            quiet,
        } => {
            let json = format.unwrap_or_else(|| controller.default_format()) == Format::Json;
            let output = output::smooth_output(&input, output, in_place, json)?;
            let started = std::time::Instant::now();
            let mut progress = fairpath_cli::progress::Progress::start("reading", quiet);
            let bytes = read::read_bytes(&input)?;
            let prepared = smooth::prepare(
                &input,
                &bytes,
                format.unwrap_or_else(|| controller.default_format()),
            )?;
            let units = prepared.units();
            let method = method.unwrap_or_else(|| controller.default_method().to_string());
            let format =
                format.unwrap_or_else(|| controller.default_format_for(prepared.holds_nurbs()));
            let mut opts = smooth::options(
                tolerance.mm(units),
                chord.map(|c| c.mm(units)),
                &method,
                Some(format),
                controller,
            )?;
            opts.set_step_share(step_share)
                .map_err(smooth::option_error)?;
            let windows = (window_lines > 0).then_some(fairpath_gcode::RunWindows {
                lines: window_lines as usize,
                ..fairpath_gcode::RunWindows::DEFAULT
            });
            opts.set_run_windows(windows)
                .map_err(smooth::option_error)?;
            let limits = machine.limits()?;
            opts.set_machine(limits, machine.override_feed)
                .map_err(smooth::option_error)?;
            if let Some(m) = method_with_options(&method, options.as_deref(), band, lambda)? {
                opts.set_method_options(m);
            }
            let summary = smooth::smooth_prepared(
                &input,
                &bytes,
                prepared,
                started,
                &output,
                &opts,
                Some(&mut progress),
            )?;
            let text = if json_summary {
                summary.json() + "\n"
            } else {
                summary.text()
            };
            // With the program on standard output the summary goes to
            // standard error.
            if read::is_stdio(&output) {
                eprint!("{text}");
            } else {
                print!("{text}");
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Simulate {
            program,
            machine,
            lookahead,
            run_ends,
            profile,
            segments,
            format,
        } => {
            for (what, out) in [("--profile", &profile), ("--segments", &segments)] {
                if let Some(out) = out {
                    output::refuse_overwrite(&program, out, what, None)?;
                }
            }
            if let (Some(p), Some(s)) = (&profile, &segments) {
                if p == s || output::same_file(p, s) {
                    return Err(usage(format!(
                        "--profile and --segments name the same file {}: give two files",
                        p.display()
                    )));
                }
            }
            let m = machine.limits()?;
            let ends = match run_ends {
                RunEndsArg::Rest => fairpath::feed::plan::RunEnds::AtRest,
                RunEndsArg::Cap => fairpath::feed::plan::RunEnds::AtCap,
            };
            fairpath_cli::simulate_command::run(
                &program,
                &m,
                machine.override_feed,
                ends,
                lookahead,
                profile.as_deref(),
                segments.as_deref(),
                format == TextOrJson::Json,
            )?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Stream {
            program,
            output,
            tolerance,
            machine,
            lead_rapids,
        } => {
            let m = machine.limits()?;
            let axis_jerk = fairpath_cli::stream::axis_jerk(machine.machine.as_deref(), &m)?;
            fairpath_cli::stream::run(&fairpath_cli::stream::StreamArgs {
                program: &program,
                output: &output,
                tolerance,
                machine: m,
                axis_jerk,
                override_feed: machine.override_feed,
                lead_rapids,
            })?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Compare {
            program,
            tolerance,
            machine,
            methods,
            controller,
            formats,
            format,
        } => {
            use fairpath_cli::compare;
            let m = machine.limits()?;
            let parsed = read::read_program(&program)?;
            let tolerance = tolerance.mm(parsed.units());
            // Every method but `none`: the `original` row is the untouched
            // program already.
            let methods = methods.unwrap_or_else(|| {
                fairpath::choose::METHODS
                    .iter()
                    .filter(|&&s| s != "none")
                    .map(|s| s.to_string())
                    .collect()
            });
            let rows = compare::compare_program(
                &program,
                &parsed,
                &compare::CompareOptions {
                    tolerance,
                    machine: m,
                    methods,
                    override_feed: machine.override_feed,
                    formats: formats.unwrap_or_else(|| {
                        let nurbs = fairpath_gcode::ProgramFacts::of(&parsed).nurbs;
                        vec![controller.default_format_for(nurbs)]
                    }),
                    controller,
                },
            )?;
            print!(
                "{}",
                match format {
                    TableFormat::Text => compare::text(&rows),
                    TableFormat::Json => compare::json(&rows) + "\n",
                    TableFormat::Csv => compare::csv(&rows),
                }
            );
            Ok(
                if rows
                    .iter()
                    .all(|r| r.verified && r.written.iter().all(|w| w.verified))
                {
                    ExitCode::SUCCESS
                } else {
                    ExitCode::from(usage::EXIT_NOT_VERIFIED)
                },
            )
        }
        Command::Report {
            program,
            tolerance,
            machine,
            methods,
            controller,
            format,
            output,
            quiet,
        } => {
            output::refuse_overwrite(&program, &output, "-o", None)?;
            let parsed = read::read_program(&program)?;
            let html = fairpath_cli::report::report_program(
                &program,
                &parsed,
                &fairpath_cli::report::ReportOptions {
                    tolerance: tolerance.mm(parsed.units()),
                    methods: methods
                        .unwrap_or_else(|| vec![controller.default_method().to_string()]),
                    machine: machine.limits()?,
                    override_feed: machine.override_feed,
                    controller,
                    format,
                    quiet,
                },
            )?;
            output::write_output(&output, html.as_bytes())?;
            eprintln!(
                "fairpath report: {} -> {}",
                program.display(),
                output.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Check {
            original,
            smoothed,
            tolerance,
            format,
        } => check::run(&original, &smoothed, tolerance, format == TextOrJson::Json),
    }
}
