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
use std::time::{Duration, Instant};

use eframe::egui::Color32;

use crate::quality::metrics::{delta_e_map, heat_color, mean_p95};
use crate::quality::LinearImage;
use crate::raster::TileCost;
use crate::render::{FrameReport, PreparedScene, Renderer, Settings, View};

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

impl Worker {
    fn run(&mut self, sh: &Shared, repaint: &(dyn Fn() + Send + Sync)) {
        loop {
            let (n, job) = {
                let mut slot = lock(&sh.job);
                loop {
                    if sh.quit.load(Ordering::SeqCst) {
                        return;
                    }
                    if let Some(j) = slot.take() {
                        break j;
                    }
                    slot = sh
                        .wake
                        .wait(slot)
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                }
            };
            sh.busy.store(true, Ordering::SeqCst);
            let stale = || sh.newest.load(Ordering::SeqCst) != n;
            let mut levels = self.plan(&job);
            // A path-traced job's levels grow as they are rendered (`next_paths`).
            for i in 0.. {
                let Some(&level) = levels.get(i) else { break };
                let from = paths_before(&levels, i);
                if i == 1 && job.interactive && Self::newer_within(sh, n, SETTLE_MS) {
                    break;
                }
                // A job's first level is what the user waits for: a newer job abandons it
                // only once it runs well past the budget (else a drag whose events come
                // faster than frames would abandon every frame and show none); later
                // levels are refinements, abandoned at once.
                let started = Instant::now();
                let long = || started.elapsed().as_secs_f64() * 1e3 > ABANDON_FIRST_MS;
                let first_stop = || stale() && long();
                let stop: &(dyn Fn() -> bool + Sync) = if i == 0 { &first_stop } else { &stale };
                // A panic in a frame (a renderer bug) must not kill the worker: the frame is
                // dropped and the next job starts from fresh renderers.
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    self.render_level(&job, n, (level, from), stop)
                }));
                match result {
                    Ok(Ok(frame)) => {
                        if i + 1 == levels.len() {
                            let ms = started.elapsed().as_secs_f64() * 1e3;
                            levels.extend(next_paths(level, from, path_cap(&job), ms));
                        }
                        let last = i + 1 == levels.len();
                        *lock(&sh.frame) = Some(Frame { last, ..frame });
                        repaint();
                    }
                    Ok(Err(_)) => {
                        if i == 0 {
                            // Too slow to finish: the next job plans a smaller first frame.
                            let spent = started.elapsed().as_secs_f64() * 1e3;
                            let slot = &mut self.times_of(level)[level.divisor() as usize];
                            *slot = Some(slot.map_or(spent, |e| e.max(spent)));
                        }
                        break;
                    }
                    Err(_) => {
                        *self = Worker::default();
                        break;
                    }
                }
            }
            sh.busy.store(false, Ordering::SeqCst);
            repaint();
        }
    }

    /// Waits up to `ms` for a job newer than `n`; true if one arrived.
    fn newer_within(sh: &Shared, n: u64, ms: u64) -> bool {
        let deadline = Instant::now() + Duration::from_millis(ms);
        let mut slot = lock(&sh.job);
        loop {
            if sh.newest.load(Ordering::SeqCst) != n || sh.quit.load(Ordering::SeqCst) {
                return true;
            }
            let now = Instant::now();
            if now >= deadline {
                return false;
            }
            slot = sh
                .wake
                .wait_timeout(slot, deadline - now)
                .map(|(g, _)| g)
                .unwrap_or_else(|e| e.into_inner().0);
        }
    }

    /// The frame times of a level's scene: the simplified copy's, or the scene's.
    fn times_of(&mut self, level: Level) -> &mut [Option<f64>; 5] {
        match level {
            Level::Simplified(_) => &mut self.proxy_times,
            Level::Reduced(_) | Level::Full | Level::Supersampled(_) | Level::Paths(_) => {
                &mut self.times
            }
        }
    }

    /// The levels to render for a job, coarsest first.
    fn plan(&self, job: &Job) -> Vec<Level> {
        let mut levels = Vec::new();
        if job.interactive {
            if job.proxy.is_some() {
                levels.push(Level::Simplified(divisor(&self.proxy_times)));
            } else {
                let d = divisor(&self.times);
                if d > 1 {
                    levels.push(Level::Reduced(d));
                }
            }
        }
        if accumulates(job) {
            levels.push(Level::Paths(1));
            return levels;
        }
        levels.push(Level::Full);
        for n in [2, 4] {
            if job.max_samples >= n {
                levels.push(Level::Supersampled(n));
            }
        }
        levels
    }
}

