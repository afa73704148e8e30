//! The viewer's threaded render host: coalesced jobs, progressive levels, a reduced first
//! frame while moving on a slow scene, and abandoned stale work.
//!
//! The worker calls its repaint callback after each frame it finishes (and once when a job
//! ends). Most tests make that callback a gate: the worker waits there until the test has
//! taken the frame, so no frame is missed however the threads are scheduled. Timeouts are
//! generous (a noisy 2-core machine); nothing waits for a fixed time.
#![cfg(feature = "viewer")]

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use realist::render::{default_camera, PreparedScene, Settings, View};
use realist::viewer::worker::{Frame, Job, Level, RenderHost, FRAME_BUDGET_MS, PATH_CAP};

/// Longest wait for anything the worker does.
const TIMEOUT: Duration = Duration::from_secs(30);

fn demo() -> Arc<PreparedScene> {
    Arc::new(PreparedScene::new(realist::scene::demo()))
}

/// The demo's default framing at `width` x `height`, turned `turn` radians about +Y.
fn view(scene: &PreparedScene, width: u32, height: u32, turn: f32) -> View {
    let mut camera = default_camera(scene.scene(), width as f32 / height as f32);
    let offset = camera.eye - camera.target;
    camera.eye = camera.target + glam::Quat::from_rotation_y(turn) * offset;
    View {
        camera,
        width,
        height,
    }
}

fn job(scene: &Arc<PreparedScene>, view: View, interactive: bool, max_samples: u32) -> Job {
    Job {
        scene: Arc::clone(scene),
        a: Arc::new(Settings::default()),
        b: None,
        heat: false,
        view,
        interactive,
        max_samples,
        proxy: None,
    }
}

/// A job path traced (`--shading path`).
fn path_job(scene: &Arc<PreparedScene>, view: View, max_samples: u32) -> Job {
    let settings = Settings {
        shading: Some(realist::shade::Shading::Path),
        ..Settings::default()
    };
    Job {
        a: Arc::new(settings),
        ..job(scene, view, false, max_samples)
    }
}

/// The repaint callback as a gate: each call waits until the test has looked.
#[derive(Default)]
struct Gate {
    state: Mutex<GateState>,
    changed: Condvar,
}

#[derive(Default)]
struct GateState {
    /// The worker is waiting in its repaint call.
    waiting: bool,
    /// The test is done: let the worker through from now on.
    open: bool,
}

impl Gate {
    /// The state, also after a panic elsewhere (a failed test must still shut down).
    fn state(&self) -> MutexGuard<'_, GateState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Waits on `changed` until `deadline`.
    fn sleep<'a>(
        &self,
        s: MutexGuard<'a, GateState>,
        deadline: Instant,
    ) -> MutexGuard<'a, GateState> {
        let left = deadline.saturating_duration_since(Instant::now());
        self.changed
            .wait_timeout(s, left)
            .map_or_else(|e| e.into_inner().0, |(s, _)| s)
    }

    /// The worker's side (its repaint call).
    fn pass(&self) {
        let mut s = self.state();
        if s.open {
            return;
        }
        s.waiting = true;
        self.changed.notify_all();
        let deadline = Instant::now() + TIMEOUT;
        while s.waiting && !s.open && Instant::now() < deadline {
            s = self.sleep(s, deadline);
        }
        s.waiting = false;
    }

    /// Waits until the worker is in its repaint call.
    fn wait(&self) {
        let deadline = Instant::now() + TIMEOUT;
        let mut s = self.state();
        while !s.waiting {
            if Instant::now() >= deadline {
                drop(s);
                panic!("no word from the worker in {TIMEOUT:?}");
            }
            s = self.sleep(s, deadline);
        }
    }

    /// Lets the worker go on.
    fn release(&self) {
        self.state().waiting = false;
        self.changed.notify_all();
    }

    fn open(&self) {
        self.state().open = true;
        self.changed.notify_all();
    }
}

/// A threaded host whose repaint calls go through a [`Gate`].
struct Gated {
    host: RenderHost,
    gate: Arc<Gate>,
}

impl Gated {
    fn new(threads: usize) -> Self {
        let gate = Arc::new(Gate::default());
        let g = Arc::clone(&gate);
        let host = RenderHost::threaded(threads, Arc::new(move || g.pass())).expect("worker");
        Self { host, gate }
    }

