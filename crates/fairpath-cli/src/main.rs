//! `fairpath`: smooth CNC tool paths within a tolerance, and check the result.

use anyhow::Result;
use clap::{Parser, Subcommand};
use fairpath_cli::{check, pipeline, Format};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "fairpath",
    version,
    about = "Tolerance-bounded G2 smoothing of CNC tool paths"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Band {
    Full,
    Half,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum TimeModel {
    Full,
    Thesis,
}

impl TimeModel {
    fn jerk_on_curves(self) -> bool {
        self == TimeModel::Full
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum TextOrJson {
    Text,
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum TableFormat {
    Text,
    Json,
    Csv,
}

#[derive(Subcommand)]
enum Command {
    /// Replace the feed moves of a program with a G2 path within the tolerance.
    Smooth {
        /// Input G-code program.
        input: PathBuf,
        /// Output file (written only when the result verifies).
        #[arg(short, long)]
        output: PathBuf,
        /// Largest distance (mm) of the output feed path from the original.
        #[arg(short, long)]
        tolerance: f64,
        /// Smoothing method.
        #[arg(short, long, default_value = "auto")]
        method: String,
        /// Output format: G-code (dense G1) or JSON (exact curves, mm).
        #[arg(short, long, value_enum, default_value_t = Format::Gcode)]
        format: Format,
        /// Chord tolerance (mm) of the G1 output, coordinate rounding
        /// included (more decimals when needed); taken from the tolerance
        /// budget. Default: a tenth of the tolerance.
        #[arg(long)]
        chord: Option<f64>,
        /// bspline-corner: error target when a transition must shrink:
        /// `full` uses the whole band (e = epsilon, the default: lower peak
        /// curvature), `half` is the paper's e* = delta / 2.
        #[arg(long, value_enum, default_value_t = Band::Full)]
        band: Band,
        /// bspline-corner: overlap-avoidance ratio lambda in [0, 1) (paper eq. 8).
        #[arg(long, default_value_t = 0.0)]
        lambda: f64,
        /// Print the summary as JSON.
        #[arg(long)]
        json_summary: bool,
    },
    /// Plan a jerk-limited feed along a program (G-code or JSON) and report
    /// the machining time.
    Simulate {
        program: PathBuf,
        /// Machine file (TOML: max_feed [mm/min], acc, normal_acc, jerk,
        /// period, chord_error, axis_feed, axis_acc).
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
        /// Run every feed move at the machine's maximum feed.
        #[arg(long)]
        override_feed: bool,
        /// Time model: `full` caps the speed on curves by the centripetal
        /// acceleration and the jerk (centripetal jerk, curvature change;
        /// the default), `thesis` by the centripetal acceleration only, as
        /// the thesis' simulation (seed 003, eq. 4-1).
        #[arg(long, value_enum)]
        time_model: Option<TimeModel>,
        /// Bounded look-ahead of N segments, as a real-time controller runs
        /// it (default: the whole run); also reports the full scan's time.
        #[arg(long)]
        lookahead: Option<usize>,
        /// Write the profile sampled every period as CSV (t,s,v,a,j,x,y,z).
        #[arg(long)]
        profile: Option<PathBuf>,
        /// Write one row per planned segment as CSV, with the constraint
        /// that limits it (s0,length,cap,constraint,v_in,v_out,time).
        #[arg(long)]
        segments: Option<PathBuf>,
        #[arg(long, value_enum, default_value_t = TextOrJson::Text)]
        format: TextOrJson,
    },
    /// Run every smoothing method (and the untouched program) on one program
    /// and print one table: deviation, joints, length, peak curvature,
    /// curvature variation energy, planned time and its ratio to the
    /// original, smoothing time. Exit status 3 if a method fails to verify.
    Compare {
        program: PathBuf,
        /// Largest distance (mm) of each method's path from the original.
        #[arg(short, long)]
        tolerance: f64,
        /// Machine file (TOML, as for `simulate`); default: the thesis machine.
        #[arg(long)]
        machine: Option<PathBuf>,
        /// Junction deviation for corners of G1 moves, mm (default 0.01).
        #[arg(long)]
        junction_deviation: Option<f64>,
        /// Methods to run, comma-separated (default: all).
        #[arg(long, value_delimiter = ',')]
        methods: Option<Vec<String>>,
        /// Run every feed move at the machine's maximum feed.
        #[arg(long)]
        override_feed: bool,
        /// Time model: `full` caps the speed on curves by the centripetal
        /// acceleration and the jerk (centripetal jerk, curvature change;
        /// the default), `thesis` by the centripetal acceleration only, as
        /// the thesis' simulation (seed 003, eq. 4-1).
        #[arg(long, value_enum)]
        time_model: Option<TimeModel>,
        #[arg(long, value_enum, default_value_t = TableFormat::Text)]
        format: TableFormat,
    },
    /// Verify a smoothed program (G-code or JSON) against its original.
    Check {
        original: PathBuf,
        smoothed: PathBuf,
        /// Largest allowed distance (mm) of the smoothed feed path from the original.
        #[arg(short, long)]
        tolerance: f64,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Smooth {
            input,
            output,
            tolerance,
            method,
            format,
            chord,
            band,
            lambda,
            json_summary,
        } => {
            let mut opts = pipeline::SmoothOptions::new(tolerance, chord, &method, format)?;
            if method == "bspline-corner" {
                opts.method = Box::new(fairpath::smooth::BsplineCorner {
                    options: fairpath::smooth::BsplineCornerOptions {
                        target: match band {
                            Band::Full => fairpath::smooth::ErrorTarget::FullBand,
                            Band::Half => fairpath::smooth::ErrorTarget::HalfBand,
                        },
                        lambda,
                        ..Default::default()
                    },
                });
            }
            let summary = pipeline::smooth_file(&input, &output, &opts)?;
            if json_summary {
                println!("{}", summary.json());
            } else {
                print!("{}", summary.text());
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Simulate {
            program,
            machine,
            max_feed,
            acc,
            jerk,
            period,
            junction_deviation,
            override_feed,
            time_model,
            lookahead,
            profile,
            segments,
            format,
        } => {
            let flags = fairpath_cli::simulate::MachineFlags {
                max_feed,
                acc,
                jerk,
                period,
                junction_deviation,
                jerk_on_curves: time_model.map(TimeModel::jerk_on_curves),
            };
            let m = fairpath_cli::simulate::machine(machine.as_deref(), flags)?;
            fairpath_cli::simulate::run(
                &program,
                &m,
                override_feed,
                lookahead,
                profile.as_deref(),
                segments.as_deref(),
                format == TextOrJson::Json,
            )?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Compare {
            program,
            tolerance,
            machine,
            junction_deviation,
            methods,
            override_feed,
            time_model,
            format,
        } => {
            use fairpath_cli::compare;
            let m = fairpath_cli::simulate::machine(
                machine.as_deref(),
                fairpath_cli::simulate::MachineFlags {
                    junction_deviation,
                    jerk_on_curves: time_model.map(TimeModel::jerk_on_curves),
                    ..Default::default()
                },
            )?;
            let methods = methods.unwrap_or_else(|| {
                fairpath::smooth::METHODS
                    .iter()
                    .map(|s| s.to_string())
                    .collect()
            });
            let rows = compare::compare(
                &program,
                &compare::CompareOptions {
                    tolerance,
                    machine: m,
                    methods,
                    override_feed,
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
            Ok(if rows.iter().all(|r| r.verified) {
                ExitCode::SUCCESS
            } else {
                ExitCode::from(3)
            })
        }
        Command::Check {
            original,
            smoothed,
            tolerance,
        } => check::run(&original, &smoothed, tolerance),
    }
}
