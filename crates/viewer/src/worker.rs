//! The render worker: renders on its own thread (and rayon pool) so the UI never waits for a
//! frame. Requests are coalesced in a one-job slot (a drag sends many, only the newest is
//! drawn), a frame in progress is abandoned between tiles when a newer job arrives, and
//! each job is refined progressively:
//!
//! 1. while the camera moves, at a reduced resolution if full resolution would take longer
//!    than [`FRAME_BUDGET_MS`] (the divisor chosen from the last full frame's time); a scene
//!    of more than [`PROXY_ABOVE`] triangles is drawn from its simplified copy
//!    ([`Job::proxy`], about [`PROXY_TRIANGLES`] triangles) until the camera stops;
//! 2. full resolution, one sample per pixel;
//! 3. 2 x 2, then 4 x 4 supersampling (as far as the job's `max_samples` allows), each a
//!    finished image shown as soon as it is done.
//!
//! A path-traced job (`--shading path` on the A side) instead accumulates: after one path
//! per pixel, batches of paths are added to a running sum kept in the renderer
//! ([`Renderer::render_paths`]), each batch shown as soon as it is done, the batch
//! doubling (1, 1, 2, 4, ... paths per pixel) while it takes less than
//! [`PATH_BATCH_MS`], up to [`PATH_CAP`] paths per pixel (or one, with `max_samples` 1).
//! Then the worker goes idle; a newer job abandons the sum and starts again from 0.
//!
//! A newer job abandons refinements at once, but a job's first frame only once it has run
//! [`ABANDON_FIRST_MS`]: a drag whose events come faster than frames then still shows a
//! frame per render instead of abandoning them all.
//!
//! After an interactive job's first frame the worker waits [`SETTLE_MS`] for a newer job
//! before refining, so a drag does not start refinements it will abandon. Finished frames
//! go to a one-frame slot and the UI is asked to repaint; an idle worker sleeps on a
//! condition variable (no polling). Tests use the synchronous host, which renders the
//! final level in the calling thread.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;

use eframe::egui::Color32;

use crate::raster::TileCost;
use crate::render::{FrameReport, PreparedScene, Renderer, Settings, View};

mod draw;
mod schedule;

use schedule::{accumulates, path_cap};

/// Interactive frames should take at most this long (about 30 frames per second).
pub const FRAME_BUDGET_MS: f64 = 33.0;
/// How long an interactive job waits for a newer one before refining.
pub const SETTLE_MS: u64 = 150;
/// A job's first frame is abandoned for a newer job only after this long (4 budgets).
pub const ABANDON_FIRST_MS: f64 = 4.0 * FRAME_BUDGET_MS;
/// Scenes with more triangles than this get a simplified copy to draw while moving.
pub const PROXY_ABOVE: u64 = 1_000_000;
/// About how many triangles the simplified copy keeps.
pub const PROXY_TRIANGLES: u64 = 250_000;
/// A path-traced job accumulates up to this many paths per pixel.
pub const PATH_CAP: u32 = 1024;
/// A path-traced job's batches stop doubling once one takes this long.
pub const PATH_BATCH_MS: f64 = 1000.0;

/// A quality level of a shown frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// Resolution divided by this (2..=4) per axis, while the camera moves.
    Reduced(u32),
    /// The scene's simplified copy ([`Job::proxy`]) at the resolution divided by this
    /// (1..=4), while the camera moves.
    Simplified(u32),
    /// Full resolution, one sample per pixel.
    Full,
    /// Full resolution, n x n samples per pixel.
    Supersampled(u32),
    /// Full resolution, path traced: the mean of this many paths per pixel.
    Paths(u32),
}

impl Level {
    /// For the status bar.
    #[must_use]
    pub fn label(self) -> String {
        match self {
            Level::Reduced(d) => format!("1/{d} resolution (moving)"),
            Level::Simplified(1) => "simplified (moving)".into(),
            Level::Simplified(d) => format!("1/{d} resolution, simplified (moving)"),
            Level::Full => "full resolution".into(),
            Level::Supersampled(n) => format!("{n}x{n} supersampled"),
            Level::Paths(1) => "path: 1 path per pixel".into(),
            Level::Paths(n) => format!("path: {n} paths per pixel"),
        }
    }

    /// The resolution divisor: 1 at full resolution.
    fn divisor(self) -> u32 {
        match self {
            Level::Reduced(d) => d.clamp(2, 4),
            Level::Simplified(d) => d.clamp(1, 4),
            Level::Full | Level::Supersampled(_) | Level::Paths(_) => 1,
        }
    }

    fn samples(self) -> u32 {
        match self {
            Level::Supersampled(n) => n,
            _ => 1,
        }
    }
}

/// A render request.
#[derive(Clone)]
pub struct Job {
    pub scene: Arc<PreparedScene>,
    /// The left (or only) image's settings.
    pub a: Arc<Settings>,
    /// The right image's settings in split view.
    pub b: Option<Arc<Settings>>,
    /// Compute the ΔE00 map between A and B (split view only).
    pub heat: bool,
    /// The full-resolution view.
    pub view: View,
    /// The camera is moving: a reduced resolution is allowed.
    pub interactive: bool,
    /// Refine up to this many samples per axis (1, 2 or 4).
    pub max_samples: u32,
    /// A simplified copy of `scene` for frames while the camera moves (a scene of more
    /// than [`PROXY_ABOVE`] triangles: [`PreparedScene::simplified`]).
    pub proxy: Option<Arc<PreparedScene>>,
}