    /// The next frame the worker finishes (job ends without a frame are skipped).
    fn next_frame(&mut self) -> Frame {
        loop {
            self.gate.wait();
            let frame = self.host.take_frame();
            self.gate.release();
            if let Some(f) = frame {
                return f;
            }
        }
    }

    /// Every frame up to and including the first final frame of job `n`.
    fn frames_until_last_of(&mut self, n: u64) -> Vec<Frame> {
        let mut frames = Vec::new();
        loop {
            let f = self.next_frame();
            let done = f.job == n && f.last;
            frames.push(f);
            if done {
                return frames;
            }
        }
    }
}

impl Drop for Gated {
    fn drop(&mut self) {
        // Before the host joins its thread, which may be waiting at the gate.
        self.gate.open();
    }
}

/// Waits (up to [`TIMEOUT`]) until the worker has nothing to do.
fn wait_idle(host: &RenderHost) {
    let deadline = Instant::now() + TIMEOUT;
    while host.busy() {
        assert!(Instant::now() < deadline, "the worker settles");
        std::thread::sleep(Duration::from_millis(2));
    }
}

fn levels(frames: &[Frame]) -> Vec<(u64, Level, bool)> {
    frames.iter().map(|f| (f.job, f.level, f.last)).collect()
}

#[test]
fn a_burst_of_jobs_is_coalesced() {
    let scene = demo();
    let mut w = Gated::new(2);
    let jobs: Vec<Job> = (0..50)
        .map(|i| job(&scene, view(&scene, 960, 600, i as f32 * 0.01), false, 1))
        .collect();
    let newest = jobs[49].view.clone();
    for j in jobs {
        w.host.submit(j);
    }
    assert_eq!(w.host.submitted(), 50);
    let frames = w.frames_until_last_of(50);
    assert!(
        frames.len() <= 5,
        "50 jobs coalesce into a few frames, not {:?}",
        levels(&frames)
    );
    assert!(frames.windows(2).all(|p| p[0].job < p[1].job));
    let last = frames.last().unwrap();
    assert_eq!(last.view, newest, "the last frame shows the newest job");
    assert_eq!(last.level, Level::Full);
    // Nothing else follows.
    w.gate.open();
    wait_idle(&w.host);
    assert!(w.host.take_frame().is_none());
}

#[test]
fn a_burst_of_jobs_renders_far_fewer_frames_ungated() {
    // Without the gate (the worker never waits): count the repaint calls, one per frame
    // and one per job started, and poll for the newest job's frame as the UI does.
    let scene = demo();
    let repaints = Arc::new(AtomicUsize::new(0));
    let r = Arc::clone(&repaints);
    let mut host = RenderHost::threaded(
        2,
        Arc::new(move || {
            r.fetch_add(1, Ordering::SeqCst);
        }),
    )
    .expect("worker");
    let jobs: Vec<Job> = (0..50)
        .map(|i| job(&scene, view(&scene, 960, 600, i as f32 * 0.01), false, 1))
        .collect();
    let newest = jobs[49].view.clone();
    for j in jobs {
        host.submit(j);
    }
    let deadline = Instant::now() + TIMEOUT;
    let last = loop {
        if let Some(f) = host.take_frame() {
            if f.job == 50 {
                break f;
            }
        }
        assert!(Instant::now() < deadline, "no frame of the newest job");
        std::thread::sleep(Duration::from_millis(2));
    };
    assert!(last.last && last.view == newest);
    while host.busy() {
        assert!(Instant::now() < deadline, "the worker settles");
        std::thread::sleep(Duration::from_millis(2));
    }
    let calls = repaints.load(Ordering::SeqCst);
    assert!(calls <= 10, "{calls} repaints for 50 jobs");
}

