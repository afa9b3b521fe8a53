//! The progress of a long command on the terminal: what it is doing, done/total, the time
//! elapsed and an estimate of the rest, on stderr. A command shows it while it runs
//! ([`show`]); the executor counts each job list's jobs ([`stage`]) and a long run counts its
//! steps ([`StepProgress`], an observer). It is hidden when stderr is not a terminal or the
//! `CI` environment variable is set, and nothing is drawn when no command shows it (a library
//! caller, a test in process). Display only: nothing computed depends on it.
//!
//! Stages nest (a command's list of references, each reference's steps): the innermost is
//! drawn, with the stage it is part of named before it, and the outer one is drawn again when
//! the inner ends.

use std::io::IsTerminal;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::harness::files::error::Error;
use crate::harness::run::{Integration, Observer};

/// Whether progress is drawn: stderr is a terminal and `CI` is not set.
fn visible() -> bool {
    std::io::stderr().is_terminal() && std::env::var_os("CI").is_none()
}

/// The progress shown, when a command shows it on a terminal.
static SHOWN: Mutex<Option<Display>> = Mutex::new(None);

/// What is drawn: the command's name, its stages (outermost first) and the bar of the innermost.
struct Display {
    command: String,
    stages: Vec<StageState>,
    bar: Option<ProgressBar>,
    next_id: u64,
}

/// One stage: what it counts and how far it is.
struct StageState {
    id: u64,
    what: String,
    unit: &'static str,
    total: u64,
    done: u64,
    started: Instant,
}

fn shown() -> MutexGuard<'static, Option<Display>> {
    SHOWN
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Display {
    /// Replaces the bar by one of the innermost stage (none when no stage is open).
    fn redraw(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        let Some(top) = self.stages.last() else {
            return;
        };
        let outer: Vec<String> = self.stages[..self.stages.len() - 1]
            .iter()
            .map(|s| format!("{} {}/{}", s.what, s.done, s.total))
            .collect();
        let what = match outer.is_empty() {
            true => top.what.clone(),
            false => format!("{} › {}", outer.join(" › "), top.what),
        };
        let template = format!(
            "{{prefix}}: {{msg}} [{{bar:30}}] {{pos}}/{{len}} {}, {{elapsed}} elapsed, about {{eta}} left",
            top.unit
        );
        let bar = ProgressBar::with_draw_target(Some(top.total), ProgressDrawTarget::stderr())
            .with_style(ProgressStyle::with_template(&template).expect("a valid template"))
            .with_prefix(self.command.clone())
            .with_message(what)
            .with_elapsed(top.started.elapsed())
            .with_position(top.done);
        // Drawn now, whether or not the ticker's thread runs before the stage ends.
        bar.tick();
        bar.enable_steady_tick(Duration::from_millis(500));
        self.bar = Some(bar);
    }
}

/// The progress of a command, shown on stderr while this lives (when [`visible`]).
pub struct Shown(());

impl Drop for Shown {
    fn drop(&mut self) {
        if let Some(mut display) = shown().take() {
            display.stages.clear();
            display.redraw();
        }
    }
}

/// Shows the progress of `command` (its name, as the user typed it) until the returned guard
/// is dropped; nothing when stderr is not a terminal or `CI` is set.
pub fn show(command: &str) -> Shown {
    if visible() {
        *shown() = Some(Display {
            command: command.to_string(),
            stages: Vec::new(),
            bar: None,
            next_id: 1,
        });
    }
    Shown(())
}

/// Prints `line` on stderr, above the progress bar when one is drawn.
pub fn note(line: &str) {
    suspended(|| eprintln!("{line}"));
}

/// Runs `f` (which prints a result, say) with the progress bar, when one is drawn, cleared
/// first and drawn again after.
pub fn suspended<R>(f: impl FnOnce() -> R) -> R {
    let bar = shown().as_ref().and_then(|d| d.bar.clone());
    match bar {
        Some(bar) => bar.suspend(f),
        None => f(),
    }
}

/// A stage of the shown progress: `total` units counted as they are done, drawn until dropped.
pub struct Stage {
    /// Its id in the display; `None` when no progress is shown.
    id: Option<u64>,
}

/// Opens a stage `what` of `total` `unit`s (`runs`, `steps`) in the progress shown, if any.
pub fn stage(what: &str, total: usize, unit: &'static str) -> Stage {
    let mut guard = shown();
    let Some(display) = guard.as_mut() else {
        return Stage { id: None };
    };
    let id = display.next_id;
    display.next_id += 1;
    display.stages.push(StageState {
        id,
        what: what.to_string(),
        unit,
        total: total as u64,
        done: 0,
        started: Instant::now(),
    });
    display.redraw();
    Stage { id: Some(id) }
}

impl Stage {
    /// `n` more units done (from any thread).
    pub fn advance(&self, n: u64) {
        self.update(|done| done + n);
    }

    /// `done` units done in all.
    fn set_done(&self, done: u64) {
        self.update(|_| done);
    }

    fn update(&self, done: impl FnOnce(u64) -> u64) {
        let Some(id) = self.id else {
            return;
        };
        let mut guard = shown();
        let Some(display) = guard.as_mut() else {
            return;
        };
        let innermost = display.stages.last().map(|s| s.id);
        if let Some(s) = display.stages.iter_mut().find(|s| s.id == id) {
            s.done = done(s.done).min(s.total);
            if innermost == Some(id) {
                if let Some(bar) = &display.bar {
                    bar.set_position(s.done);
                }
            }
        }
    }
}

impl Drop for Stage {
    fn drop(&mut self) {
        let Some(id) = self.id else {
            return;
        };
        if let Some(display) = shown().as_mut() {
            display.stages.retain(|s| s.id != id);
            display.redraw();
        }
    }
}

/// An observer that counts a run's steps in a stage of the progress shown: `what`, to the
/// horizon `horizon` (the number of steps is known from the first state's time step). It
/// counts every step and draws at most a few hundred times.
pub struct StepProgress {
    what: String,
    horizon: f64,
    stage: Option<(Stage, usize)>,
}

impl StepProgress {
    /// The steps of the run named `what`, to `horizon`.
    pub fn new(what: &str, horizon: f64) -> Self {
        Self {
            what: what.to_string(),
            horizon,
            stage: None,
        }
    }
}

impl Observer for StepProgress {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let step = state.step_index();
        let (stage, every) = self.stage.get_or_insert_with(|| {
            let steps = (self.horizon / state.dt()).round().max(1.0) as usize;
            (stage(&self.what, steps, "steps"), (steps / 400).max(1))
        });
        if step % *every == 0 {
            stage.set_done(step as u64);
        }
        Ok(())
    }
}
