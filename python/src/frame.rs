//! One frame: rendered into plain buffers without Python (so `render_many` runs many at
//! once with the GIL released), then handed to Python as a `Frame` of numpy arrays.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyArray3};
use pyo3::prelude::*;
use rayon::prelude::*;

use realist::color::{unorm8, Srgb8Table};
use realist::render::rays::unkey;
use realist::render::{PreparedScene, Renderer, View};
use realist::scene::Camera as RCamera;
use realist::scenefile;
use realist::trace::Ray;

use crate::camera::Camera;
use crate::options::Options;
use crate::scene::{LoadFailure, Scene};

/// What to draw: a scene already prepared, or a file to load first.
pub(crate) enum Source {
    Scene(Arc<PreparedScene>),
    Path(PathBuf),
}

/// One frame to render.
pub(crate) struct Job {
    pub source: Source,
    pub camera: Option<Camera>,
}

/// A rendered frame in plain buffers, row-major, top row first.
pub(crate) struct Rendered {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
    pub linear: Vec<f32>,
    pub depth: Vec<f32>,
    pub ids: Option<Vec<i32>>,
    pub camera: RCamera,
}

/// Renders `job` with `opts` on the current rayon pool.
pub(crate) fn render_job(job: &Job, opts: &Options) -> Result<Rendered, LoadFailure> {
    let loaded;
    let prepared: &PreparedScene = match &job.source {
        Source::Scene(p) => p,
        Source::Path(path) => {
            loaded = Scene::load_path(path)?;
            &loaded.prepared
        }
    };
    let scene = prepared.scene();
    let (w, h) = opts
        .size
        .or_else(|| Camera::wanted_size(job.camera.as_ref()))
        .unwrap_or(scenefile::DEFAULT_SIZE);
    let camera =
        Camera::resolve(job.camera.as_ref(), scene, (w, h), opts.up).map_err(LoadFailure::Other)?;
    let mut settings = opts.settings.clone();
    if opts.shadows {
        settings.lights = scenefile::shadow_every_light(&settings.lights, prepared.lights());
    }
    let view = View {
        camera,
        width: w,
        height: h,
    };
    let mut renderer = Renderer::new();
    renderer.render(prepared, &settings, &view);
    let target = renderer
        .target()
        .ok_or_else(|| LoadFailure::Other("no frame was rendered".into()))?;
    let fb = target.resolve();
    let lut = Srgb8Table::get();
    let n = fb.color.len();
    let mut rgba = vec![0u8; n * 4];
    let mut linear = vec![0f32; n * 4];
    rgba.par_chunks_mut(4)
        .zip(linear.par_chunks_mut(4))
        .zip(&fb.color)
        .for_each(|((px, lin), c)| {
            px.copy_from_slice(&[
                lut.encode(c.x),
                lut.encode(c.y),
                lut.encode(c.z),
                unorm8(c.w),
            ]);
            lin.copy_from_slice(&c.to_array());
        });
    let proj = view.camera.projection(view.aspect()).as_dmat4();
    let depth = view_depth(&fb.depth, proj.inverse());
    let ids = opts
        .ids
        .then(|| instance_ids(prepared, &settings, &view, &fb.depth));
    Ok(Rendered {
        width: w,
        height: h,
        rgba,
        linear,
        depth,
        ids,
        camera: view.camera,
    })
}

/// The depth buffer (reversed-Z z/w, 0 where nothing was drawn) as the distance in front of
/// the camera along its line of sight (view-space -z), infinity where nothing was drawn.
fn view_depth(depth: &[f32], inv_proj: DMat4) -> Vec<f32> {
    depth
        .par_iter()
        .map(|&d| {
            if d > 0.0 && d.is_finite() {
                // x and y do not change view z for these projections: the centre will do.
                let p = inv_proj.project_point3(DVec3::new(0.0, 0.0, f64::from(d)));
                (-p.z) as f32
            } else {
                f32::INFINITY
            }
        })
        .collect()
}

