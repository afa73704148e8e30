//! `Camera`: where a render looks from. Look-at and orbit cameras, and the calibrated
//! pinhole camera of computer vision (OpenCV's intrinsics and pose).

use glam::{Mat4, Vec3, Vec4};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use realist::render::default_camera_up;
use realist::scene::{Camera as RCamera, Scene, Up};
use realist::scenefile;

/// How a camera is made; orbit and default cameras need the scene and the image's aspect.
#[derive(Clone, Debug)]
pub(crate) enum Kind {
    /// A fixed camera; near and far fitted to the scene's bounds when `fit` is set.
    Fixed { camera: RCamera, fit: bool },
    /// Intrinsics for an image of `size`: renders must be that size.
    Intrinsics {
        camera: RCamera,
        size: (u32, u32),
        fit: bool,
    },
    /// `realist render --camera AZ,EL[,DIST]`, with an optional field of view (radians).
    Orbit {
        azimuth: f32,
        elevation: f32,
        distance: Option<f32>,
        yfov: Option<f32>,
    },
}

/// A camera for `realist.render`. Make one with `Camera.look_at`, `Camera.orbit` or
/// `Camera.from_intrinsics`; immutable.
#[pyclass(module = "realist", frozen)]
#[derive(Clone, Debug)]
pub struct Camera {
    pub(crate) kind: Kind,
}

/// A finite 3-vector argument.
fn vec3(name: &str, v: (f64, f64, f64)) -> PyResult<Vec3> {
    let p = Vec3::new(v.0 as f32, v.1 as f32, v.2 as f32);
    if p.is_finite() {
        Ok(p)
    } else {
        Err(PyValueError::new_err(format!(
            "{name}: expected three finite numbers, got {v:?}"
        )))
    }
}

/// Near and far planes: both given (0 < near < far), or neither (fitted to the scene).
fn planes(near: Option<f64>, far: Option<f64>) -> PyResult<Option<(f32, f32)>> {
    match (near, far) {
        (None, None) => Ok(None),
        (Some(n), Some(f)) if n.is_finite() && f.is_finite() && n > 0.0 && f > n => {
            Ok(Some((n as f32, f as f32)))
        }
        (Some(n), Some(f)) => Err(PyValueError::new_err(format!(
            "near {n}, far {f}: expected 0 < near < far, both finite"
        ))),
        _ => Err(PyValueError::new_err(
            "near and far: give both, or neither (then they are fitted to the scene)",
        )),
    }
}

/// A vertical field of view in degrees, as radians.
fn fov(deg: f64) -> PyResult<f32> {
    if deg.is_finite() && deg > 0.0 && deg < 180.0 {
        Ok((deg as f32).to_radians())
    } else {
        Err(PyValueError::new_err(format!(
            "fov_y_degrees {deg}: expected degrees between 0 and 180"
        )))
    }
}

/// A 4x4 rigid transform from a numpy array (rows as in numpy: `m[row, col]`).
fn rigid(name: &str, a: &PyReadonlyArray2<'_, f64>) -> PyResult<Mat4> {
    if a.shape() != [4, 4] {
        return Err(PyValueError::new_err(format!(
            "{name}: expected a 4x4 matrix, got shape {:?}",
            a.shape()
        )));
    }
    let v = a.as_array();
    if v.iter().any(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{name}: the matrix holds a value that is not finite"
        )));
    }
    let col = |c: usize| {
        Vec4::new(
            v[[0, c]] as f32,
            v[[1, c]] as f32,
            v[[2, c]] as f32,
            v[[3, c]] as f32,
        )
    };
    let m = Mat4::from_cols(col(0), col(1), col(2), col(3));
    if (m.row(3) - Vec4::W).abs().max_element() > 1e-6 {
        return Err(PyValueError::new_err(format!(
            "{name}: the last row must be (0, 0, 0, 1), got {:?}",
            m.row(3).to_array()
        )));
    }
    let r = glam::Mat3::from_mat4(m);
    let gram = r.transpose() * r;
    let off = (gram.x_axis - Vec3::X)
        .abs()
        .max((gram.y_axis - Vec3::Y).abs())
        .max((gram.z_axis - Vec3::Z).abs())
        .max_element();
    if off > 1e-3 || r.determinant() < 0.0 {
        return Err(PyValueError::new_err(format!(
            "{name}: the upper-left 3x3 block must be a rotation (orthonormal, determinant +1); \
             a pose has no scale, shear or mirror"
        )));
    }
    Ok(m)
}

