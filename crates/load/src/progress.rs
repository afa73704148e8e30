//! Progress reporting and cancellation of a load.
//!
//! This module owns [`Progress`], the handle a caller shares (as `Arc<Progress>`, through
//! [`LoadOptions::progress`](super::LoadOptions::progress)) with a load running on another
//! thread, and `Tracker`, the loaders' side of it.
//!
//! **What a reader sees.** A [`Stage`] label (what the loader is doing now) and one
//! fraction of the whole load, 0 to 1, that never goes down during a load: each loader
//! gives every stage a share of the bar (measured on real files) and maps the stage's own
//! units (bytes of text, corners of meshes, primitives) into that share. Stage and
//! fraction are published together in one atomic word, so [`Progress::snapshot`] never
//! pairs a new stage with an old fraction. A load that succeeds ends at
//! ([`Stage::Done`], 1.0).
//!
//! **Cancellation.** [`Progress::cancel`] sets a flag. A load given a `Progress` runs on a
//! helper thread ([`watch`]) while the caller's thread waits for it, looking at the flag
//! every [`POLL`]: on cancel [`load`](super::load) returns [`LoadError::Cancelled`] within
//! a few milliseconds, whatever the loader is doing. The loader stops at its next
//! checkpoint and frees what it built: every 4 MiB of the model file read, every 4096
//! lines of the OBJ pre-scan, every 64 KiB of text `tobj` parses, before every MTL
//! texture and glTF image is decoded and every glTF buffer loaded, between the steps of a
//! glTF primitive, and around every mesh. What has no checkpoint inside (measured on a
//! 2-million-triangle OBJ grid, 75 MB): UTF-8 validation of the text (40 ms), `tobj`
//! assembling a group at its end (up to 270 ms), and building one mesh's topology and
//! normals in `mesh/` (250 ms); that much work may go on after the caller has its error.
//!
//! **Cost model.** A checkpoint is one relaxed atomic load (the flag) and at most one
//! relaxed atomic store (the published word); there is no lock, no allocation and no
//! syscall. Checkpoints are spaced so that there are a few thousand per second of loading
//! (none per line or per vertex), and they cost the same whether or not a `Progress` was
//! given. A watched load also costs one thread start (tens of microseconds) and a wake-up
//! of the waiting thread every [`POLL`]; a load without a `Progress` runs on the caller's
//! thread as before.

use std::cell::Cell;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use super::LoadError;

/// What a load is doing. Stages are a label for the user; the bar is
/// [`Progress::fraction`]. A glTF load shows `Textures` while it decodes an image in the
/// middle of its geometry, then `Geometry` again.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u8)]
pub enum Stage {
    /// Reading the model file.
    Reading = 0,
    /// Checking and parsing the text (OBJ) or the JSON (glTF).
    Parsing = 1,
    /// Reading accessors and building meshes (topology).
    Geometry = 2,
    /// Building meshes whose normals are generated (OBJ groups without `vn`).
    Normals = 3,
    /// Reading and decoding textures.
    Textures = 4,
    /// Loaded: the fraction is 1.
    Done = 5,
}

impl Stage {
    /// Every stage, in declaration order.
    pub const ALL: [Stage; 6] = [
        Stage::Reading,
        Stage::Parsing,
        Stage::Geometry,
        Stage::Normals,
        Stage::Textures,
        Stage::Done,
    ];