#[test]
fn progressive_levels_arrive_coarse_to_fine() {
    let scene = demo();
    let mut w = Gated::new(2);
    let mut n = 0;
    for (max_samples, expected) in [
        (
            4,
            vec![Level::Full, Level::Supersampled(2), Level::Supersampled(4)],
        ),
        (2, vec![Level::Full, Level::Supersampled(2)]),
        (1, vec![Level::Full]),
    ] {
        let v = view(&scene, 320, 200, n as f32 * 0.1);
        w.host.submit(job(&scene, v.clone(), false, max_samples));
        n += 1;
        let frames = w.frames_until_last_of(n);
        let got: Vec<Level> = frames.iter().map(|f| f.level).collect();
        assert_eq!(got, expected, "max_samples {max_samples}");
        for (i, f) in frames.iter().enumerate() {
            assert_eq!(f.job, n);
            assert_eq!(f.last, i + 1 == frames.len(), "only the finest is last");
            assert_eq!(f.view, v, "every level at full resolution");
            let samples = match f.level {
                Level::Supersampled(s) => s,
                _ => 1,
            };
            assert_eq!(f.a.report.samples, samples);
            assert_eq!(f.a.pixels.len(), 320 * 200);
        }
    }
}

#[test]
fn an_interactive_job_on_a_slow_scene_starts_at_a_reduced_resolution() {
    let scene = demo();
    // One render thread and a big frame (bigger if that was not enough, up to 3600 x 2250,
    // 8 Mpixels): full resolution takes longer than the budget. The worker times the full
    // frames it renders and plans the next interactive job from the last one.
    let mut w = Gated::new(1);
    let (mut width, mut height) = (2400, 1500);
    let mut n = 0;
    let full_ms = loop {
        w.host
            .submit(job(&scene, view(&scene, width, height, 0.0), false, 1));
        n += 1;
        let frames = w.frames_until_last_of(n);
        assert_eq!(levels(&frames), [(n, Level::Full, true)]);
        let ms = frames[0].a.report.times.total;
        if ms > 2.0 * FRAME_BUDGET_MS || n == 2 {
            break ms;
        }
        (width, height) = (width * 3 / 2, height * 3 / 2);
    };
    assert!(
        full_ms > FRAME_BUDGET_MS,
        "a {width}x{height} frame should be slow, took {full_ms} ms"
    );
    let v = view(&scene, width, height, 0.2);
    w.host.submit(job(&scene, v.clone(), true, 1));
    n += 1;
    let frames = w.frames_until_last_of(n);
    let first = &frames[0];
    let Level::Reduced(d) = first.level else {
        panic!("the first frame is reduced: {:?}", levels(&frames));
    };
    assert!((2..=4).contains(&d), "divisor {d}");
    assert_eq!(
        [first.view.width, first.view.height],
        [width / d, height / d]
    );
    assert_eq!(first.view.camera, v.camera);
    assert!(!first.last);
    // With no newer job, the full-resolution frame follows.
    assert_eq!(
        levels(&frames[1..]),
        [(n, Level::Full, true)],
        "refined after the settle time"
    );
    assert_eq!(frames[1].view, v);
}

#[test]
fn a_new_job_abandons_the_one_in_progress() {
    let scene = demo();
    let mut w = Gated::new(2);
    let old = view(&scene, 960, 600, 0.0);
    w.host.submit(job(&scene, old, false, 4));
    let first = w.next_frame();
    assert_eq!(
        (first.job, first.level, first.last),
        (1, Level::Full, false)
    );
    // The worker goes on to 2x2 and then 4x4 for job 1; job 2 arrives meanwhile.
    let new = view(&scene, 960, 600, 0.5);
    w.host.submit(job(&scene, new.clone(), false, 1));
    let frames = w.frames_until_last_of(2);
    assert!(
        frames.iter().all(|f| !(f.job == 1 && f.last)),
        "job 1's final level never arrives: {:?}",
        levels(&frames)
    );
    assert!(
        frames
            .iter()
            .all(|f| f.job == 2 || f.level == Level::Supersampled(2)),
        "{:?}",
        levels(&frames)
    );
    let last = frames.last().unwrap();
    assert_eq!((last.level, &last.view), (Level::Full, &new));
    // And nothing of job 1 comes later.
    w.gate.open();
    wait_idle(&w.host);
    assert!(w.host.take_frame().is_none());
}

