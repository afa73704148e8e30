//! The progress line on standard error: models done of the total, failed, rate and time
//! left; redrawn in place on a terminal, one line per item otherwise (a log file).

use std::io::{IsTerminal as _, Write as _};
use std::time::Instant;

pub(crate) struct Progress {
    /// Items of this shard.
    total: usize,
    /// Skipped as already done.
    skipped: usize,
    /// Finished in this run (ok or not).
    finished: usize,
    failed: usize,
    started: Instant,
    terminal: bool,
    /// A progress line is on the screen without its newline.
    drawn: bool,
}

/// Seconds as h:mm:ss or m:ss.
fn clock(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    if s >= 3600 {
        format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    } else {
        format!("{}:{:02}", s / 60, s % 60)
    }
}

impl Progress {
    pub fn new(total: usize, skipped: usize) -> Self {
        Self {
            total,
            skipped,
            finished: 0,
            failed: 0,
            started: Instant::now(),
            terminal: std::io::stderr().is_terminal(),
            drawn: false,
        }
    }

    pub fn failed(&self) -> usize {
        self.failed
    }

    pub fn finished(&self) -> usize {
        self.finished
    }

    /// "12/27 done, 1 failed, 0.82 models/s, 0:14 left".
    fn line(&self) -> String {
        let done = self.skipped + self.finished;
        let secs = self.started.elapsed().as_secs_f64();
        let rate = if secs > 0.0 {
            self.finished as f64 / secs
        } else {
            0.0
        };
        let left = if done >= self.total {
            "0:00 left".to_string()
        } else if rate > 0.0 {
            format!("{} left", clock((self.total - done) as f64 / rate))
        } else {
            "time left unknown".to_string()
        };
        format!(
            "{done}/{} done, {} failed, {rate:.2} models/s, {left}",
            self.total, self.failed
        )
    }

    /// Draws the line before the first item finishes (on a terminal).
    pub fn start(&mut self) {
        if self.terminal && self.skipped < self.total {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "{}", self.line());
            let _ = err.flush();
            self.drawn = true;
        }
    }

    /// One item finished: `item` ok or not, after `seconds`.
    pub fn item(&mut self, item: &str, status: &str, seconds: f64, error: Option<&str>) {
        self.finished += 1;
        if status != "ok" {
            self.failed += 1;
        }
        let mut err = std::io::stderr().lock();
        if self.terminal {
            let _ = write!(err, "\r\x1b[K");
            if let Some(e) = error {
                let _ = writeln!(err, "{status}: {item}: {e}");
            }
            let _ = write!(err, "{}", self.line());
            self.drawn = true;
        } else {
            let what = match error {
                Some(e) => format!("{status}: {e}"),
                None => status.to_string(),
            };
            let _ = writeln!(err, "[{}] {item} {what} ({seconds:.2} s)", self.line());
        }
        let _ = err.flush();
    }

    /// Ends the progress line.
    pub fn finish(&mut self) {
        if self.drawn {
            let mut err = std::io::stderr().lock();
            let _ = writeln!(err);
            self.drawn = false;
        }
    }
}
