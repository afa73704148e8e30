//! `render` and `render_many`: the GIL released while realist works, on a rayon pool of
//! the size asked for (every core by default).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use pyo3::exceptions::{PyFileNotFoundError, PyTypeError, PyValueError};
use pyo3::prelude::*;

use realist::shade::Shading;

use crate::camera::Camera;
use crate::frame::{render_job, Frame, Job, Rendered, Source};
use crate::options::{self, Options};
use crate::scene::{LoadFailure, Scene};

/// Pools by thread count, made once and kept (a pool per call would start threads every
/// call).
static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());

/// Runs `f` on a pool of `threads` workers (`None`: rayon's global pool, every core).
fn on_pool<R: Send>(threads: Option<usize>, f: impl FnOnce() -> R + Send) -> Result<R, String> {
    let Some(n) = threads else {
        return Ok(f());
    };
    let pool = {
        let mut pools = POOLS.lock().unwrap_or_else(PoisonError::into_inner);
        match pools.iter().find(|(k, _)| *k == n) {
            Some((_, p)) => Arc::clone(p),
            None => {
                let p = rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .thread_name(|i| format!("realist-{i}"))
                    .build()
                    .map_err(|e| format!("could not start {n} worker threads: {e}"))?;
                let p = Arc::new(p);
                pools.push((n, Arc::clone(&p)));
                p
            }
        }
    };
    Ok(pool.install(f))
}

/// A size given that differs from the one a camera from intrinsics was calibrated for.
fn check_size(opts: &Options, camera: Option<&Camera>) -> PyResult<()> {
    match (opts.size, Camera::wanted_size(camera)) {
        (Some((w, h)), Some((cw, ch))) if (w, h) != (cw, ch) => Err(PyValueError::new_err(
            format!("the camera's intrinsics are for a {cw}x{ch} image, but size is {w}x{h}"),
        )),
        _ => Ok(()),
    }
}

/// Pools of one thread each, made once and kept: `render_many`'s workers.
static SINGLES: Mutex<Vec<Arc<rayon::ThreadPool>>> = Mutex::new(Vec::new());

/// `n` pools of one thread each.
fn single_pools(n: usize) -> Result<Vec<Arc<rayon::ThreadPool>>, String> {
    let mut pools = SINGLES.lock().unwrap_or_else(PoisonError::into_inner);
    while pools.len() < n {
        let k = pools.len();
        let p = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .thread_name(move |_| format!("realist-many-{k}"))
            .build()
            .map_err(|e| format!("could not start worker thread {k}: {e}"))?;
        pools.push(Arc::new(p));
    }
    Ok(pools[..n].to_vec())
}

/// Renders every job, in order. With at least as many jobs as threads, each of `threads`
/// workers renders whole frames one after another, each frame on one thread (frames in
/// parallel need no parallelism inside a frame, and nested parallel loops made a batch
/// several times slower); with fewer, the frames are rendered one after another, each over
/// every thread.
fn run_many(jobs: &[Job], opts: &Options) -> Result<Vec<Result<Rendered, LoadFailure>>, String> {
    let threads = opts
        .threads
        .unwrap_or_else(rayon::current_num_threads)
        .max(1);
    if jobs.len() < threads {
        return on_pool(opts.threads, || {
            jobs.iter().map(|j| guarded(j, opts)).collect()
        });
    }
    let pools = single_pools(threads)?;
    let next = AtomicUsize::new(0);
    let mut out: Vec<Option<Result<Rendered, LoadFailure>>> = jobs.iter().map(|_| None).collect();
    std::thread::scope(|s| {
        let workers: Vec<_> = pools
            .iter()
            .map(|pool| {
                let next = &next;
                s.spawn(move || {
                    pool.install(|| {
                        let mut done = Vec::new();
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            let Some(job) = jobs.get(i) else { break };
                            done.push((i, guarded(job, opts)));
                        }
                        done
                    })
                })
            })
            .collect();
        for w in workers {
            // A worker's own panics are caught per job; a failed join leaves its slots empty.
            for (i, r) in w.join().unwrap_or_default() {
                out[i] = Some(r);
            }
        }
    });
    Ok(out
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Err(LoadFailure::Other("a worker thread failed".into()))))
        .collect())
}

/// [`render_job`] with a panic caught and reported as an error.
fn guarded(job: &Job, opts: &Options) -> Result<Rendered, LoadFailure> {
    match catch_unwind(AssertUnwindSafe(|| render_job(job, opts))) {
        Ok(r) => r,
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_else(|| "unknown panic".into());
            Err(LoadFailure::Other(format!("realist panicked: {msg}")))
        }
    }
}

/// A scene argument: a `Scene`, or a path (str or os.PathLike) to load.
fn source(v: &Bound<'_, PyAny>) -> PyResult<Source> {
    if let Ok(s) = v.cast::<Scene>() {
        return Ok(Source::Scene(Arc::clone(&s.get().prepared)));
    }
    match v.extract::<PathBuf>() {
        Ok(p) => Ok(Source::Path(p)),
        Err(_) => Err(PyTypeError::new_err(format!(
            "expected a realist.Scene or a path (str or os.PathLike), got {}",
            v.get_type().name()?
        ))),
    }
}