/// Records a frame time `ms` at divisor `d` (a moving average) and corrects the other
/// divisors' times that it contradicts: a frame at 1/k resolution has (d/k)² times the
/// pixels of one at 1/d, so it cannot honestly cost more than that ratio (at least 1) times
/// as much; a time more than twice over is stale (one frame slowed by a busy machine or a
/// first-use cost) and is set to the ratio. Without this, one slow full-resolution frame
/// kept every later interactive frame reduced, since reduced frames never measure the full
/// one again (an animation of 0.4 ms frames played at 1/2 resolution for good).
fn record(times: &mut [Option<f64>; 5], d: usize, ms: f64) {
    let Some(slot) = times.get_mut(d) else { return };
    let t = slot.map_or(ms, |old| 0.5 * (old + ms));
    *slot = Some(t);
    for (k, slot) in times.iter_mut().enumerate().skip(1) {
        let ceiling = t * ((d * d) as f64 / (k * k) as f64).max(1.0);
        if let Some(tk) = slot {
            if k != d && *tk > 2.0 * ceiling {
                *tk = ceiling;
            }
        }
    }
}

/// The resolution divisor (1..=4) for a frame that should fit [`FRAME_BUDGET_MS`], from the
/// frame times `times`: the smallest whose time (measured, or extrapolated from the nearest
/// measured divisor as if cost followed the pixel count) fits; if none does, the fastest,
/// preferring the larger image within 10% (a frame bound by geometry gains nothing from
/// fewer pixels).
fn divisor(times: &[Option<f64>; 5]) -> u32 {
    {
        let estimate = |d: usize| -> Option<f64> {
            times[d].or_else(|| {
                (1..=4)
                    .filter_map(|k| times[k].map(|t| (k, t)))
                    .min_by_key(|(k, _)| k.abs_diff(d))
                    .map(|(k, t)| t * (k * k) as f64 / (d * d) as f64)
            })
        };
        let Some(full) = estimate(1) else {
            return 1;
        };
        if full <= FRAME_BUDGET_MS {
            return 1;
        }
        let est: Vec<(u32, f64)> = (2..=4u32)
            .map(|d| (d, estimate(d as usize).unwrap_or(f64::INFINITY)))
            .collect();
        if let Some(&(d, _)) = est.iter().find(|(_, t)| *t <= FRAME_BUDGET_MS) {
            return d;
        }
        let fastest = est.iter().map(|e| e.1).fold(f64::INFINITY, f64::min);
        est.iter()
            .find(|(_, t)| *t <= fastest * 1.1)
            .map_or(4, |&(d, _)| d)
    }
}

impl Worker {
    /// Renders one level of a job (A, B and the heat map); `from`: for a [`Level::Paths`],
    /// the paths per pixel already summed by the job's earlier levels.
    fn render_level(
        &mut self,
        job: &Job,
        n: u64,
        (level, from): (Level, u32),
        stale: &(dyn Fn() -> bool + Sync),
    ) -> Result<Frame, crate::render::Interrupted> {
        let start = Instant::now();
        let mut view = job.view.clone();
        let d = level.divisor();
        view.width = (view.width / d).max(1);
        view.height = (view.height / d).max(1);
        let samples = level.samples();
        let scene = match (level, &job.proxy) {
            (Level::Simplified(_), Some(p)) => p,
            _ => &job.scene,
        };
        let paths = match level {
            Level::Paths(to) => Some(from..to),
            _ => None,
        };
        let a = render_image(&mut self.a, scene, &job.a, &view, (samples, paths), stale)?;
        let b = match &job.b {
            Some(s) => {
                let how = (level, from, job.max_samples);
                Some(self.render_b(scene, s, &view, how, stale)?)
            }
            None => None,
        };
        if !matches!(level, Level::Supersampled(_) | Level::Paths(2..)) {
            let ms = start.elapsed().as_secs_f64() * 1e3;
            record(self.times_of(level), level.divisor() as usize, ms);
        }
        let heat = match (&b, job.heat, level) {
            (Some(_), true, Level::Full | Level::Supersampled(_) | Level::Paths(_)) => {
                Some(heat(&self.a, &self.b))
            }
            _ => None,
        };
        let mut depth = vec![0.0; (view.width * view.height) as usize];
        if let Some(t) = self.a.target() {
            t.write_depth(&mut depth);
        }
        Ok(Frame {
            job: n,
            level,
            view,
            a,
            b,
            heat,
            depth,
            last: false,
        })
    }
}