#[test]
fn a_drag_faster_than_frames_still_shows_frames() {
    // Interactive jobs every 3 ms (a fast mouse) on frames that take longer than that (a
    // 262,000-triangle sphere on one thread: geometry-bound at any resolution): each job's
    // first frame is finished rather than abandoned for the next job (which would leave the
    // screen frozen for the whole drag), so frames keep arriving.
    let setup = realist::quality::sphere::SphereSetup::standard(1280, 720);
    let scene = Arc::new(PreparedScene::new(setup.scene(512, 256).expect("sphere")));
    let mut host = RenderHost::threaded(1, Arc::new(|| {})).expect("worker");
    let drag = Duration::from_millis(1500);
    let start = Instant::now();
    let (mut times, mut k) = (Vec::new(), 0);
    while start.elapsed() < drag {
        host.submit(job(
            &scene,
            view(&scene, 1280, 720, k as f32 * 0.003),
            true,
            1,
        ));
        k += 1;
        if let Some(f) = host.take_frame() {
            times.push(f.a.report.times.total);
        }
        std::thread::sleep(Duration::from_millis(3));
    }
    times.sort_by(f64::total_cmp);
    let median = times.get(times.len() / 2).copied().unwrap_or(f64::NAN);
    eprintln!(
        "{k} jobs, {} frames shown during the drag, median {median:.1} ms",
        times.len()
    );
    assert!(
        median > 6.0,
        "frames must be slower than the jobs for this test: {median} ms"
    );
    assert!(
        times.len() >= 5,
        "{} frames for {k} jobs in {drag:?}",
        times.len()
    );
    wait_idle(&host);
}