/// A camera argument: None or a `Camera`.
fn camera(v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Camera>> {
    match v {
        None => Ok(None),
        Some(v) if v.is_none() => Ok(None),
        Some(v) => match v.cast::<Camera>() {
            Ok(c) => Ok(Some(c.get().clone())),
            Err(_) => Err(PyTypeError::new_err(format!(
                "camera: expected a realist.Camera or None, got {}",
                v.get_type().name()?
            ))),
        },
    }
}

/// Renders one frame of a model file or a Scene and returns it as numpy arrays.
///
/// The keyword arguments are those of `realist render` (see the stubs for each). The GIL
/// is released while rendering; the frame uses `threads` worker threads (default: every
/// core), and the image does not depend on how many.
#[pyfunction]
#[pyo3(signature = (scene, size=None, camera=None, *, shading=None, env=None, env_background=None,
                    background=None, msaa=1, samples=1, exposure=None, tone=None,
                    double_sided=false, ground=false, shadows=false, up="y", ids=true, threads=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    size: Option<(i64, i64)>,
    camera: Option<&Bound<'_, PyAny>>,
    shading: Option<&str>,
    env: Option<&str>,
    env_background: Option<f64>,
    background: Option<&Bound<'_, PyAny>>,
    msaa: u32,
    samples: u32,
    exposure: Option<f64>,
    tone: Option<&str>,
    double_sided: bool,
    ground: bool,
    shadows: bool,
    up: &str,
    ids: bool,
    threads: Option<usize>,
) -> PyResult<Frame> {
    let opts = options::parse(
        size,
        shading,
        env,
        env_background,
        background,
        msaa,
        samples,
        exposure,
        tone,
        double_sided,
        ground,
        shadows,
        up,
        ids,
        threads,
    )?;
    let job = Job {
        source: source(scene)?,
        camera: self::camera(camera)?,
    };
    check_size(&opts, job.camera.as_ref())?;
    let rendered = py
        .detach(|| on_pool(opts.threads, || guarded(&job, &opts)))
        .map_err(crate::RealistError::new_err)?
        .map_err(LoadFailure::into_py)?;
    Frame::new(py, rendered)
}

/// Renders many frames at once, over every core (or `threads`), with the GIL released:
/// `items` is a list of Scenes or paths, or of (Scene or path, Camera) pairs. Returns the
/// Frames in the order of `items`. Takes the keyword arguments of `render`, applied to
/// every frame.
///
/// A failing item raises (FileNotFoundError or RealistError) naming its index; no frames
/// are returned then.
#[pyfunction]
#[pyo3(signature = (items, size=None, *, shading=None, env=None, env_background=None,
                    background=None, msaa=1, samples=1, exposure=None, tone=None,
                    double_sided=false, ground=false, shadows=false, up="y", ids=true, threads=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_many(
    py: Python<'_>,
    items: &Bound<'_, PyAny>,
    size: Option<(i64, i64)>,
    shading: Option<&str>,
    env: Option<&str>,
    env_background: Option<f64>,
    background: Option<&Bound<'_, PyAny>>,
    msaa: u32,
    samples: u32,
    exposure: Option<f64>,
    tone: Option<&str>,
    double_sided: bool,
    ground: bool,
    shadows: bool,
    up: &str,
    ids: bool,
    threads: Option<usize>,
) -> PyResult<Vec<Frame>> {
    let opts = options::parse(
        size,
        shading,
        env,
        env_background,
        background,
        msaa,
        samples,
        exposure,
        tone,
        double_sided,
        ground,
        shadows,
        up,
        ids,
        threads,
    )?;
    if items.is_instance_of::<pyo3::types::PyString>() || items.cast::<Scene>().is_ok() {
        return Err(PyTypeError::new_err(
            "render_many takes a list of scenes, paths or (scene, camera) pairs; render takes one",
        ));
    }
    let mut jobs = Vec::new();
    for (i, item) in items.try_iter()?.enumerate() {
        let item = item?;
        let (scene, cam) = options::split_item(&item)?;
        let job = source(&scene)
            .and_then(|s| Ok((s, camera(cam.as_ref())?)))
            .map_err(|e| PyTypeError::new_err(format!("render_many item {i}: {}", e.value(py))))?;
        check_size(&opts, job.1.as_ref())
            .map_err(|e| PyValueError::new_err(format!("render_many item {i}: {}", e.value(py))))?;
        jobs.push(Job {
            source: job.0,
            camera: job.1,
        });
    }
    let results = py
        .detach(|| run_many(&jobs, &opts))
        .map_err(crate::RealistError::new_err)?;
    let mut frames = Vec::with_capacity(results.len());
    for (i, r) in results.into_iter().enumerate() {
        match r {
            Ok(r) => frames.push(Frame::new(py, r)?),
            Err(LoadFailure::NotFound(m)) => {
                return Err(PyFileNotFoundError::new_err(format!(
                    "render_many item {i}: {m}"
                )))
            }
            Err(e) => {
                return Err(crate::RealistError::new_err(format!(
                    "render_many item {i}: {}",
                    e.message()
                )))
            }
        }
    }
    Ok(frames)
}

/// The names `shading=` takes, in the order `realist render --help` lists them.
#[pyfunction]
pub(crate) fn shading_modes() -> Vec<&'static str> {
    Shading::ALL.iter().map(|m| m.name()).collect()
}