impl Worker {
    /// Renders side B at `level` (`from`: as in [`Worker::render_level`]). Beside a
    /// path-traced A that accumulates, a B not path traced is drawn twice only: with one
    /// sample beside A's first path, then supersampled as far as `max_samples` allows beside
    /// the second batch; A's later batches show that image again (a path-traced B
    /// accumulates as A does).
    fn render_b(
        &mut self,
        scene: &PreparedScene,
        settings: &Settings,
        view: &View,
        (level, from, max_samples): (Level, u32, u32),
        stale: &(dyn Fn() -> bool + Sync),
    ) -> Result<Image, crate::render::Interrupted> {
        let paths = match level {
            Level::Paths(to) => Some(from..to),
            _ => None,
        };
        let fixed = paths.is_some() && !path_traced(settings);
        if let (true, 2.., Some(image)) = (fixed, from, &self.b_image) {
            return Ok(image.clone());
        }
        let samples = match (fixed, from) {
            (true, 1) => max_samples.clamp(1, 4),
            _ => level.samples(),
        };
        let image = render_image(&mut self.b, scene, settings, view, (samples, paths), stale)?;
        self.b_image = fixed.then(|| image.clone());
        Ok(image)
    }
}

/// Renders one side: `samples` per axis, or for a path-traced side given `paths`, those
/// paths added to its running sum (a side not path traced is drawn with `samples`).
fn render_image(
    r: &mut Renderer,
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    (samples, paths): (u32, Option<std::ops::Range<u32>>),
    stale: &(dyn Fn() -> bool + Sync),
) -> Result<Image, crate::render::Interrupted> {
    let report = match paths {
        Some(range) if path_traced(settings) => {
            r.render_paths(scene, settings, view, range, stale)?.clone()
        }
        _ => {
            let mut s = settings.clone();
            s.samples = samples;
            r.render_until(scene, &s, view, stale)?.clone()
        }
    };
    let mut pixels = vec![Color32::BLACK; (view.width * view.height) as usize];
    r.write_pixels(&mut pixels, |[cr, cg, cb, ca]| {
        Color32::from_rgba_premultiplied(cr, cg, cb, ca)
    });
    let tiles_x = r.target().map_or(1, |t| t.tiles_x);
    Ok(Image {
        pixels,
        report,
        tile_costs: r.tile_costs().to_vec(),
        tiles_x,
    })
}

/// Whether `settings` shade by path tracing (what [`Renderer::render_paths`] adds up).
fn path_traced(settings: &Settings) -> bool {
    settings.rays() == crate::shade::mode::Rays::Path
        && settings.output == crate::render::Output::Shaded
}

/// Whether a job accumulates paths: its A side is path traced (a path-traced B beside
/// another A follows A's levels: supersampled, its passes one path each).
fn accumulates(job: &Job) -> bool {
    path_traced(&job.a)
}

/// Paths per pixel a path-traced job accumulates: [`PATH_CAP`], or one when refinement is
/// off (`max_samples` 1).
fn path_cap(job: &Job) -> u32 {
    if job.max_samples > 1 {
        PATH_CAP
    } else {
        1
    }
}

/// Paths per pixel summed by the levels before `levels[i]` (0 unless it follows a
/// [`Level::Paths`]).
fn paths_before(levels: &[Level], i: usize) -> u32 {
    match i.checked_sub(1).map(|j| levels[j]) {
        Some(Level::Paths(n)) => n,
        _ => 0,
    }
}

/// The level after `level` of a path-traced job, which added paths `from..n` in `ms`
/// milliseconds: the batch doubles (as many paths again as summed so far) unless that
/// would take longer than [`PATH_BATCH_MS`] (then as many as fit, at least one), up to
/// `cap` paths per pixel; `None` at the cap or after any other level.
fn next_paths(level: Level, from: u32, cap: u32, ms: f64) -> Option<Level> {
    let Level::Paths(n) = level else { return None };
    if n >= cap {
        return None;
    }
    let per_path = ms / f64::from(n.saturating_sub(from).max(1));
    // A float beyond u32's range saturates.
    let fits = (PATH_BATCH_MS / per_path.max(1e-9)).floor() as u32;
    let batch = n.min(fits).max(1).min(cap - n);
    Some(Level::Paths(n + batch))
}

