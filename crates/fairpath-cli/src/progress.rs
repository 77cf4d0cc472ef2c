//! A progress line on standard error for jobs that take a while: a spinner,
//! the step under way and the time so far, redrawn ten times a second once
//! the job has run for [`DELAY`], and erased when the job ends. Shown only
//! when standard error is a terminal (never in a pipe or a log file) and
//! not asked to be quiet.

use fairpath_gcode::pipeline::StepObserver;
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
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Progress {
    /// Starts with step `first`; hidden when `quiet` or when standard error
    /// is not a terminal. `FAIRPATH_PROGRESS_DELAY_MS` overrides [`DELAY`]
    /// (for tests).
    pub fn start(first: &str, quiet: bool) -> Progress {
        let step = Arc::new(Mutex::new(first.to_string()));
        let stop = Arc::new(AtomicBool::new(false));
        let shown = !quiet && std::io::stderr().is_terminal();
        let delay = std::env::var("FAIRPATH_PROGRESS_DELAY_MS")
            .ok()
            .and_then(|v| v.parse().ok())
            .map_or(DELAY, Duration::from_millis);
        let thread = shown.then(|| {
            let (step, stop) = (step.clone(), stop.clone());
            std::thread::spawn(move || draw(&step, &stop, delay))
        });
        Progress { step, stop, thread }
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

fn draw(step: &Mutex<String>, stop: &AtomicBool, delay: Duration) {
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
        let mut err = std::io::stderr().lock();
        let _ = write!(
            err,
            "\r\x1b[2K{} {text} ({:.1} s)",
            SPINNER[k % SPINNER.len()],
            elapsed.as_secs_f64()
        );
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
