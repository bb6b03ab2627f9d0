//! Progress of a run on stderr.
//!
//! - On a terminal ([`ProgressMode::Bar`]): an `indicatif` bar with steps done, simulated time,
//!   Newton iterations so far and the estimated time left, redrawn at most 20 times a second.
//! - When stderr is not a terminal (a log file, CI; [`ProgressMode::Lines`]): one plain line each
//!   time another 10 % of the steps is done, and a summary at the end.
//! - Nothing at all with [`ProgressMode::Quiet`].
//!
//! [`ProgressMode::detect`] picks the mode from a `--quiet` flag and whether stderr is a terminal.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pendulum_fem_core::simulation::{Simulation, StepRecord};
use pendulum_fem_core::Error;
use pendulum_fem_run::driver::{Attach, RunObserver};
use pendulum_fem_run::StepPlan;

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressMode {
    /// An animated bar (for terminals).
    Bar,
    /// A plain line every 10 % (for logs).
    Lines,
    /// Nothing.
    Quiet,
}

impl ProgressMode {
    /// `Quiet` if `quiet`, else `Bar` when stderr is a terminal and `Lines` otherwise.
    pub fn detect(quiet: bool) -> Self {
        if quiet {
            Self::Quiet
        } else if std::io::stderr().is_terminal() {
            Self::Bar
        } else {
            Self::Lines
        }
    }
}

/// Reports the progress of a time-stepping run.
pub struct Progress {
    total: usize,
    start: Instant,
    bar: Option<ProgressBar>,
    lines: Option<Box<dyn Write + Send>>,
    next_decile: usize,
    last: (usize, f64, usize),
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Progress")
            .field("total", &self.total)
            .field("last", &self.last)
            .finish_non_exhaustive()
    }
}

impl Progress {
    /// A reporter for `total_steps` steps on stderr.
    pub fn new(total_steps: usize, mode: ProgressMode) -> Self {
        match mode {
            ProgressMode::Bar => {
                let bar =
                    ProgressBar::with_draw_target(Some(total_steps as u64), ProgressDrawTarget::stderr_with_hz(20));
                let style = ProgressStyle::with_template(
                    "{elapsed_precise} [{wide_bar}] {pos}/{len} steps  {msg}  about {eta} left",
                )
                .expect("valid progress template")
                .progress_chars("=> ");
                bar.set_style(style);
                Self::build(total_steps, Some(bar), None)
            }
            ProgressMode::Lines => Self::build(total_steps, None, Some(Box::new(std::io::stderr()))),
            ProgressMode::Quiet => Self::build(total_steps, None, None),
        }
    }

    /// A reporter writing plain lines (as [`ProgressMode::Lines`]) to `out`.
    pub fn with_writer(total_steps: usize, out: Box<dyn Write + Send>) -> Self {
        Self::build(total_steps, None, Some(out))
    }

    fn build(total: usize, bar: Option<ProgressBar>, lines: Option<Box<dyn Write + Send>>) -> Self {
        Self {
            total,
            start: Instant::now(),
            bar,
            lines,
            next_decile: 1,
            last: (0, 0.0, 0),
        }
    }

    /// Reports that `step` steps are done, at simulated time `t` \[s\], with `newton_its_total`
    /// Newton iterations so far.
    pub fn update(&mut self, step: usize, t: f64, newton_its_total: usize) {
        self.last = (step, t, newton_its_total);
        if let Some(bar) = &self.bar {
            bar.set_message(format!("t = {t:.4} s, {newton_its_total} Newton its"));
            bar.set_position(step as u64);
        }
        if self.lines.is_some() && self.total > 0 {
            let decile = step * 10 / self.total;
            if decile >= self.next_decile {
                self.next_decile = decile + 1;
                let line = self.line(step, t, newton_its_total);
                self.write_line(&line);
            }
        }
    }

