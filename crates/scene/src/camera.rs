//! The pinhole camera of the textbook's pipeline chapter (§2-§3): position and orientation,
//! vertical field of view (or the textbook's zoom = 1/tan(fov/2)), aspect ratio from the output
//! window, near and far planes.

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

/// The default vertical field of view: 45 degrees.
pub const DEFAULT_YFOV: f32 = std::f32::consts::FRAC_PI_4;

/// Keeps a vertical field of view (radians) within 0.1..179 degrees; NaN becomes the default.
#[must_use]
pub fn clamp_fov(yfov: f32) -> f32 {
    if yfov.is_nan() {
        DEFAULT_YFOV
    } else {
        yfov.clamp(0.1f32.to_radians(), 179f32.to_radians())
    }
}

/// A perspective camera looking from `eye` at `target`.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub name: String,
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub yfov: f32,
    /// Distance to the near plane (> 0).
    pub near: f32,
    /// Distance to the far plane (> near).
    pub far: f32,
    /// Aspect ratio (width / height) the file's author framed for, if any. Informational:
    /// the projection always uses the output image's aspect with this camera's vertical
    /// field of view, so a file camera never stretches the image.
    pub aspect: Option<f32>,
    /// `Some(half_height)`: an orthographic (parallel) projection showing `half_height` world
    /// units above and below the line of sight (glTF `ymag`); `yfov` is then unused by the
    /// projection. `None`: perspective.
    pub ortho: Option<f32>,
    /// The principal point off the image centre and non-square pixels, as a calibrated
    /// camera's intrinsics give them ([`Camera::from_intrinsics`]); [`Lens::CENTRED`] for
    /// every other camera.
    pub lens: Lens,
}

/// What a pinhole camera's intrinsics (fx, fy, cx, cy) add to a vertical field of view: the
/// principal point's offset from the image centre and the ratio of the focal lengths. The
/// projection maps clip-space x to `x_scale * x + shift.x * w` and y to `y + shift.y * w`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lens {
    /// The principal point's offset from the image centre in normalised device coordinates
    /// (x right, y up; 1 is half the image's width or height).
    pub shift: Vec2,
    /// The horizontal focal length over the vertical one (fx / fy; 1 for square pixels).
    pub x_scale: f32,
}

impl Lens {
    /// On-axis, square pixels: the projection of the field of view alone.
    pub const CENTRED: Lens = Lens {
        shift: Vec2::ZERO,
        x_scale: 1.0,
    };
}

impl Default for Lens {
    fn default() -> Self {
        Self::CENTRED
    }
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            name: "default".into(),
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            yfov: 45f32.to_radians(),
            near: 0.1,
            far: 100.0,
            aspect: None,
            ortho: None,
            lens: Lens::CENTRED,
        }
    }
}

impl Camera {
    /// The textbook's zoom factor, 1/tan(fov/2).
    #[must_use]
    pub fn zoom(&self) -> f32 {
        1.0 / libm::tanf(self.yfov * 0.5)
    }

    /// Sets the field of view from a zoom factor (zoom = 1/tan(fov/2)); zoom must be > 0.
    pub fn set_zoom(&mut self, zoom: f32) {
        self.yfov = 2.0 * libm::atanf(1.0 / zoom);
    }

    /// A camera orbiting `center` at `distance`, from `azimuth` degrees around +Y (0 = looking
    /// down -Z from +Z, positive turns towards +X) and `elevation` degrees above the horizon.
    #[must_use]
    pub fn orbit(center: Vec3, azimuth: f32, elevation: f32, distance: f32, yfov: f32) -> Self {
        let (sa, ca) = libm::sincosf(azimuth.to_radians());
        let (se, ce) = libm::sincosf(elevation.clamp(-89.9, 89.9).to_radians());
        let dir = Vec3::new(sa * ce, se, ca * ce);
        Self {
            name: "orbit".into(),
            eye: center + dir * distance,
            target: center,
            up: Vec3::Y,
            yfov,
            near: distance * 0.01,
            far: distance * 100.0,
            aspect: None,
            ortho: None,
            lens: Lens::CENTRED,
        }
    }