#[pymethods]
impl Camera {
    /// A perspective camera at `eye` looking at `target`, `up` upwards on the screen.
    ///
    /// `near` and `far` (distances along the line of sight) are fitted to the scene's
    /// bounds unless both are given.
    #[staticmethod]
    #[pyo3(signature = (eye, target, up=(0.0, 1.0, 0.0), fov_y_degrees=45.0, near=None, far=None))]
    fn look_at(
        eye: (f64, f64, f64),
        target: (f64, f64, f64),
        up: (f64, f64, f64),
        fov_y_degrees: f64,
        near: Option<f64>,
        far: Option<f64>,
    ) -> PyResult<Camera> {
        let (eye, target, up) = (vec3("eye", eye)?, vec3("target", target)?, vec3("up", up)?);
        if (target - eye).length_squared() == 0.0 {
            return Err(PyValueError::new_err("eye and target are the same point"));
        }
        if up.length_squared() == 0.0 {
            return Err(PyValueError::new_err("up is the zero vector"));
        }
        let planes = planes(near, far)?;
        let (n, f) = planes.unwrap_or((0.1, 100.0));
        let camera = RCamera {
            name: "look_at".into(),
            eye,
            target,
            up,
            yfov: fov(fov_y_degrees)?,
            near: n,
            far: f,
            ..RCamera::default()
        };
        Ok(Camera {
            kind: Kind::Fixed {
                camera,
                fit: planes.is_none(),
            },
        })
    }

    /// `realist render --camera AZIMUTH,ELEVATION[,DISTANCE]`: a camera orbiting the
    /// scene's centre, `azimuth` degrees around the up axis (0 looks down -Z from +Z) and
    /// `elevation` degrees above the horizon; the distance frames the scene unless given.
    #[staticmethod]
    #[pyo3(signature = (azimuth, elevation, distance=None, fov_y_degrees=None))]
    fn orbit(
        azimuth: f64,
        elevation: f64,
        distance: Option<f64>,
        fov_y_degrees: Option<f64>,
    ) -> PyResult<Camera> {
        if !(azimuth.is_finite() && elevation.is_finite()) {
            return Err(PyValueError::new_err(
                "azimuth and elevation must be finite numbers of degrees",
            ));
        }
        if let Some(d) = distance.filter(|d| !(d.is_finite() && *d > 0.0)) {
            return Err(PyValueError::new_err(format!(
                "distance {d}: expected a positive number"
            )));
        }
        Ok(Camera {
            kind: Kind::Orbit {
                azimuth: azimuth as f32,
                elevation: elevation as f32,
                distance: distance.map(|d| d as f32),
                yfov: fov_y_degrees.map(fov).transpose()?,
            },
        })
    }