    /// Ends the report (the bar is left showing the final state; lines mode prints a summary).
    pub fn finish(mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish();
        }
        if self.lines.is_some() {
            let (step, t, its) = self.last;
            let line = format!(
                "done: {step} steps to t = {t:.4} s, {its} Newton iterations, {:.1} s",
                self.start.elapsed().as_secs_f64()
            );
            self.write_line(&line);
        }
    }

    fn line(&self, step: usize, t: f64, its: usize) -> String {
        let elapsed = self.start.elapsed();
        let left = if step > 0 {
            Duration::from_secs_f64(elapsed.as_secs_f64() * (self.total.saturating_sub(step)) as f64 / step as f64)
        } else {
            Duration::ZERO
        };
        format!(
            "step {step}/{} ({}%), t = {t:.4} s, {its} Newton iterations, {:.1} s elapsed, about {:.1} s left",
            self.total,
            step * 100 / self.total.max(1),
            elapsed.as_secs_f64(),
            left.as_secs_f64()
        )
    }

    fn write_line(&mut self, line: &str) {
        if let Some(out) = &mut self.lines {
            let _ = writeln!(out, "{line}");
            let _ = out.flush();
        }
    }
}

/// The progress of a run on stderr, as an observer of the run driver (none with `quiet`).
pub fn attach(quiet: bool) -> Attach {
    Attach::new(move |start| {
        let mode = if quiet {
            ProgressMode::Quiet
        } else {
            ProgressMode::detect(false)
        };
        let progress = Progress::new(StepPlan::of(&start.config.time).steps(), mode);
        Ok(Some(Box::new(progress) as Box<dyn RunObserver>))
    })
}

impl RunObserver for Progress {
    fn record(&mut self, sim: &mut Simulation, record: &StepRecord, _resumed: bool) -> Result<(), Error> {
        self.update(record.step, record.time, sim.total_iterations);
        Ok(())
    }

    fn finish(self: Box<Self>, _sim: &mut Simulation, _last: &StepRecord) -> Result<Vec<std::path::PathBuf>, Error> {
        Progress::finish(*self);
        Ok(Vec::new())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    #[derive(Clone, Default)]
    struct Shared(Arc<Mutex<Vec<u8>>>);
    impl Write for Shared {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn lines_mode_prints_every_ten_percent_and_a_summary() {
        let buf = Shared::default();
        let mut p = Progress::with_writer(200, Box::new(buf.clone()));
        for s in 1..=200 {
            p.update(s, s as f64 * 0.01, 3 * s);
        }
        p.finish();
        let text = String::from_utf8(buf.0.lock().unwrap().clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 11, "{text}");
        assert!(lines[0].starts_with("step 20/200 (10%)"), "{}", lines[0]);
        assert!(lines[10].starts_with("done: 200 steps"), "{}", lines[10]);
    }

    #[test]
    fn bar_mode_builds_its_template_and_shows_the_steps_time_and_iterations_until_finished() {
        // the template is parsed when the bar is made (an invalid one panics there)
        let mut p = Progress::new(10, ProgressMode::Bar);
        let bar = p.bar.clone().expect("bar mode draws a bar");
        assert!(p.lines.is_none(), "no plain lines beside the bar");
        assert_eq!(bar.length(), Some(10));
        for s in 1..=10 {
            p.update(s, s as f64 * 0.1, 2 * s);
            assert_eq!(bar.position(), s as u64);
        }
        assert_eq!(bar.message(), "t = 1.0000 s, 20 Newton its");
        assert!(!bar.is_finished());
        p.finish();
        assert!(bar.is_finished(), "finish() ends the bar");
    }

    #[test]
    fn quiet_mode_has_neither_a_bar_nor_a_writer_so_it_prints_nothing() {
        assert_eq!(ProgressMode::detect(true), ProgressMode::Quiet);
        let mut p = Progress::new(10, ProgressMode::Quiet);
        assert!(p.bar.is_none() && p.lines.is_none());
        p.update(5, 0.5, 10);
        assert_eq!(p.last, (5, 0.5, 10));
        p.finish();
    }
}