    /// The default view of a bounding sphere: from a fixed three-quarter direction
    /// (azimuth 35, elevation 25 degrees), far enough that the sphere fits the vertical and
    /// horizontal field of view, with near/far fitted to the sphere.
    #[must_use]
    pub fn frame(center: Vec3, radius: f32, aspect: f32) -> Self {
        Self::frame_from(center, radius, aspect, 35.0, 25.0)
    }

    /// Like [`Camera::frame`] from a given azimuth and elevation (degrees).
    #[must_use]
    pub fn frame_from(
        center: Vec3,
        radius: f32,
        aspect: f32,
        azimuth: f32,
        elevation: f32,
    ) -> Self {
        Self::frame_sphere_fov(center, radius, aspect, azimuth, elevation, DEFAULT_YFOV)
    }

    /// Frames a bounding sphere with a vertical field of view `yfov` (radians, clamped to
    /// 0.1..179 degrees).
    #[must_use]
    pub fn frame_sphere_fov(
        center: Vec3,
        radius: f32,
        aspect: f32,
        azimuth: f32,
        elevation: f32,
        yfov: f32,
    ) -> Self {
        let yfov = clamp_fov(yfov);
        let radius = if radius.is_finite() && radius > 0.0 {
            radius
        } else {
            1.0
        };
        let half_v = yfov * 0.5;
        let half_h = libm::atanf((libm::tanf(half_v)) * aspect.max(1e-3));
        let half = half_v.min(half_h);
        let distance = radius / libm::sinf(half) * 1.05;
        let mut cam = Self::orbit(center, azimuth, elevation, distance, yfov);
        cam.fit(center, radius);
        cam
    }

    /// [`Camera::frame_box_fov`] for a world whose up axis is `up`: the azimuth turns about
    /// it and the elevation rises towards it (for [`Up::Z`], azimuth 0 looks along -Y,
    /// with +Z up on screen). The box is framed in the Y-up frame and the camera turned back.
    #[must_use]
    pub fn frame_box_up(
        lo: Vec3,
        hi: Vec3,
        aspect: f32,
        azimuth: f32,
        elevation: f32,
        yfov: f32,
        up: Up,
    ) -> Self {
        let (lo, hi) = up.box_to_y_up(lo, hi);
        let cam = Self::frame_box_fov(lo, hi, aspect, azimuth, elevation, yfov);
        cam.turned(up.to_y_up().inverse())
    }

    /// The camera turned by `q` about the origin (eye, target and up).
    #[must_use]
    pub fn turned(self, q: Quat) -> Self {
        Self {
            eye: q * self.eye,
            target: q * self.target,
            up: q * self.up,
            ..self
        }
    }

    /// The default view of an axis-aligned box: from `azimuth`/`elevation` degrees, at the
    /// smallest distance where all eight corners project inside 90% of the view, with
    /// near/far fitted to the box's bounding sphere. Tighter than framing the bounding sphere
    /// for elongated models.
    #[must_use]
    pub fn frame_box(lo: Vec3, hi: Vec3, aspect: f32, azimuth: f32, elevation: f32) -> Self {
        Self::frame_box_fov(lo, hi, aspect, azimuth, elevation, DEFAULT_YFOV)
    }