    /// A calibrated pinhole camera in OpenCV's convention: focal lengths `fx`, `fy` and
    /// principal point `cx`, `cy` in pixels of a `width` x `height` image (the centre of the
    /// top-left pixel is (0, 0)); camera axes x right, y down, z forward (into the scene).
    ///
    /// The pose is a 4x4 rigid transform, given as exactly one of `cam_to_world` (the
    /// camera's axes and position in world coordinates, as NeRF-style datasets store it)
    /// or `world_to_cam` (OpenCV's extrinsics [R | t], as `cv2.solvePnP` and COLMAP give
    /// them); neither means the identity (the camera at the origin looking down +Z). A
    /// world point X lands at pixel (u, v) = (fx x / z + cx, fy y / z + cy) where (x, y, z)
    /// = world_to_cam @ X. Renders with this camera must be `width` x `height`.
    #[staticmethod]
    #[pyo3(signature = (fx, fy, cx, cy, width, height, cam_to_world=None, world_to_cam=None, near=None, far=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_intrinsics(
        fx: f64,
        fy: f64,
        cx: f64,
        cy: f64,
        width: u32,
        height: u32,
        cam_to_world: Option<PyReadonlyArray2<'_, f64>>,
        world_to_cam: Option<PyReadonlyArray2<'_, f64>>,
        near: Option<f64>,
        far: Option<f64>,
    ) -> PyResult<Camera> {
        for (name, v) in [("fx", fx), ("fy", fy)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(PyValueError::new_err(format!(
                    "{name} {v}: expected a positive focal length in pixels"
                )));
            }
        }
        for (name, v) in [("cx", cx), ("cy", cy)] {
            if !v.is_finite() {
                return Err(PyValueError::new_err(format!(
                    "{name} {v}: expected a finite number of pixels"
                )));
            }
        }
        if !(1..=16384).contains(&width) || !(1..=16384).contains(&height) {
            return Err(PyValueError::new_err(format!(
                "width x height {width}x{height}: expected 1 to 16384 pixels each"
            )));
        }
        let pose = match (&cam_to_world, &world_to_cam) {
            (Some(_), Some(_)) => {
                return Err(PyValueError::new_err(
                    "give cam_to_world or world_to_cam, not both",
                ))
            }
            (Some(m), None) => rigid("cam_to_world", m)?,
            (None, Some(m)) => rigid("world_to_cam", m)?.inverse(),
            (None, None) => Mat4::IDENTITY,
        };
        let planes = planes(near, far)?;
        let (n, f) = planes.unwrap_or((0.1, 100.0));
        let camera = RCamera::from_intrinsics(
            [fx as f32, fy as f32, cx as f32, cy as f32],
            (width, height),
            pose,
            n,
            f,
        );
        Ok(Camera {
            kind: Kind::Intrinsics {
                camera,
                size: (width, height),
                fit: planes.is_none(),
            },
        })
    }

    /// The image size a camera from intrinsics was calibrated for, else None.
    #[getter]
    fn size(&self) -> Option<(u32, u32)> {
        match self.kind {
            Kind::Intrinsics { size, .. } => Some(size),
            _ => None,
        }
    }

    fn __repr__(&self) -> String {
        match &self.kind {
            Kind::Fixed { camera: c, .. } => format!(
                "realist.Camera.look_at(eye={:?}, target={:?}, up={:?}, fov_y_degrees={})",
                c.eye.to_array(),
                c.target.to_array(),
                c.up.to_array(),
                c.yfov.to_degrees()
            ),
            Kind::Intrinsics { camera: c, size, .. } => format!(
                "realist.Camera(intrinsics for {}x{}, eye={:?}, fov_y_degrees={})",
                size.0,
                size.1,
                c.eye.to_array(),
                c.yfov.to_degrees()
            ),
            Kind::Orbit {
                azimuth,
                elevation,
                distance,
                ..
            } => format!(
                "realist.Camera.orbit(azimuth={azimuth}, elevation={elevation}, distance={distance:?})"
            ),
        }
    }
}

impl Camera {
    /// The realist camera for `scene` at image size `(w, h)`; `None` for the default view
    /// (the scene framed from a three-quarter view, as `realist render` frames it).
    pub(crate) fn resolve(
        camera: Option<&Camera>,
        scene: &Scene,
        (w, h): (u32, u32),
        up: Up,
    ) -> Result<RCamera, String> {
        let aspect = w as f32 / h as f32;
        let fit = |mut c: RCamera| {
            if let Some((lo, hi)) = scene.bounds() {
                let (centre, radius) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length());
                c.fit(centre, radius);
            }
            c
        };
        let Some(camera) = camera else {
            return Ok(default_camera_up(scene, aspect, up));
        };
        Ok(match &camera.kind {
            Kind::Fixed { camera, fit: f } => {
                if *f {
                    fit(camera.clone())
                } else {
                    camera.clone()
                }
            }
            Kind::Intrinsics {
                camera,
                size,
                fit: f,
            } => {
                if *size != (w, h) {
                    return Err(format!(
                        "the camera's intrinsics are for a {}x{} image, but size is {w}x{h}",
                        size.0, size.1
                    ));
                }
                if *f {
                    fit(camera.clone())
                } else {
                    camera.clone()
                }
            }
            Kind::Orbit {
                azimuth,
                elevation,
                distance,
                yfov,
            } => scenefile::orbit_camera(scene, aspect, *azimuth, *elevation, *distance, *yfov, up),
        })
    }

    /// The size a camera asks for (intrinsics), if any.
    pub(crate) fn wanted_size(camera: Option<&Camera>) -> Option<(u32, u32)> {
        match camera.map(|c| &c.kind) {
            Some(Kind::Intrinsics { size, .. }) => Some(*size),
            _ => None,
        }
    }
}