/// The scene instance seen at each pixel centre (a ray through it, cast against the
/// instances the frame shows), -1 for the background and the ground plane. Pixels where the
/// rasterizer drew nothing are -1 without a ray.
fn instance_ids(
    prepared: &PreparedScene,
    settings: &realist::render::Settings,
    view: &View,
    depth: &[f32],
) -> Vec<i32> {
    let rays = prepared.rays(settings);
    let (w, h) = (view.width, view.height);
    let vp = view.camera.projection(view.aspect()) * view.camera.view();
    let inv = vp.as_dmat4().inverse();
    let count = prepared.scene().instances.len();
    let mut ids = vec![-1i32; depth.len()];
    ids.par_chunks_mut(w as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, id) in row.iter_mut().enumerate() {
                if depth[y * w as usize + x] <= 0.0 {
                    continue;
                }
                let ndc = glam::DVec2::new(
                    (x as f64 + 0.5) / f64::from(w) * 2.0 - 1.0,
                    1.0 - (y as f64 + 0.5) / f64::from(h) * 2.0,
                );
                // Reversed Z: the near plane at 1, the far plane at 0.
                let near = inv.project_point3(ndc.extend(1.0));
                let far = inv.project_point3(ndc.extend(0.0));
                let reach = (far - near).length();
                let dir = ((far - near) / reach).as_vec3();
                let ray = Ray::new(near.as_vec3(), dir, 0.0, reach as f32);
                if let Some(hit) = rays.closest(&ray) {
                    let (k, _) = unkey(hit.key);
                    if k < count {
                        *id = k as i32;
                    }
                }
            }
        });
    ids
}

/// A rendered image and its buffers as numpy arrays (rows top first, C order).
#[pyclass(module = "realist", frozen)]
pub struct Frame {
    rgba: Py<PyArray3<u8>>,
    linear: Py<PyArray3<f32>>,
    depth: Py<PyArray2<f32>>,
    ids: Option<Py<PyArray2<i32>>>,
    width: u32,
    height: u32,
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    fov_y_degrees: f32,
}

impl Frame {
    pub(crate) fn new(py: Python<'_>, r: Rendered) -> PyResult<Frame> {
        let (w, h) = (r.width as usize, r.height as usize);
        let shape = |e: numpy::ndarray::ShapeError| {
            crate::RealistError::new_err(format!("frame buffers do not match {w}x{h}: {e}"))
        };
        let rgba = Array3::from_shape_vec((h, w, 4), r.rgba).map_err(shape)?;
        let linear = Array3::from_shape_vec((h, w, 4), r.linear).map_err(shape)?;
        let depth = Array2::from_shape_vec((h, w), r.depth).map_err(shape)?;
        let ids = r
            .ids
            .map(|v| Array2::from_shape_vec((h, w), v).map_err(shape))
            .transpose()?;
        Ok(Frame {
            rgba: rgba.into_pyarray(py).unbind(),
            linear: linear.into_pyarray(py).unbind(),
            depth: depth.into_pyarray(py).unbind(),
            ids: ids.map(|a| a.into_pyarray(py).unbind()),
            width: r.width,
            height: r.height,
            eye: r.camera.eye,
            target: r.camera.target,
            up: r.camera.up,
            fov_y_degrees: r.camera.yfov.to_degrees(),
        })
    }
}

#[pymethods]
impl Frame {
    /// The image as 8-bit sRGB with alpha, uint8 (height, width, 4): the bytes `realist
    /// render` writes to a PNG, plus alpha (the linear alpha times 255, rounded).
    #[getter]
    fn rgba(&self, py: Python<'_>) -> Py<PyArray3<u8>> {
        self.rgba.clone_ref(py)
    }

    /// The image in linear light, float32 (height, width, 4) RGBA: after exposure and the
    /// tone map, before the sRGB encoding of `rgba`.
    #[getter]
    fn linear(&self, py: Python<'_>) -> Py<PyArray3<f32>> {
        self.linear.clone_ref(py)
    }

    /// Depth, float32 (height, width): each pixel's distance in front of the camera along
    /// its line of sight (view-space z, as OpenCV depth maps measure it, not the distance
    /// to the eye); infinity where nothing was drawn.
    #[getter]
    fn depth(&self, py: Python<'_>) -> Py<PyArray2<f32>> {
        self.depth.clone_ref(py)
    }

    /// The scene instance seen at each pixel, int32 (height, width): an index into the
    /// scene's instances (0 to Scene.instances - 1; a Scene from arrays has one, 0), -1 for
    /// the background and the ground plane. Found by a ray through each pixel's centre.
    /// None when rendered with ids=False.
    #[getter]
    fn ids(&self, py: Python<'_>) -> Option<Py<PyArray2<i32>>> {
        self.ids.as_ref().map(|a| a.clone_ref(py))
    }

    /// (width, height) in pixels.
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The camera the frame was rendered with: a dict of eye, target, up (world
    /// coordinates) and fov_y_degrees.
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let d = pyo3::types::PyDict::new(py);
        d.set_item("eye", self.eye.to_array())?;
        d.set_item("target", self.target.to_array())?;
        d.set_item("up", self.up.to_array())?;
        d.set_item("fov_y_degrees", self.fov_y_degrees)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!("realist.Frame({}x{})", self.width, self.height)
    }
}
