//! Progress of a sweep on stderr: an `indicatif` bar over the cases on a terminal, otherwise plain
//! lines.

use std::time::Instant;

use super::{CaseRow, CaseStatus};

/// Progress of the whole sweep on stderr: a bar on a terminal, otherwise a line per finished case
/// (every tenth of the cases for more than 100) and every failure.
pub(super) struct SweepProgress {
    bar: Option<indicatif::ProgressBar>,
    lines: bool,
    total: usize,
    done: usize,
    failed: usize,
    start: Instant,
}

impl SweepProgress {
    pub(super) fn new(total: usize, skipped: usize, quiet: bool) -> Self {
        use std::io::IsTerminal;
        let terminal = !quiet && std::io::stderr().is_terminal();
        let bar = terminal.then(|| {
            let bar = indicatif::ProgressBar::with_draw_target(
                Some(total as u64),
                indicatif::ProgressDrawTarget::stderr_with_hz(10),
            );
            let style = indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{wide_bar}] {pos}/{len} cases  {msg}  about {eta} left",
            )
            .expect("valid progress template")
            .progress_chars("=> ");
            bar.set_style(style);
            bar.set_position(skipped as u64);
            bar
        });
        if !quiet && skipped > 0 {
            eprintln!("sweep: {skipped} of {total} cases finished before (kept)");
        }
        Self {
            bar,
            lines: !quiet && !terminal,
            total,
            done: skipped,
            failed: 0,
            start: Instant::now(),
        }
    }

    pub(super) fn case_done(&mut self, k: usize, row: &CaseRow) {
        if !row.status.is_finished() {
            return;
        }
        self.done += 1;
        let failed = matches!(row.status, CaseStatus::Failed(_));
        self.failed += usize::from(failed);
        let seconds = row.metrics.wall_time_s.unwrap_or(0.0);
        let line = match &row.status {
            CaseStatus::Failed(m) => format!("case {k} failed after {seconds:.2} s: {m}"),
            _ => format!("case {k} ok in {seconds:.2} s"),
        };
        if let Some(bar) = &self.bar {
            if failed {
                bar.println(&line);
            }
            bar.set_message(format!("{} failed", self.failed));
            bar.set_position(self.done as u64);
        } else if self.lines {
            let tenth = self.total <= 100 || (self.done * 10 / self.total) != ((self.done - 1) * 10 / self.total);
            if failed || tenth {
                eprintln!(
                    "[{}/{} cases, {:.1} s] {line}",
                    self.done,
                    self.total,
                    self.start.elapsed().as_secs_f64()
                );
            }
        }
    }

    pub(super) fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish();
        }
    }
}