    /// A short lower-case name for a status line ("reading", "parsing", ...).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Stage::Reading => "reading",
            Stage::Parsing => "parsing",
            Stage::Geometry => "geometry",
            Stage::Normals => "normals",
            Stage::Textures => "textures",
            Stage::Done => "done",
        }
    }

    fn from_bits(bits: u8) -> Stage {
        Stage::ALL
            .get(usize::from(bits))
            .copied()
            .unwrap_or(Stage::Done)
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The fraction 1.0 in the published word's fixed point (exact in `f32`).
const FULL: u32 = 1 << 24;
/// The published fraction of a load that has not started.
const UNKNOWN: u32 = u32::MAX;

/// Packs a stage and a fixed-point fraction into one word.
fn pack(stage: Stage, fixed: u32) -> u64 {
    (u64::from(stage as u8) << 32) | u64::from(fixed)
}

/// Progress of one load, shared between the loading thread and whoever watches or cancels
/// it. Atomics only: every method is wait-free and may be called from any thread.
///
/// `Progress::default()` is a fresh handle: stage [`Stage::Reading`], fraction unknown,
/// not cancelled. [`load`](super::load) resets stage and fraction when it starts but
/// keeps the cancel flag, so a load given an already cancelled `Progress` returns
/// [`LoadError::Cancelled`] at once. Use one `Progress` per load.
///
/// ```
/// use realist_load::{load, LoadError, LoadOptions, Progress, Stage};
///
/// let dir = std::env::temp_dir().join(format!("realist-progress-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("tri.obj");
/// std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
///
/// let progress = Progress::new();
/// let opts = LoadOptions { progress: Some(progress.clone()), ..LoadOptions::default() };
/// let worker = {
///     let (path, opts) = (path.clone(), opts.clone());
///     std::thread::spawn(move || load(&path, &opts))
/// };
/// // A UI shows `progress.snapshot()` every frame and calls `progress.cancel()` on request.
/// let scene = worker.join().unwrap().unwrap();
/// assert_eq!(scene.meshes.len(), 1);
/// assert_eq!(progress.snapshot(), (Stage::Done, Some(1.0)));
///
/// let cancelled = Progress::new();
/// cancelled.cancel();
/// let opts = LoadOptions { progress: Some(cancelled), ..LoadOptions::default() };
/// assert!(matches!(load(&path, &opts), Err(LoadError::Cancelled { .. })));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub struct Progress {
    /// `stage << 32 | fraction` (fraction in 1/[`FULL`] units, or [`UNKNOWN`]).
    state: AtomicU64,
    cancelled: AtomicBool,
}

impl Default for Progress {
    fn default() -> Self {
        Self {
            state: AtomicU64::new(pack(Stage::Reading, UNKNOWN)),
            cancelled: AtomicBool::new(false),
        }
    }
}

impl Progress {
    /// A fresh handle, shareable with a loading thread.
    #[must_use]
    pub fn new() -> Arc<Progress> {
        Arc::new(Progress::default())
    }

    /// Asks the load to stop. It returns [`LoadError::Cancelled`] at its next checkpoint
    /// (within a few milliseconds); a cancel after the load returned has no effect on it.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether [`Progress::cancel`] was called.
    #[must_use]
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// What the load is doing now.
    #[must_use]
    pub fn stage(&self) -> Stage {
        self.snapshot().0
    }

    /// How much of the whole load is done, 0 to 1 and never decreasing during a load;
    /// `None` before the load has started.
    #[must_use]
    pub fn fraction(&self) -> Option<f32> {
        self.snapshot().1
    }

    /// Stage and fraction read together (one atomic load, so they belong to each other).
    #[must_use]
    pub fn snapshot(&self) -> (Stage, Option<f32>) {
        let word = self.state.load(Ordering::Relaxed);
        let stage = Stage::from_bits((word >> 32) as u8);
        let fixed = word as u32;
        let fraction = (fixed != UNKNOWN).then(|| fixed.min(FULL) as f32 / FULL as f32);
        (stage, fraction)
    }

    fn publish(&self, stage: Stage, fixed: u32) {
        self.state.store(pack(stage, fixed), Ordering::Relaxed);
    }
}

impl fmt::Debug for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (stage, fraction) = self.snapshot();
        f.debug_struct("Progress")
            .field("stage", &stage)
            .field("fraction", &fraction)
            .field("cancelled", &self.is_cancelled())
            .finish()
    }
}

/// How often the thread waiting for a watched load looks at the cancel flag.
const POLL: Duration = Duration::from_millis(2);

/// Runs `work` (a whole load of `path`, which returns promptly once `progress` is
/// cancelled) on a helper thread, and waits for its result or for a cancel, whichever
/// comes first. After a cancel the helper is left to reach its next checkpoint and drop
/// what it built; nobody receives its result.
pub(crate) fn watch<T: Send + 'static>(
    path: &Path,
    progress: &Progress,
    work: impl FnOnce() -> Result<T, LoadError> + Send + 'static,
) -> Result<T, LoadError> {
    let (tx, rx) = mpsc::sync_channel(1);
    std::thread::Builder::new()
        .name("realist-load".into())
        // What the caller's (main) thread would have had.
        .stack_size(8 << 20)
        .spawn(move || {
            // The receiver is gone only after a cancel: nobody wants the result.
            let _ = tx.send(work());
        })
        .map_err(|e| LoadError::Io {
            path: path.to_owned(),
            source: std::io::Error::new(e.kind(), format!("cannot start a loading thread: {e}")),
        })?;
    let cancelled = || LoadError::Cancelled {
        path: path.to_owned(),
    };
    loop {
        match rx.recv_timeout(POLL) {
            Ok(Err(e @ LoadError::Panic { .. })) => return Err(e),
            Ok(_) | Err(mpsc::RecvTimeoutError::Timeout) if progress.is_cancelled() => {
                return Err(cancelled())
            }
            Ok(result) => return result,
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            // `work` catches its own panics, so this is not expected.
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(LoadError::Panic {
                    path: path.to_owned(),
                    message: "the loading thread ended without a result".into(),
                })
            }
        }
    }
}

