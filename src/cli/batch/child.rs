//! One item's process: this same program run as `realist render ...` (or `thumbnail`), its
//! standard error kept for the error message, killed when it runs past its time.

use std::io::Read as _;
use std::path::PathBuf;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

/// Most bytes of a child's standard error kept (its end).
const KEEP_STDERR: usize = 64 << 10;

/// A running item.
pub(crate) struct Running {
    /// The item's index in the batch's list.
    pub index: usize,
    /// The folder it writes into, renamed into place when it succeeds.
    pub temp: PathBuf,
    child: Child,
    started: Instant,
    stderr: Receiver<Vec<u8>>,
}

/// How an item's process ended.
pub(crate) enum Ended {
    /// Exit status 0.
    Ok,
    /// Non-zero exit status or a signal: the message.
    Failed(String),
    /// Killed at the time limit.
    Timeout,
}

impl Running {
    /// Starts `exe args...` with no input, output discarded, standard error captured.
    pub fn start(
        index: usize,
        temp: PathBuf,
        exe: &std::path::Path,
        args: &[std::ffi::OsString],
    ) -> Result<Self> {
        let mut child = Command::new(exe)
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("could not start {}", exe.display()))?;
        let mut pipe = child.stderr.take().context("no standard error pipe")?;
        let (tx, rx) = mpsc::channel();
        // Read on a thread, so a child writing much to stderr never blocks on a full pipe.
        std::thread::spawn(move || {
            let mut kept = Vec::new();
            let mut buf = [0u8; 8192];
            while let Ok(n) = pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                kept.extend_from_slice(&buf[..n]);
                if kept.len() > 2 * KEEP_STDERR {
                    kept.drain(..kept.len() - KEEP_STDERR);
                }
            }
            let _ = tx.send(kept);
        });
        Ok(Self {
            index,
            temp,
            child,
            started: Instant::now(),
            stderr: rx,
        })
    }

    /// Ends it now (a run stopped by an error).
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// `None` while it runs (killing it once past `timeout`), else how it ended.
    pub fn poll(&mut self, timeout: Duration) -> Result<Option<Ended>> {
        let status = match self.child.try_wait()? {
            Some(s) => s,
            None if self.started.elapsed() > timeout => {
                // Already gone is fine: wait() below collects it either way.
                let _ = self.child.kill();
                self.child.wait()?;
                return Ok(Some(Ended::Timeout));
            }
            None => return Ok(None),
        };
        if status.success() {
            return Ok(Some(Ended::Ok));
        }
        Ok(Some(Ended::Failed(self.message(status))))
    }

    /// The child's standard error (what it wrote until it ended; a process it started that
    /// still holds the pipe does not keep us waiting past a second).
    fn stderr(&self) -> String {
        let bytes = self
            .stderr
            .recv_timeout(Duration::from_secs(1))
            .unwrap_or_default();
        String::from_utf8_lossy(&bytes).into_owned()
    }

    /// Why it failed: its error line (`realist: ...`), a panic's message, or the end of what
    /// it wrote, with how it ended.
    fn message(&self, status: ExitStatus) -> String {
        let text = self.stderr();
        let lines: Vec<&str> = text
            .lines()
            .map(str::trim_end)
            .filter(|l| !l.is_empty())
            .collect();
        let said = if let Some(l) = lines.iter().rev().find(|l| l.starts_with("realist: ")) {
            l.trim_start_matches("realist: ").to_string()
        } else if let Some(i) = lines.iter().position(|l| l.contains("panicked at")) {
            lines[i..lines.len().min(i + 2)].join(" ")
        } else {
            lines[lines.len().saturating_sub(3)..].join(" ")
        };
        let how = ended(status);
        let mut msg = if said.is_empty() {
            how
        } else {
            format!("{said} ({how})")
        };
        if msg.len() > 2000 {
            let mut cut = 2000;
            while !msg.is_char_boundary(cut) {
                cut -= 1;
            }
            msg.truncate(cut);
            msg.push_str("...");
        }
        msg
    }
}

/// "exit status N", or the signal that ended the process.
fn ended(status: ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt as _;
        if let Some(sig) = status.signal() {
            let name = match sig {
                4 => " (SIGILL)",
                6 => " (SIGABRT)",
                7 => " (SIGBUS)",
                8 => " (SIGFPE)",
                9 => " (SIGKILL, e.g. out of memory)",
                11 => " (SIGSEGV)",
                15 => " (SIGTERM)",
                _ => "",
            };
            return format!("killed by signal {sig}{name}");
        }
    }
    match status.code() {
        Some(c) => format!("exit status {c}"),
        None => "ended abnormally".into(),
    }
}