/// One rendered image with what the panels show about it.
#[derive(Clone)]
pub struct Image {
    /// sRGB8, row-major, `view.width * view.height` (of the frame's view).
    pub pixels: Vec<Color32>,
    pub report: FrameReport,
    pub tile_costs: Vec<TileCost>,
    /// Tiles per row of the frame's target.
    pub tiles_x: u32,
}

/// The ΔE00 difference of a split view.
pub struct Heat {
    pub pixels: Vec<Color32>,
    pub mean: f64,
    pub p95: f64,
}

/// A finished frame.
pub struct Frame {
    /// Which job (counting from 1) it belongs to.
    pub job: u64,
    pub level: Level,
    /// The view actually rendered (reduced size while moving).
    pub view: View,
    pub a: Image,
    pub b: Option<Image>,
    pub heat: Option<Heat>,
    /// Depth of A, row-major (reversed-Z, 0 = nothing drawn), for picking.
    pub depth: Vec<f32>,
    /// No finer level follows for this job.
    pub last: bool,
}

/// What the worker thread and the UI share.
struct Shared {
    job: Mutex<Option<(u64, Job)>>,
    wake: Condvar,
    /// Number of the newest job submitted.
    newest: AtomicU64,
    frame: Mutex<Option<Frame>>,
    /// The worker is rendering (for the status bar's spinner).
    busy: AtomicBool,
    quit: AtomicBool,
}

/// Renders jobs on a worker thread, or synchronously for tests.
pub struct RenderHost {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    /// `Some` in synchronous mode: the renderers used inline.
    sync: Option<Box<Worker>>,
    submitted: u64,
}

impl RenderHost {
    /// A worker thread with its own rayon pool of `threads` threads (0 = all cores);
    /// `repaint` is called whenever a frame is ready.
    ///
    /// # Errors
    /// If the thread or its pool cannot be started.
    pub fn threaded(threads: usize, repaint: Arc<dyn Fn() + Send + Sync>) -> std::io::Result<Self> {
        let shared = Arc::new(Shared::new());
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("realist-render-{i}"))
            .build()
            .map_err(std::io::Error::other)?;
        let sh = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("realist-render".into())
            .spawn(move || {
                // The loop runs on a pool thread, so the renderer's parallel work is queued
                // locally (rayon's injector would allocate per frame).
                pool.install(|| Worker::default().run(&sh, &*repaint));
            })?;
        Ok(Self {
            shared,
            thread: Some(thread),
            sync: None,
            submitted: 0,
        })
    }

    /// Renders each job's final level inside [`RenderHost::submit`] (UI tests).
    #[must_use]
    pub fn synchronous() -> Self {
        Self {
            shared: Arc::new(Shared::new()),
            thread: None,
            sync: Some(Box::default()),
            submitted: 0,
        }
    }

    /// Queues a job, replacing any job not yet started; the frame in progress is abandoned.
    pub fn submit(&mut self, job: Job) {
        self.submitted += 1;
        let n = self.submitted;
        if let Some(w) = &mut self.sync {
            let level = match job.max_samples {
                _ if accumulates(&job) => Level::Paths(path_cap(&job)),
                0 | 1 => Level::Full,
                s => Level::Supersampled(s),
            };
            if let Ok(frame) = w.render_level(&job, n, (level, 0), &|| false) {
                *lock(&self.shared.frame) = Some(Frame {
                    last: true,
                    ..frame
                });
            }
            return;
        }
        *lock(&self.shared.job) = Some((n, job));
        self.shared.newest.store(n, Ordering::SeqCst);
        self.shared.wake.notify_all();
    }

    /// The newest finished frame, if one arrived since the last call.
    pub fn take_frame(&mut self) -> Option<Frame> {
        lock(&self.shared.frame).take()
    }

    /// Whether the worker is rendering or has a job queued.
    #[must_use]
    pub fn busy(&self) -> bool {
        self.shared.busy.load(Ordering::SeqCst) || lock(&self.shared.job).is_some()
    }

    /// Number of the newest job submitted.
    #[must_use]
    pub fn submitted(&self) -> u64 {
        self.submitted
    }
}

impl Drop for RenderHost {
    fn drop(&mut self) {
        self.shared.quit.store(true, Ordering::SeqCst);
        self.shared.newest.fetch_add(1, Ordering::SeqCst);
        self.shared.wake.notify_all();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Shared {
    fn new() -> Self {
        Self {
            job: Mutex::new(None),
            wake: Condvar::new(),
            newest: AtomicU64::new(0),
            frame: Mutex::new(None),
            busy: AtomicBool::new(false),
            quit: AtomicBool::new(false),
        }
    }
}

/// Locks a mutex, recovering the data of a poisoned one (a panic elsewhere must not take
/// the viewer down).
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The worker's state: its renderers and what it learnt about frame times.
#[derive(Default)]
struct Worker {
    a: Renderer,
    b: Renderer,
    /// Moving averages of one-sample frame times (A and B) at full resolution (index 1)
    /// and at 1/2, 1/3, 1/4 (indices 2..=4), for choosing the first level of a job.
    times: [Option<f64>; 5],
    /// The same for the simplified copy of the scene.
    proxy_times: [Option<f64>; 5],
    /// Side B's image beside a path-traced A, kept for A's later batches.
    b_image: Option<Image>,
}