/// The ΔE00 map between the two renderers' frames.
fn heat(a: &Renderer, b: &Renderer) -> Heat {
    let (Some(ta), Some(tb)) = (a.target(), b.target()) else {
        return Heat {
            pixels: Vec::new(),
            mean: 0.0,
            p95: 0.0,
        };
    };
    let (fa, fb) = (ta.resolve(), tb.resolve());
    let (ia, ib) = (
        LinearImage::from_framebuffer(&fa),
        LinearImage::from_framebuffer(&fb),
    );
    let de = delta_e_map(&ia, &ib);
    // The statistics are over the pixels either side drew something in: the background
    // (ΔE 0 wherever both clear to it) would dilute the mean and zero the percentile.
    let drawn: Vec<f64> = de
        .iter()
        .zip(fa.depth.iter().zip(&fb.depth))
        .filter(|(_, (a, b))| **a > 0.0 || **b > 0.0)
        .map(|(d, _)| *d)
        .collect();
    let (mean, p95) = mean_p95(&drawn);
    let pixels = de
        .iter()
        .map(|&d| {
            let [r, g, b] = heat_color(d);
            Color32::from_rgb(r, g, b)
        })
        .collect();
    Heat { pixels, mean, p95 }
}

#[cfg(test)]
mod tests {
    use super::{divisor, next_paths, record, Level, FRAME_BUDGET_MS, PATH_BATCH_MS, PATH_CAP};

    #[test]
    fn path_batches_double_within_the_batch_time_up_to_the_cap() {
        let quick = |level, from| next_paths(level, from, PATH_CAP, 1.0);
        let mut n = Level::Paths(1);
        let mut from = 0;
        let mut counts = vec![1];
        while let Some(next) = quick(n, from) {
            let Level::Paths(k) = next else { panic!() };
            (from, n) = (counts[counts.len() - 1], next);
            counts.push(k);
        }
        assert_eq!(counts, [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]);
        // A slow batch (8 paths in 4 batch times): the next adds 2 paths, not 16.
        let slow = next_paths(Level::Paths(16), 8, PATH_CAP, 4.0 * PATH_BATCH_MS);
        assert_eq!(slow, Some(Level::Paths(18)));
        // Slower than a batch time per path: one at a time.
        let slower = next_paths(Level::Paths(16), 8, PATH_CAP, 80.0 * PATH_BATCH_MS);
        assert_eq!(slower, Some(Level::Paths(17)));
        // The cap is not passed, and nothing follows other levels.
        assert_eq!(
            next_paths(Level::Paths(1000), 500, PATH_CAP, 1.0),
            Some(Level::Paths(1024))
        );
        assert_eq!(next_paths(Level::Paths(1), 0, 1, 1.0), None);
        assert_eq!(next_paths(Level::Full, 0, PATH_CAP, 1.0), None);
    }

    #[test]
    fn one_slow_full_frame_does_not_keep_later_frames_reduced() {
        let mut times = [None; 5];
        // A first full frame slowed far past the budget: the next is reduced.
        record(&mut times, 1, FRAME_BUDGET_MS * 5.0);
        assert!(divisor(&times) > 1);
        // The reduced frame is fast: full resolution cannot cost more than 4x that.
        let d = divisor(&times) as usize;
        record(&mut times, d, 0.1);
        assert_eq!(divisor(&times), 1, "{times:?}");
        assert!(times[1].unwrap() <= 0.1 * (d * d) as f64);
        // Times consistent with the pixel counts (fill bound: 4x; geometry bound: 1x) stay.
        let mut fill = [None, Some(40.0), None, None, None];
        record(&mut fill, 2, 10.0);
        assert_eq!(fill[1], Some(40.0));
        let mut geometry = [None, Some(40.0), None, None, None];
        record(&mut geometry, 2, 39.0);
        assert_eq!(geometry[1], Some(40.0));
        // A smaller image slower than twice a larger one is stale too.
        let mut small = [None, None, Some(500.0), None, None];
        record(&mut small, 1, 10.0);
        assert_eq!(small[2], Some(10.0));
    }
}