/// A 2,000,000-triangle sphere dragged at 100 mouse events a second on two threads: the
/// moving frames are drawn from its simplified copy (about 250,000 triangles, made once),
/// so they keep coming. Prints the intervals between frames (the README quotes a run);
/// asserts, loosely enough for a shared machine, one frame per 200 ms on average and that
/// every moving frame was the simplified copy's.
#[test]
fn a_two_million_triangle_drag_is_drawn_from_a_simplified_copy() {
    use realist::viewer::worker::{PROXY_ABOVE, PROXY_TRIANGLES};
    let setup = realist::quality::sphere::SphereSetup::standard(1280, 720);
    let scene = Arc::new(PreparedScene::new(setup.scene(1000, 1000).expect("sphere")));
    assert!(
        scene.triangle_count() >= 2 * PROXY_ABOVE - 10_000,
        "{}",
        scene.triangle_count()
    );
    let t = Instant::now();
    let proxy = Arc::new(scene.simplified(PROXY_TRIANGLES).expect("simplified"));
    let made = t.elapsed();
    let kept = proxy.triangle_count();
    eprintln!(
        "simplified {} triangles to {kept} in {:.0} ms",
        scene.triangle_count(),
        made.as_secs_f64() * 1e3
    );
    assert!(
        kept <= PROXY_TRIANGLES && kept * 2 >= PROXY_TRIANGLES,
        "{kept}"
    );
    let mut host = RenderHost::threaded(2, Arc::new(|| {})).expect("worker");
    let drag = Duration::from_millis(3000);
    let start = Instant::now();
    let (mut arrivals, mut levels, mut k) = (Vec::new(), Vec::new(), 0);
    while start.elapsed() < drag {
        host.submit(Job {
            proxy: Some(Arc::clone(&proxy)),
            ..job(&scene, view(&scene, 1280, 720, k as f32 * 0.01), true, 1)
        });
        k += 1;
        if let Some(f) = host.take_frame() {
            arrivals.push(start.elapsed().as_secs_f64() * 1e3);
            levels.push(f.level);
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let mut gaps: Vec<f64> = arrivals.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_by(f64::total_cmp);
    let at = |q: f64| {
        gaps.get(((gaps.len() as f64 - 1.0) * q) as usize)
            .copied()
            .unwrap_or(f64::NAN)
    };
    eprintln!(
        "{k} jobs in {drag:?}: {} frames, gaps median {:.1} ms, 95th percentile {:.1} ms, max {:.1} ms; levels {:?}",
        arrivals.len(),
        at(0.5),
        at(0.95),
        at(1.0),
        levels
            .iter()
            .map(|l| l.label())
            .collect::<std::collections::BTreeSet<_>>()
    );
    assert!(
        arrivals.len() as f64 >= drag.as_secs_f64() * 1e3 / 200.0,
        "{} frames in {drag:?}",
        arrivals.len()
    );
    assert!(
        levels.iter().all(|l| matches!(l, Level::Simplified(_))),
        "{levels:?}"
    );
    wait_idle(&host);
}

/// Playing an animation sends a job per frame as a moving camera does (interactive): when
/// a full frame is cheap (here `models/anim/skin8.glb`, a skinned mesh, at 640 x 400), every
/// frame of the playback is drawn at full resolution, never reduced.
#[test]
fn an_animation_with_cheap_frames_plays_at_full_resolution() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/anim/skin8.glb");
    let loaded = realist::load::load(&path, &realist::load::LoadOptions::default()).expect("skin8");
    assert!(!loaded.animations.is_empty(), "an animated file");
    let base = PreparedScene::new(loaded);
    let v = view(&base, 640, 400, 0.0);
    let mut host = RenderHost::threaded(2, Arc::new(|| {})).expect("worker");
    let (mut frames, mut times) = (Vec::new(), Vec::new());
    for k in 0..60 {
        let mut posed = base.clone();
        posed.pose_at(realist::scene::Play::All, k as f32 / 30.0, true);
        host.submit(job(&Arc::new(posed), v.clone(), true, 1));
        std::thread::sleep(Duration::from_millis(16));
        if let Some(f) = host.take_frame() {
            times.push(f.a.report.times.total);
            frames.push(f.level);
        }
    }
    wait_idle(&host);
    times.sort_by(f64::total_cmp);
    let median = times.get(times.len() / 2).copied().unwrap_or(f64::NAN);
    eprintln!(
        "{} frames of 60, median {median:.2} ms: {frames:?}",
        frames.len()
    );
    assert!(
        median < 10.0,
        "the premise: a full frame costs under 10 ms ({median} ms)"
    );
    assert!(frames.len() >= 10, "{} frames", frames.len());
    // Full resolution throughout, but for a frame right after one that a busy machine
    // slowed past the budget (the next is planned smaller, and the one after is full
    // again): at most one in ten, never two in a row.
    let reduced = frames.iter().filter(|l| **l != Level::Full).count();
    assert!(
        reduced * 10 <= frames.len(),
        "{reduced} reduced: {frames:?}"
    );
    assert!(
        frames
            .windows(2)
            .all(|w| w[0] == Level::Full || w[1] == Level::Full),
        "two reduced frames in a row: {frames:?}"
    );
}

#[test]
fn the_split_views_difference_statistics_are_over_the_drawn_pixels() {
    let scene = demo();
    let v = view(&scene, 160, 100, 0.0);
    let heat_of = |b: Settings| {
        let mut host = RenderHost::synchronous();
        host.submit(Job {
            b: Some(Arc::new(b)),
            heat: true,
            ..job(&scene, v.clone(), false, 1)
        });
        let frame = host.take_frame().expect("a frame");
        let drawn = frame.depth.iter().filter(|d| **d > 0.0).count();
        (frame.heat.expect("the difference map"), drawn)
    };
    // B differs from A only behind the model: the map shows the background differing,
    // the statistics (over the model's pixels) say the model is the same.
    let (heat, drawn) = heat_of(Settings {
        background: glam::Vec4::new(0.8, 0.1, 0.1, 1.0),
        ..Settings::default()
    });
    assert!(
        drawn > 1000 && drawn < 160 * 100 / 2,
        "{drawn} drawn pixels"
    );
    assert_eq!(heat.pixels.len(), 160 * 100);
    let lit = heat
        .pixels
        .iter()
        .filter(|c| [c.r(), c.g(), c.b()] != [0, 0, 0])
        .count();
    assert!(
        lit >= 160 * 100 - drawn,
        "the background differs: {lit} pixels"
    );
    assert_eq!((heat.mean, heat.p95), (0.0, 0.0));
    // Flat against Phong differs on the model.
    let (heat, _) = heat_of(Settings {
        shading: Some(realist::shade::Shading::Flat),
        ..Settings::default()
    });
    assert!(
        heat.p95 > 0.0 && heat.mean > 0.01,
        "mean {} p95 {}",
        heat.mean,
        heat.p95
    );
}

#[test]
fn a_path_job_counts_paths_up_to_the_cap_then_idles() {
    let scene = demo();
    let mut w = Gated::new(2);
    let v = view(&scene, 64, 40, 0.3);
    w.host.submit(path_job(&scene, v.clone(), 4));
    let frames = w.frames_until_last_of(1);
    let counts: Vec<u32> = frames
        .iter()
        .map(|f| match f.level {
            Level::Paths(n) => n,
            other => panic!("a path job shows paths, not {other:?}"),
        })
        .collect();
    // One path, then batches that double while they are quick (a small frame: always).
    assert_eq!(counts[..3], [1, 2, 4], "{counts:?}");
    assert!(counts.windows(2).all(|p| p[0] < p[1]), "{counts:?}");
    assert!(
        counts.windows(2).all(|p| p[1] <= 2 * p[0]),
        "batches at most double: {counts:?}"
    );
    assert_eq!(*counts.last().unwrap(), PATH_CAP);
    assert_eq!(frames.iter().filter(|f| f.last).count(), 1);
    assert!(frames
        .iter()
        .all(|f| f.view == v && f.a.pixels.len() == 64 * 40));
    assert_eq!(
        frames.last().unwrap().level.label(),
        "path: 1024 paths per pixel"
    );
    // Nothing follows: the worker is idle.
    w.gate.open();
    wait_idle(&w.host);
    assert!(w.host.take_frame().is_none());
    // The sum of the batches is the image of the 1,024 paths in one go (the synchronous
    // host renders the final level at once).
    let mut sync = RenderHost::synchronous();
    sync.submit(path_job(&scene, v, 4));
    let once = sync.take_frame().expect("a frame");
    assert_eq!((once.level, once.last), (Level::Paths(PATH_CAP), true));
    assert!(once.a.pixels == frames.last().unwrap().a.pixels);
    // With refinement off, one path per pixel and no more.
    sync.submit(path_job(&scene, view(&scene, 64, 40, 0.3), 1));
    let one = sync.take_frame().expect("a frame");
    assert_eq!(one.level, Level::Paths(1));
    assert!(one.a.pixels == frames[0].a.pixels);
}

#[test]
fn a_new_job_abandons_the_path_sum_and_starts_from_zero() {
    let scene = demo();
    let mut w = Gated::new(2);
    // Big enough that the sum is far from its cap when job 2 arrives.
    w.host
        .submit(path_job(&scene, view(&scene, 320, 200, 0.0), 4));
    let first = w.next_frame();
    assert_eq!((first.job, first.level), (1, Level::Paths(1)));
    let second = w.next_frame();
    assert_eq!((second.job, second.level), (1, Level::Paths(2)));
    let new = view(&scene, 320, 200, 0.5);
    w.host.submit(path_job(&scene, new.clone(), 1));
    let frames = w.frames_until_last_of(2);
    assert!(
        frames.iter().all(|f| !(f.job == 1 && f.last)),
        "job 1 never reaches its cap: {:?}",
        levels(&frames)
    );
    let last = frames.last().unwrap();
    assert_eq!((last.level, &last.view), (Level::Paths(1), &new));
    // Job 2's one path is a fresh sum, not job 1's continued.
    let mut sync = RenderHost::synchronous();
    sync.submit(path_job(&scene, new, 1));
    assert!(sync.take_frame().expect("a frame").a.pixels == last.a.pixels);
    w.gate.open();
    wait_idle(&w.host);
    assert!(w.host.take_frame().is_none());
}

#[test]
fn a_split_view_beside_a_path_job_keeps_its_raster_image_and_heat_map() {
    let scene = demo();
    let mut w = Gated::new(2);
    let v = view(&scene, 64, 40, 0.3);
    w.host.submit(Job {
        b: Some(Arc::new(Settings::default())),
        heat: true,
        ..path_job(&scene, v.clone(), 4)
    });
    let frames = w.frames_until_last_of(1);
    assert_eq!(frames.last().unwrap().level, Level::Paths(PATH_CAP));
    assert!(
        frames.iter().all(|f| f.heat.is_some()),
        "a heat map each batch"
    );
    let b: Vec<&Frame> = frames.iter().collect();
    // B is drawn with one sample beside the first path, 4x4 beside the second, then kept.
    let report = |f: &Frame| f.b.as_ref().expect("B").report.samples;
    assert_eq!((report(b[0]), report(b[1])), (1, 4));
    let second = &b[1].b.as_ref().unwrap().pixels;
    assert!(b[2..]
        .iter()
        .all(|f| &f.b.as_ref().unwrap().pixels == second));
    // The heat map follows A's accumulation: the difference changes as the noise falls.
    let mean = |f: &Frame| f.heat.as_ref().unwrap().mean;
    assert!(mean(b[1]) != mean(frames.last().unwrap()));
    w.gate.open();
    wait_idle(&w.host);
}