    /// [`Camera::frame_box`] with a vertical field of view `yfov` in radians.
    #[must_use]
    pub fn frame_box_fov(
        lo: Vec3,
        hi: Vec3,
        aspect: f32,
        azimuth: f32,
        elevation: f32,
        yfov: f32,
    ) -> Self {
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo) * 0.5).length();
        let mut cam = Self::frame_sphere_fov(center, radius, aspect, azimuth, elevation, yfov);
        if !(radius.is_finite() && radius > 0.0) {
            return cam;
        }
        let dir = (cam.eye - center).normalize();
        let right = cam.up.cross(dir).normalize_or_zero();
        let up = dir.cross(right);
        let tan_v = libm::tanf(cam.yfov * 0.5) * 0.9;
        let tan_h = tan_v * aspect.max(1e-3);
        // Corner c at lateral offsets (x, y) and depth offset z along dir is inside the view
        // when |x| <= tan_h * (d - z) and |y| <= tan_v * (d - z).
        let mut d = 0.0f32;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            ) - center;
            let z = c.dot(dir);
            d = d
                .max(z + c.dot(right).abs() / tan_h)
                .max(z + c.dot(up).abs() / tan_v);
        }
        if d.is_finite() && d > 0.0 {
            cam.eye = center + dir * d;
            cam.fit(center, radius);
        }
        cam
    }

    /// Fits near and far to a bounding sphere: near just in front of it (never closer than
    /// 1/1000 of its radius), far just behind it.
    pub fn fit(&mut self, center: Vec3, radius: f32) {
        let d = (center - self.eye).length();
        let radius = radius.max(1e-6);
        self.far = (d + radius) * 1.01;
        self.near = (d - radius).max(radius * 1e-3).max(self.far * 1e-6) * 0.99;
    }

    /// The camera of a calibrated pinhole model as computer vision gives it (OpenCV's
    /// convention: camera x right, y down, z forward; the centre of the top-left pixel is
    /// pixel (0, 0)): focal lengths `fx`, `fy` and principal point `cx`, `cy` in pixels of
    /// a `width` x `height` image, and `cam_to_world`, the camera's pose (its columns the
    /// camera's x, y and z axes and its position in the world). A point at camera
    /// coordinates (X, Y, Z) lands at pixel (fx X / Z + cx, fy Y / Z + cy) of an image of
    /// that size. The rotation part of the pose must be a rotation (it is not checked
    /// here): its scale and shear are lost.
    #[must_use]
    pub fn from_intrinsics(
        [fx, fy, cx, cy]: [f32; 4],
        (width, height): (u32, u32),
        cam_to_world: Mat4,
        near: f32,
        far: f32,
    ) -> Self {
        let (w, h) = (width.max(1) as f32, height.max(1) as f32);
        let eye = cam_to_world.w_axis.truncate();
        let forward = cam_to_world.z_axis.truncate();
        // OpenCV's y points down the image; realist's camera up is the image's up.
        let up = -cam_to_world.y_axis.truncate();
        Self {
            name: "intrinsics".into(),
            eye,
            target: eye + forward,
            up,
            yfov: 2.0 * libm::atanf(h / (2.0 * fy)),
            near,
            far,
            aspect: Some(w / h),
            ortho: None,
            lens: Lens {
                // Pixel u's centre is at NDC (u + 0.5) / w * 2 - 1 (y: 1 - (v + 0.5) / h * 2).
                shift: Vec2::new((2.0 * cx + 1.0) / w - 1.0, 1.0 - (2.0 * cy + 1.0) / h),
                x_scale: fx / fy,
            },
        }
    }

    /// World -> camera (right-handed, looking down -Z).
    #[must_use]
    pub fn view(&self) -> Mat4 {
        let fwd = self.target - self.eye;
        let up = if fwd.cross(self.up).length_squared() < 1e-12 * fwd.length_squared() {
            // Looking straight along `up`: any perpendicular will do.
            fwd.any_orthonormal_vector()
        } else {
            self.up
        };
        Mat4::look_at_rh(self.eye, self.target, up)
    }

    /// Unit vector from the eye towards the target (`-Z` if they coincide).
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye).normalize_or(Vec3::NEG_Z)
    }

    /// The point highlights are computed from: the eye for a perspective camera; for an
    /// orthographic one, a point far back along the line of sight, so every surface point
    /// sees (to f32 precision) the same view direction, as parallel projection implies.
    #[must_use]
    pub fn shading_eye(&self) -> Vec3 {
        match self.ortho {
            None => self.eye,
            Some(_) => {
                let reach = (self.far.abs() + (self.target - self.eye).length()).max(1.0);
                self.eye - self.forward() * reach * 1e4
            }
        }
    }

    /// Camera -> clip with reversed depth in the Direct3D convention: after the divide,
    /// z = 1 on the near plane and z = 0 on the far plane, and clip w = distance in front of
    /// the camera (perspective) or 1 (orthographic). Reversed-Z spreads f32 depth precision
    /// evenly over distance.
    ///
    /// A [`Lens`] other than [`Lens::CENTRED`] moves the principal point and stretches x
    /// after this (an off-centre frustum).
    #[must_use]
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let p = self.centred_projection(aspect);
        if self.lens == Lens::CENTRED {
            return p;
        }
        let Lens { shift, x_scale } = self.lens;
        let lens = Mat4::from_cols(
            Vec4::new(x_scale, 0.0, 0.0, 0.0),
            Vec4::Y,
            Vec4::Z,
            Vec4::new(shift.x, shift.y, 0.0, 1.0),
        );
        lens * p
    }

    /// [`Camera::projection`] on the axis, with square pixels.
    fn centred_projection(&self, aspect: f32) -> Mat4 {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let (n, fa) = (self.near, self.far);
        if let Some(half) = self.ortho {
            let half = if half.is_finite() && half > 0.0 {
                half
            } else {
                1.0
            };
            // z_clip = (far + z_view) / (far - near): 1 at distance near, 0 at far; w = 1.
            let depth = 1.0 / (fa - n);
            return Mat4::from_cols(
                Vec4::new(1.0 / (half * aspect), 0.0, 0.0, 0.0),
                Vec4::new(0.0, 1.0 / half, 0.0, 0.0),
                Vec4::new(0.0, 0.0, depth, 0.0),
                Vec4::new(0.0, 0.0, fa * depth, 1.0),
            );
        }
        let f = self.zoom();
        // z_clip = a + b * w with w = -z_view; z_clip / w = 1 at w = n and 0 at w = far.
        let a = n * fa / (fa - n);
        let b = -n / (fa - n);
        Mat4::from_cols(
            Vec4::new(f / aspect, 0.0, 0.0, 0.0),
            Vec4::new(0.0, f, 0.0, 0.0),
            Vec4::new(0.0, 0.0, -b, -1.0),
            Vec4::new(0.0, 0.0, a, 0.0),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reversed_depth_maps_near_to_one_far_to_zero() {
        let cam = Camera {
            near: 0.5,
            far: 10.0,
            ..Camera::default()
        };
        let p = cam.projection(1.0);
        let near = p * Vec4::new(0.0, 0.0, -0.5, 1.0);
        let far = p * Vec4::new(0.0, 0.0, -10.0, 1.0);
        assert!((near.z / near.w - 1.0).abs() < 1e-6, "{near}");
        assert!((far.z / far.w).abs() < 1e-6, "{far}");
        assert!((near.w - 0.5).abs() < 1e-6);
    }

    #[test]
    fn orthographic_maps_depth_and_extent() {
        let cam = Camera {
            near: 0.5,
            far: 10.0,
            ortho: Some(2.0),
            ..Camera::default()
        };
        let p = cam.projection(2.0);
        let near = p * Vec4::new(4.0, 2.0, -0.5, 1.0);
        let far = p * Vec4::new(-4.0, -2.0, -10.0, 1.0);
        assert_eq!(near.w, 1.0);
        assert!(
            (near - Vec4::new(1.0, 1.0, 1.0, 1.0)).abs().max_element() < 1e-6,
            "{near}"
        );
        assert!(
            (far - Vec4::new(-1.0, -1.0, 0.0, 1.0)).abs().max_element() < 1e-6,
            "{far}"
        );
        // Highlights see a parallel view direction.
        let e = cam.shading_eye();
        assert!((e - cam.eye).normalize().dot(Vec3::Z) > 0.999_999);
        assert!((e - cam.eye).length() > 1e4);
    }

    #[test]
    fn intrinsics_project_as_opencv_does() {
        // A pose turned and moved off the origin, off-centre principal point, fx != fy.
        let (fx, fy, cx, cy, w, h) = (500.0f32, 450.0f32, 300.25f32, 210.5f32, 640u32, 480u32);
        let rot = Mat4::from_quat(Quat::from_euler(glam::EulerRot::YXZ, 0.4, -0.3, 0.2));
        let pose = Mat4::from_translation(Vec3::new(1.0, -2.0, 3.0)) * rot;
        let cam = Camera::from_intrinsics([fx, fy, cx, cy], (w, h), pose, 0.1, 100.0);
        let vp = cam.projection(w as f32 / h as f32) * cam.view();
        for p_cam in [
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::new(1.0, -0.5, 4.0),
            Vec3::new(-2.0, 1.5, 9.0),
        ] {
            let world = pose.transform_point3(p_cam);
            let clip = vp * world.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            // Back to OpenCV pixels: u = (ndc.x + 1) / 2 * w - 0.5.
            let u = (ndc.x + 1.0) * 0.5 * w as f32 - 0.5;
            let v = (1.0 - ndc.y) * 0.5 * h as f32 - 0.5;
            let (eu, ev) = (fx * p_cam.x / p_cam.z + cx, fy * p_cam.y / p_cam.z + cy);
            assert!(
                (u - eu).abs() < 1e-3 && (v - ev).abs() < 1e-3,
                "{u},{v} vs {eu},{ev}"
            );
            // In front of the camera, inside the reversed-Z depth range.
            assert!(clip.w > 0.0 && ndc.z > 0.0 && ndc.z < 1.0, "{ndc}");
        }
        // A centred principal point is the plain projection.
        let c = Camera::from_intrinsics([fy, fy, 319.5, 239.5], (w, h), pose, 0.1, 100.0);
        assert!(c.lens.shift.abs().max_element() < 1e-6 && c.lens.x_scale == 1.0);
    }

    #[test]
    fn zoom_round_trips() {
        let mut cam = Camera::default();
        cam.set_zoom(2.0);
        assert!((cam.zoom() - 2.0).abs() < 1e-5);
    }
}

/// The world's up axis: +Y (glTF, OBJ by convention) or +Z (most scans, STL and PLY files,
/// CAD). Models whose up is +Z lie on their back when viewed Y-up.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Up {
    #[default]
    Y,
    Z,
}

impl Up {
    /// The up vector.
    #[must_use]
    pub fn vector(self) -> Vec3 {
        match self {
            Up::Y => Vec3::Y,
            Up::Z => Vec3::Z,
        }
    }

    /// The rotation taking this up axis to +Y (X stays; for Z: Z -> Y, Y -> -Z).
    #[must_use]
    pub fn to_y_up(self) -> Quat {
        match self {
            Up::Y => Quat::IDENTITY,
            Up::Z => Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        }
    }

    /// The axis-aligned box `lo..hi` in the Y-up frame (exact: a quarter turn maps a box
    /// onto a box).
    #[must_use]
    pub fn box_to_y_up(self, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
        let q = self.to_y_up();
        let (a, b) = (q * lo, q * hi);
        (a.min(b), a.max(b))
    }

    /// `y` or `z`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Up::Y => "y",
            Up::Z => "z",
        }
    }
}

impl std::str::FromStr for Up {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "y" | "+y" => Ok(Up::Y),
            "z" | "+z" => Ok(Up::Z),
            other => Err(format!("up axis '{other}': expected y or z")),
        }
    }
}
