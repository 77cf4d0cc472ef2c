//! A progress line on standard error for jobs that take a while: a spinner,
//! the step under way and the time so far, redrawn ten times a second once
//! the job has run for [`DELAY`], and erased when the job ends; once a job
//! processed in parts has written its first part, a bar with the share of
//! the program's lines written, and the time left at that pace. Shown only
//! when standard error is a terminal (never in a pipe or a log file) and
//! not asked to be quiet.

use fairpath_gcode::pipeline::{LinesObserver, StepObserver};
use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How long a job runs before its progress is shown (a second: shorter
/// jobs finish before a reader would look).
pub const DELAY: Duration = Duration::from_secs(1);

/// Redraw period.
const TICK: Duration = Duration::from_millis(100);

const SPINNER: [char; 4] = ['|', '/', '-', '\\'];

/// What runs after each step of the library's job
/// ([`fairpath_gcode::smooth_parsed_with`]) ends.
pub fn next_step(done: &str) -> &'static str {
    match done {
        "read" => "smoothing",
        "smooth" => "verifying the curves",
        "verify curves" => "planning the input and the curves",
        "plan input and curves" => "writing the program, reading it back and checking it",
        "render" => "writing the program, reading it back and checking it",
        "render, write, check" | "write, check" => "planning the written program",
        _ => "saving",
    }
}

/// A running progress line (nothing is drawn when it is hidden).
pub struct Progress {
    step: Arc<Mutex<String>>,
    /// Lines of the program written, and in all, once known.
    lines: Arc<Mutex<Option<(usize, usize)>>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

/// Characters of the bar.
const BAR_WIDTH: usize = 24;

impl Progress {
    /// Starts with step `first`; hidden when `quiet` or when standard error
    /// is not a terminal. `FAIRPATH_PROGRESS_DELAY_MS` overrides [`DELAY`]
    /// (for tests).
    pub fn start(first: &str, quiet: bool) -> Progress {
        let step = Arc::new(Mutex::new(first.to_string()));
        let lines = Arc::new(Mutex::new(None));
        let stop = Arc::new(AtomicBool::new(false));
        let shown = !quiet && std::io::stderr().is_terminal();
        let delay = std::env::var("FAIRPATH_PROGRESS_DELAY_MS")
            .ok()
            .and_then(|v| v.parse().ok())
            .map_or(DELAY, Duration::from_millis);
        let thread = shown.then(|| {
            let (step, lines, stop) = (step.clone(), lines.clone(), stop.clone());
            std::thread::spawn(move || draw(&step, &lines, &stop, delay))
        });
        Progress {
            step,
            lines,
            stop,
            thread,
        }
    }

    /// Says that `step` is under way.
    pub fn set(&self, step: &str) {
        if let Ok(mut s) = self.step.lock() {
            *s = step.to_string();
        }
    }

    /// An observer for the library's clock: each step that ends moves the
    /// line to the next, with `prefix` before it (e.g. the method's name).
    pub fn observer(&self, prefix: &str) -> StepObserver {
        let step = self.step.clone();
        let prefix = prefix.to_string();
        Arc::new(move |done: &'static str| {
            if let Ok(mut s) = step.lock() {
                *s = format!("{prefix}{}", next_step(done));
            }
        })
    }

    /// An observer of the lines a job in parts has written: the bar.
    pub fn lines_observer(&self) -> LinesObserver {
        let lines = self.lines.clone();
        Arc::new(move |done: usize, total: usize| {
            if let Ok(mut l) = lines.lock() {
                *l = Some((done, total));
            }
        })
    }

    /// Stops and erases the line.
    pub fn finish(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

/// The bar and what follows it for `done` of `total` lines after
/// `elapsed`: `[#########...............]  37% of 10000 lines, about 12 s
/// left`.
pub fn bar(done: usize, total: usize, elapsed: Duration) -> String {
    let f = if total > 0 {
        (done as f64 / total as f64).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let filled = (f * BAR_WIDTH as f64).round() as usize;
    let left = if f > 0.0 {
        let s = elapsed.as_secs_f64() * (1.0 - f) / f;
        format!(", about {s:.0} s left")
    } else {
        String::new()
    };
    format!(
        "[{}{}] {:>3.0}% of {total} lines{left}",
        "#".repeat(filled),
        ".".repeat(BAR_WIDTH - filled),
        100.0 * f
    )
}

fn draw(
    step: &Mutex<String>,
    lines: &Mutex<Option<(usize, usize)>>,
    stop: &AtomicBool,
    delay: Duration,
) {
    let started = Instant::now();
    let mut drawn = false;
    let mut k = 0;
    let mut first = true;
    while !stop.load(Ordering::SeqCst) {
        if !first {
            std::thread::sleep(TICK);
        }
        first = false;
        let elapsed = started.elapsed();
        if elapsed < delay || stop.load(Ordering::SeqCst) {
            continue;
        }
        let text = step.lock().map(|s| s.clone()).unwrap_or_default();
        let written = lines.lock().ok().and_then(|l| *l);
        let mut err = std::io::stderr().lock();
        let spinner = SPINNER[k % SPINNER.len()];
        let secs = elapsed.as_secs_f64();
        let _ = match written {
            Some((done, total)) => write!(
                err,
                "\r\x1b[2K{spinner} {} ({secs:.1} s)",
                bar(done, total, elapsed)
            ),
            None => write!(err, "\r\x1b[2K{spinner} {text} ({secs:.1} s)"),
        };
        let _ = err.flush();
        drawn = true;
        k += 1;
    }
    if drawn {
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r\x1b[2K");
        let _ = err.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::bar;
    use std::time::Duration;

    #[test]
    fn the_bar_fills_with_the_lines_written_and_says_the_time_left() {
        let b = bar(250, 1000, Duration::from_secs(10));
        assert_eq!(
            b,
            "[######..................]  25% of 1000 lines, about 30 s left"
        );
        assert!(bar(0, 1000, Duration::from_secs(1)).starts_with("[....."));
        assert!(bar(1000, 1000, Duration::from_secs(7)).contains("100% of 1000 lines, about 0 s"));
        // A total of nothing (no lines) is no division by zero.
        assert!(bar(0, 0, Duration::ZERO).contains("0% of 0 lines"));
    }
}