/// The loaders' side of a [`Progress`]: the current stage's share of the bar and its units.
/// Single-threaded (the loading thread owns it); all state but the shared word is local.
pub(crate) struct Tracker {
    path: PathBuf,
    /// The caller's handle, or a private one when none was given (same checkpoints).
    shared: Arc<Progress>,
    stage: Cell<Stage>,
    /// The current stage's share of the bar, `from..to` in fixed point.
    from: Cell<u32>,
    to: Cell<u32>,
    /// The current stage's size and progress in its own units (total at least 1).
    total: Cell<u64>,
    done: Cell<u64>,
    /// Last published fraction: the bar never goes below it.
    shown: Cell<u32>,
}

impl Tracker {
    /// Starts tracking a load of `path`: stage [`Stage::Reading`] at fraction 0.
    pub(crate) fn new(path: &Path, progress: Option<&Arc<Progress>>) -> Self {
        let shared = progress.cloned().unwrap_or_default();
        shared.publish(Stage::Reading, 0);
        Self {
            path: path.to_owned(),
            shared,
            stage: Stage::Reading.into(),
            from: 0.into(),
            to: 0.into(),
            total: 1.into(),
            done: 0.into(),
            shown: 0.into(),
        }
    }

    /// Enters `stage`, whose `total` units (of the loader's choosing) fill the bar from
    /// where it is up to `until` (0 to 1). Then a checkpoint.
    pub(crate) fn begin(&self, stage: Stage, until: f32, total: u64) -> Result<(), LoadError> {
        let until = (until.clamp(0.0, 1.0) * FULL as f32) as u32;
        let from = self.shown.get();
        self.from.set(from);
        self.to.set(until.max(from));
        self.total.set(total.max(1));
        self.done.set(0);
        self.stage.set(stage);
        self.shared.publish(stage, from);
        self.check()
    }

    /// `done` of the current stage's units are done (clamped to its total; the bar never
    /// goes back). Then a checkpoint.
    pub(crate) fn advance(&self, done: u64) -> Result<(), LoadError> {
        self.done.set(done);
        let (from, to, total) = (self.from.get(), self.to.get(), self.total.get());
        let span = u128::from(to - from) * u128::from(done.min(total)) / u128::from(total);
        let fixed = from + span as u32;
        if fixed > self.shown.get() {
            self.shown.set(fixed);
            self.shared.publish(self.stage.get(), fixed);
        }
        self.check()
    }

    /// The current stage's units done so far.
    pub(crate) fn done(&self) -> u64 {
        self.done.get()
    }

    /// Shows `stage` without moving the bar or changing the current stage's units (a
    /// texture decoded in the middle of glTF geometry). Then a checkpoint.
    pub(crate) fn label(&self, stage: Stage) -> Result<(), LoadError> {
        self.stage.set(stage);
        self.shared.publish(stage, self.shown.get());
        self.check()
    }

    /// A checkpoint: [`LoadError::Cancelled`] once the load was cancelled.
    pub(crate) fn check(&self) -> Result<(), LoadError> {
        if self.is_cancelled() {
            return Err(self.cancelled());
        }
        Ok(())
    }

    pub(crate) fn is_cancelled(&self) -> bool {
        self.shared.is_cancelled()
    }

    /// The shared handle, for worker threads to see a cancel (the tracker itself stays on
    /// the loading thread).
    pub(crate) fn progress(&self) -> &Progress {
        &self.shared
    }

    /// The error a cancelled load returns.
    pub(crate) fn cancelled(&self) -> LoadError {
        LoadError::Cancelled {
            path: self.path.clone(),
        }
    }

    /// Marks the load as done (fraction 1).
    pub(crate) fn finish(&self) {
        self.stage.set(Stage::Done);
        self.shown.set(FULL);
        self.shared.publish(Stage::Done, FULL);
    }
}

#[cfg(test)]
mod tests;
