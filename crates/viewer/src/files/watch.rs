//! [`FileWatcher`]: reports changes to one file by polling its metadata (modification time,
//! size and, on Unix, inode) on a background thread, every [`POLL_INTERVAL`] by default. One
//! `stat` per poll costs nothing measurable, so an idle viewer stays idle; no platform
//! notification API (and no new dependency) is needed.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::thread::{self, JoinHandle};
use std::time::{Duration, SystemTime};

/// Default time between two looks at the file.
pub const POLL_INTERVAL: Duration = Duration::from_millis(500);

/// Watches one file and calls a callback when it has changed and then stayed unchanged for
/// one poll (so a file being rewritten is reported once, when complete). Deleting the file is
/// not reported (nor an error); it is reported again once it reappears and is stable.
/// Dropping the watcher stops and joins its thread at once (it waits on a channel, not a
/// sleep), unless the callback is running, which it waits for.
#[derive(Debug)]
pub struct FileWatcher {
    path: PathBuf,
    /// Dropping this wakes the thread and ends it.
    stop: Option<mpsc::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl FileWatcher {
    /// Watches `path`, polling every [`POLL_INTERVAL`]; `on_change` runs on the watcher's
    /// thread (e.g. set a flag and call egui's `Context::request_repaint`). Fails only if the
    /// thread cannot be started.
    pub fn new(path: impl Into<PathBuf>, on_change: Box<dyn Fn() + Send>) -> std::io::Result<Self> {
        Self::with_interval(path, POLL_INTERVAL, on_change)
    }

    /// [`FileWatcher::new`] with a given poll interval.
    pub fn with_interval(
        path: impl Into<PathBuf>,
        interval: Duration,
        on_change: Box<dyn Fn() + Send>,
    ) -> std::io::Result<Self> {
        let path = path.into();
        let watched = path.clone();
        // The state is taken now, so a change right after `new` returns is seen.
        let mut debounce = Debounce::new(Stamp::of(&watched));
        let (stop, stopped) = mpsc::channel::<()>();
        let thread = thread::Builder::new()
            .name("realist-watch".into())
            .spawn(move || {
                while let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(interval) {
                    if debounce.poll(Stamp::of(&watched)) {
                        on_change();
                    }
                }
            })?;
        Ok(Self {
            path,
            stop: Some(stop),
            thread: Some(thread),
        })
    }

    /// The watched file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for FileWatcher {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(thread) = self.thread.take() {
            // A callback that drops its own watcher must not join itself.
            if thread.thread().id() != thread::current().id() {
                let _ = thread.join();
            }
        }
    }
}

/// What identifies a version of the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Stamp {
    pub(super) modified: Option<SystemTime>,
    pub(super) len: u64,
    pub(super) inode: u64,
}

impl Stamp {
    /// The file's current stamp; `None` if it does not exist or cannot be read.
    fn of(path: &Path) -> Option<Self> {
        let meta = std::fs::metadata(path).ok()?;
        #[cfg(unix)]
        let inode = std::os::unix::fs::MetadataExt::ino(&meta);
        #[cfg(not(unix))]
        let inode = 0;
        Some(Self {
            modified: meta.modified().ok(),
            len: meta.len(),
            inode,
        })
    }
}

/// The change detector: a new stamp is reported once it has been seen on two polls in a
/// row and differs from the last one reported; a missing file is remembered, not reported.
#[derive(Debug)]
pub(super) struct Debounce {
    reported: Option<Stamp>,
    last: Option<Stamp>,
}

impl Debounce {
    pub(super) fn new(initial: Option<Stamp>) -> Self {
        Self {
            reported: initial,
            last: initial,
        }
    }

    /// One poll with the file's current stamp; true when a change is to be reported.
    pub(super) fn poll(&mut self, now: Option<Stamp>) -> bool {
        let stable = now == self.last;
        self.last = now;
        if !stable || now == self.reported {
            return false;
        }
        self.reported = now;
        now.is_some()
    }
}
