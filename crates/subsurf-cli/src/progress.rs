//! A progress bar on stderr that appears only when a job takes more than about a second.
//!
//! The bar starts hidden; a timer thread switches it to stderr after [`DELAY`] unless the
//! job has finished by then. It is never shown with `--quiet` or when stderr is not a
//! terminal. Warnings go through [`Progress::warn`] so they do not tear the bar.

use std::borrow::Cow;
use std::io::IsTerminal;
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::thread::{self, JoinHandle};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a job runs before its bar is drawn.
const DELAY: Duration = Duration::from_secs(1);
/// The bar's template; `{unit}` is replaced by what it counts.
const TEMPLATE: &str = "{spinner} {msg} [{bar:30}] {pos}/{len} {unit} ({elapsed})";

/// The progress of one job (read, refine `levels` times, write).
pub struct Progress {
    bar: ProgressBar,
    /// Dropping the sender tells the timer thread that the job is over.
    timer: Option<(Sender<()>, JoinHandle<()>)>,
}

impl Progress {
    /// A bar for `levels` refinement levels, shown after [`DELAY`] unless `quiet` is set
    /// or stderr is not a terminal.
    pub fn new(levels: u32, quiet: bool) -> Self {
        Self::counting(u64::from(levels), "levels", quiet)
    }

    /// A bar for `len` steps of what `unit` names ("poses"), shown as [`new`](Self::new)'s.
    pub fn counting(len: u64, unit: &str, quiet: bool) -> Self {
        let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
        let style = ProgressStyle::with_template(&TEMPLATE.replace("{unit}", unit))
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
        bar.set_style(style);
        let timer = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let (tx, rx) = mpsc::channel::<()>();
            let shown = bar.clone();
            let handle = thread::spawn(move || {
                if let Err(RecvTimeoutError::Timeout) = rx.recv_timeout(DELAY) {
                    shown.set_draw_target(ProgressDrawTarget::stderr());
                    shown.enable_steady_tick(Duration::from_millis(100));
                }
            });
            (tx, handle)
        });
        Self { bar, timer }
    }

    /// What the job is doing now ("reading x.obj", ...).
    pub fn set_message(&self, msg: impl Into<Cow<'static, str>>) {
        self.bar.set_message(msg);
    }

    /// The callback of `subdivide_with_progress`: `done` of `levels` levels are refined.
    pub fn level_done(&self, done: u32, levels: u32) {
        self.bar.set_length(u64::from(levels));
        self.bar.set_position(u64::from(done));
    }

    /// One more step done (of a [`counting`](Self::counting) bar).
    pub fn step_done(&self) {
        self.bar.inc(1);
    }

    /// Prints `warning: {msg}` on stderr, clearing the bar while doing so.
    pub fn warn(&self, msg: &str) {
        self.bar
            .suspend(|| crate::output::eprint_line(&format!("warning: {msg}")));
    }

    /// Prints `note: {msg}` on stderr (information, not a problem), clearing the bar.
    pub fn note(&self, msg: &str) {
        self.bar
            .suspend(|| crate::output::eprint_line(&format!("note: {msg}")));
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some((tx, handle)) = self.timer.take() {
            drop(tx);
            // The timer thread only touches the bar; it cannot panic in a way worth reporting.
            let _ = handle.join();
        }
        self.bar.disable_steady_tick();
        self.bar.finish_and_clear();
    }
}
