//! The thumbnailer's budgets and its one write: the address-space limit, the watchdog that
//! ends the process when the wall-clock budget runs out, and the output written atomically
//! (a temporary file in the output's folder, renamed over it), by whichever of the work
//! and the watchdog comes first.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::Instant;

use anyhow::{Context, Result};

/// Limits this process's address space (RLIMIT_AS, soft limit) to `bytes`, or to the hard
/// limit if that is lower. An allocation past it fails (the process then aborts with Rust's
/// "memory allocation failed"); the loaders' own budget, half of it, refuses a large model
/// with a message long before.
#[cfg(target_os = "linux")]
pub(super) fn limit_address_space(bytes: u64) -> Result<()> {
    use rustix::process::{getrlimit, setrlimit, Resource, Rlimit};
    let old = getrlimit(Resource::As);
    let soft = match (old.current, old.maximum) {
        (Some(cur), _) if cur <= bytes => return Ok(()),
        (_, Some(max)) => bytes.min(max),
        (_, None) => bytes,
    };
    setrlimit(
        Resource::As,
        Rlimit {
            current: Some(soft),
            maximum: old.maximum,
        },
    )
    .context("could not limit the address space (RLIMIT_AS)")
}

#[cfg(not(target_os = "linux"))]
pub(super) fn limit_address_space(_bytes: u64) -> Result<()> {
    Ok(())
}

/// The output file and what is ready to go into it.
pub(super) struct Output {
    path: PathBuf,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    /// The quick preview's PNG, once drawn: what the watchdog writes.
    preview: Option<Vec<u8>>,
    /// The output is written: nobody writes again.
    written: bool,
}

impl Output {
    pub(super) fn new(path: PathBuf) -> Self {
        Self {
            path,
            state: Mutex::default(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Keeps `png` for the watchdog to write if the budget runs out.
    pub(super) fn set_preview(&self, png: Vec<u8>) {
        self.lock().preview = Some(png);
    }

    /// Writes the finished thumbnail (unless the watchdog wrote the preview first, in which
    /// case the process is already ending).
    pub(super) fn write(&self, png: &[u8]) -> Result<()> {
        let mut state = self.lock();
        if !state.written {
            write_atomic(&self.path, png)?;
            state.written = true;
        }
        Ok(())
    }
}

/// Writes `bytes` to `path` through a temporary file in the same folder, renamed over it:
/// a reader sees the old file or the whole new one, never a part. The temporary file is
/// removed if anything fails.
pub(super) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let tmp = folder.join(format!(
        ".{}.realist-{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let written = (|| -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(e).with_context(|| format!("could not write {}", path.display()));
    }
    Ok(())
}

/// The watchdog thread; [`Watchdog::finish`] stops it.
pub(super) struct Watchdog {
    stop: Option<mpsc::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl Watchdog {
    /// Stops the watchdog (the work is done, written or failed).
    pub(super) fn finish(mut self) {
        drop(self.stop.take());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Starts the watchdog: at `deadline`, unless stopped, it writes the preview and exits with
/// status 0, or with none exits with status 1, whatever the work is doing.
pub(super) fn watchdog(out: Arc<Output>, deadline: Instant, input: String) -> Watchdog {
    let (stop, stopped) = mpsc::channel::<()>();
    let thread = std::thread::Builder::new()
        .name("thumbnail watchdog".into())
        .spawn(move || {
            let wait = deadline.saturating_duration_since(Instant::now());
            if !matches!(stopped.recv_timeout(wait), Err(RecvTimeoutError::Timeout)) {
                return;
            }
            let mut state = out.lock();
            if state.written {
                return;
            }
            let code = match state.preview.take() {
                Some(png) => match write_atomic(&out.path, &png) {
                    Ok(()) => {
                        state.written = true;
                        eprintln!(
                            "realist thumbnail: {input}: the time budget ran out; wrote the \
                             quick preview (no environment, no anti-aliasing) instead"
                        );
                        0
                    }
                    Err(e) => {
                        eprintln!("realist thumbnail: {input}: the time budget ran out, and {e:#}");
                        1
                    }
                },
                None => {
                    eprintln!(
                        "realist: no thumbnail of {input}: the time budget ran out before \
                         anything was drawn (--budget to allow more)"
                    );
                    1
                }
            };
            // Ends every thread, the work included, with the lock held: nothing else writes.
            std::process::exit(code);
        });
    match thread {
        Ok(t) => Watchdog {
            stop: Some(stop),
            thread: Some(t),
        },
        Err(e) => {
            // Without a watchdog the work still runs; say so rather than fail.
            eprintln!("warning: no watchdog thread ({e}): the time budget is not enforced");
            Watchdog {
                stop: None,
                thread: None,
            }
        }
    }
}
