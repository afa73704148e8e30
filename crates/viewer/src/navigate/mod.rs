//! The viewer's interactive camera: turntable or trackball orbit, pan, exponential dolly (to
//! the cursor if asked), framing of the scene's bounding sphere, f3d's named views and up axes,
//! an orthographic toggle and the field of view. Pure logic, no egui: the viewer feeds it
//! pointer deltas and reads a [`Camera`] back from [`Navigator::camera`].
//!
//! # Conventions
//! - Pointer deltas and viewport sizes are physical **pixels**, x to the right, **y down**
//!   (egui's screen convention). A drag moves the model with the cursor, as three.js
//!   OrbitControls and f3d do.
//! - Cursor positions given to [`Navigator::dolly_at`] are **NDC**: -1..1 across the viewport,
//!   x to the right, **y up** ([`pixel_to_ndc`] converts).
//! - Angles are **radians** except where a name says degrees (`*_DEGREES`,
//!   [`Navigator::fov_degrees`], [`Navigator::set_fov_degrees`]).
//! - Lengths are world units; ranges relative to the scene are in scene radii (`r`).
//! - Camera frame: right = +X, up = +Y, looking down -Z (right-handed, as [`Camera::view`]).
//! - Projection: perspective, or orthographic with half-height
//!   `distance * tan(yfov / 2)`, so toggling keeps the apparent size at the target and
//!   every operation treats both the same way. Near and far always come from the scene's
//!   bounding sphere (reversed-Z, see [`Camera::projection`]).

use std::f32::consts::PI;

use glam::{Mat3, Quat, Vec3};

use crate::scene::{clamp_fov, Camera, DEFAULT_YFOV};

mod axes;
mod moves;
#[cfg(test)]
mod tests;

use axes::orientation;
pub use axes::{pixel_to_ndc, Mode, UpAxis, View};

/// Orbit speed: radians turned per drag of one viewport height (pi: 180 degrees).
pub const ORBIT_RADIANS_PER_HEIGHT: f32 = PI;
/// Turntable pitch limit for orbiting, degrees above or below the horizon. The named top and
/// bottom views sit exactly at +-90; dragging from there only moves away from the pole.
pub const PITCH_LIMIT_DEGREES: f32 = 89.0;
/// Dolly factor per wheel step: distance *= `DOLLY_PER_STEP ^ steps` (steps > 0 move in).
pub const DOLLY_PER_STEP: f32 = 0.9;
/// Field of view range of [`Navigator::set_fov_degrees`], vertical, degrees.
pub const FOV_RANGE_DEGREES: (f32, f32) = (5.0, 120.0);
/// Framing margin: the bounding sphere fills `1 / FRAME_PADDING` of the tighter axis.
pub const FRAME_PADDING: f32 = 1.1;
/// Eye-to-target distance range, in scene radii.
pub const DISTANCE_RANGE: (f32, f32) = (1e-3, 1e4);
/// Near plane never closer than `far * NEAR_FAR_RATIO` (the eye may be inside the sphere).
pub const NEAR_FAR_RATIO: f32 = 1e-4;
/// Default three-quarter view, the same as [`Camera::frame`]: degrees from the front towards
/// the right about the up axis...
pub const DEFAULT_AZIMUTH_DEGREES: f32 = 35.0;
/// ...and degrees above the horizon.
pub const DEFAULT_ELEVATION_DEGREES: f32 = 25.0;

/// Where the camera is: everything [`Navigator::reset`] restores.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pose {
    /// The orbit centre, world units.
    target: Vec3,
    /// Eye to target, world units, within [`DISTANCE_RANGE`] scene radii.
    distance: f32,
    /// Camera to world (the camera looks down its -Z, its up is +Y). Unit length.
    rotation: Quat,
    /// Vertical field of view, radians.
    yfov: f32,
}

/// The interactive camera's state. Produces a [`Camera`] with [`Navigator::camera`].
#[derive(Clone, Debug, PartialEq)]
pub struct Navigator {
    mode: Mode,
    up_axis: UpAxis,
    ortho: bool,
    pose: Pose,
    /// What [`Navigator::reset`] returns to.
    home: Pose,
    /// Scene bounding sphere (world units, radius > 0): near/far, framing, clamps.
    center: Vec3,
    radius: f32,
}

impl Default for Navigator {
    fn default() -> Self {
        Self::new(Vec3::ZERO, 1.0, 1.0)
    }
}

impl Navigator {
    /// Turntable, Y up, perspective with the default field of view, framing the sphere
    /// (`radius` world units) from the default three-quarter view for a viewport of `aspect`
    /// (width / height). That framing is the home [`Navigator::reset`] returns to.
    #[must_use]
    pub fn new(center: Vec3, radius: f32, aspect: f32) -> Self {
        let pose = Pose {
            target: Vec3::ZERO,
            distance: 1.0,
            rotation: Quat::IDENTITY,
            yfov: DEFAULT_YFOV,
        };
        let mut nav = Self {
            mode: Mode::Turntable,
            up_axis: UpAxis::Y,
            ortho: false,
            pose,
            home: pose,
            center: Vec3::ZERO,
            radius: 1.0,
        };
        nav.new_scene(center, radius, aspect);
        nav
    }

    /// Starts from a file's camera (exactly its view, roll included; an orthographic camera's
    /// eye may be moved back along the line of sight to see the whole sphere), which becomes
    /// the home. The field of view is kept within [`clamp_fov`]'s range; the distance is
    /// clamped to [`DISTANCE_RANGE`]. A camera whose eye is on its target (or not finite)
    /// gives [`Navigator::new`]'s framing instead.
    #[must_use]
    pub fn from_camera(camera: &Camera, center: Vec3, radius: f32, up_axis: UpAxis) -> Self {
        let mut nav = Self::new(center, radius, 1.0);
        nav.set_up_axis(up_axis, 1.0);
        let to_target = camera.target - camera.eye;
        let length = to_target.length();
        if camera.eye.is_finite() && camera.target.is_finite() && length > 0.0 {
            let back = -to_target / length;
            let up = camera.up - back * camera.up.dot(back);
            let up = up
                .try_normalize()
                .unwrap_or_else(|| back.any_orthonormal_vector());
            let right = up.cross(back);
            let yfov = clamp_fov(camera.yfov);
            let distance = match camera.ortho {
                Some(half) if half.is_finite() && half > 0.0 => half / libm::tanf(yfov * 0.5),
                _ => length,
            };
            nav.pose = Pose {
                target: camera.target,
                distance,
                rotation: Quat::from_mat3(&Mat3::from_cols(right, up, back)).normalize(),
                yfov,
            };
            nav.ortho = camera.ortho.is_some();
            nav.clamp_pose();
            nav.home = nav.pose;
        }
        nav
    }

    /// A new model: keeps the mode, up axis, projection and field of view, frames the sphere
    /// from the default three-quarter view, and makes that the home.
    pub fn new_scene(&mut self, center: Vec3, radius: f32, aspect: f32) {
        let (yaw, pitch) = (DEFAULT_AZIMUTH_DEGREES, DEFAULT_ELEVATION_DEGREES);
        self.pose.rotation = orientation(self.up_axis, yaw.to_radians(), pitch.to_radians());
        self.frame(center, radius, aspect);
        self.home = self.pose;
    }

    /// The camera for a viewport of `aspect` (width / height). Its `up` is the screen's up
    /// (perpendicular to the line of sight), `ortho` is the half-height in orthographic mode,
    /// and near/far enclose the scene sphere (see [`NEAR_FAR_RATIO`]).
    #[must_use]
    pub fn camera(&self, aspect: f32) -> Camera {
        let Pose { target, .. } = self.pose;
        let back = self.pose.rotation * Vec3::Z;
        let mut eye_distance = self.pose.distance;
        if self.ortho {
            // Any eye on the line of sight gives the same image: stand back far enough that
            // the whole sphere is in front whatever the direction (and its rounding).
            let reach = (self.center - target).length() + 1.1 * self.radius;
            eye_distance = eye_distance.max(reach);
        }
        let eye = target + back * eye_distance;
        // Depths as the view matrix will measure them: along the rounded `target - eye`,
        // which far from the origin at a short distance is a little off `-back`.
        let (near, far) = self.near_far(eye, (target - eye).normalize_or(-back));
        Camera {
            name: "viewer".into(),
            eye,
            target,
            up: self.pose.rotation * Vec3::Y,
            yfov: self.pose.yfov,
            near,
            far,
            aspect: (aspect.is_finite() && aspect > 0.0).then_some(aspect),
            ortho: self.ortho.then(|| self.half_height()),
            lens: Default::default(),
        }
    }

    /// Fits the sphere (`radius` world units) for the current view direction and field of
    /// view: perspective distance `FRAME_PADDING * r / sin(min(fov_v, fov_h) / 2)`,
    /// orthographic half-height `FRAME_PADDING * r` (divided by the aspect when the viewport
    /// is taller than wide). The sphere becomes the scene's (near/far, clamps); the home
    /// stays (see [`Navigator::set_home`]).
    pub fn frame(&mut self, center: Vec3, radius: f32, aspect: f32) {
        self.center = if center.is_finite() {
            center
        } else {
            Vec3::ZERO
        };
        self.radius = if radius.is_finite() && radius > 0.0 {
            radius.clamp(1e-20, 1e30)
        } else {
            1.0
        };
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let half_v = self.pose.yfov * 0.5;
        let r = FRAME_PADDING * self.radius;
        self.pose.target = self.center;
        self.pose.distance = if self.ortho {
            r / aspect.min(1.0) / libm::tanf(half_v)
        } else {
            let half_h = libm::atanf(libm::tanf(half_v) * aspect);
            r / libm::sinf(half_v.min(half_h))
        };
        self.clamp_pose();
    }

    /// Turns to a named view, keeping the target and distance.
    pub fn set_view(&mut self, view: View) {
        let (yaw, pitch) = view.yaw_pitch();
        self.pose.rotation = orientation(self.up_axis, yaw, pitch);
    }

    /// Changes the up axis; when it changes, re-frames the scene from the default view for a
    /// viewport of `aspect`, which becomes the home.
    pub fn set_up_axis(&mut self, up_axis: UpAxis, aspect: f32) {
        if up_axis != self.up_axis {
            self.up_axis = up_axis;
            self.new_scene(self.center, self.radius, aspect);
        }
    }

    /// Switches the rotation mode. The eye, target and view direction stay; switching to
    /// turntable levels the horizon (removes the trackball's roll).
    pub fn set_mode(&mut self, mode: Mode) {
        if mode == Mode::Turntable && self.mode != Mode::Turntable {
            let (yaw, pitch) = self.yaw_pitch();
            self.pose.rotation = orientation(self.up_axis, yaw, pitch);
        }
        self.mode = mode;
    }

    /// Orthographic on or off; the apparent size at the target stays (half-height =
    /// `distance * tan(yfov / 2)`).
    pub fn set_ortho(&mut self, ortho: bool) {
        self.ortho = ortho;
    }

    pub fn toggle_ortho(&mut self) {
        self.ortho = !self.ortho;
    }

    /// Sets the vertical field of view in degrees, clamped to [`FOV_RANGE_DEGREES`]; the
    /// distance changes so the apparent size at the target stays. NaN is ignored.
    pub fn set_fov_degrees(&mut self, degrees: f32) {
        if degrees.is_nan() {
            return;
        }
        let new = degrees
            .clamp(FOV_RANGE_DEGREES.0, FOV_RANGE_DEGREES.1)
            .to_radians();
        self.pose.distance *= libm::tanf(self.pose.yfov * 0.5) / libm::tanf(new * 0.5);
        self.pose.yfov = new;
        self.clamp_pose();
    }

    /// Back to the home pose exactly (target, distance, orientation, field of view); the
    /// mode, up axis and projection stay.
    pub fn reset(&mut self) {
        self.pose = self.home;
    }

    /// Makes the current pose the one [`Navigator::reset`] returns to.
    pub fn set_home(&mut self) {
        self.home = self.pose;
    }

    #[must_use]
    pub fn mode(&self) -> Mode {
        self.mode
    }

    #[must_use]
    pub fn up_axis(&self) -> UpAxis {
        self.up_axis
    }

    #[must_use]
    pub fn is_ortho(&self) -> bool {
        self.ortho
    }

    /// Vertical field of view, degrees.
    #[must_use]
    pub fn fov_degrees(&self) -> f32 {
        self.pose.yfov.to_degrees()
    }

    /// The orbit centre, world units.
    #[must_use]
    pub fn target(&self) -> Vec3 {
        self.pose.target
    }

    /// Eye to target, world units (in orthographic mode the nominal distance that sets the
    /// half-height; the camera's eye may be further back).
    #[must_use]
    pub fn distance(&self) -> f32 {
        self.pose.distance
    }

    /// World units from the target to the top of the view at the target's depth: the
    /// orthographic half-height, `distance * tan(yfov / 2)`.
    #[must_use]
    pub fn half_height(&self) -> f32 {
        self.pose.distance * libm::tanf(self.pose.yfov * 0.5)
    }

    /// The scene's bounding sphere: centre and radius, world units.
    #[must_use]
    pub fn scene(&self) -> (Vec3, f32) {
        (self.center, self.radius)
    }

    /// Turntable angles of the current orientation in radians: yaw from the front towards
    /// the right about the up axis, pitch above the horizon (-pi/2..pi/2).
    fn yaw_pitch(&self) -> (f32, f32) {
        let local = self.up_axis.frame().inverse() * self.pose.rotation;
        let back = local * Vec3::Z;
        let horizontal = libm::hypotf(back.x, back.z);
        let pitch = libm::atan2f(back.y, horizontal);
        let yaw = if horizontal > 1e-4 {
            libm::atan2f(back.x, back.z)
        } else {
            // Looking along the up axis: the heading is the right vector's.
            let right = local * Vec3::X;
            libm::atan2f(-right.z, right.x)
        };
        (yaw, pitch)
    }

    fn clamp_distance(&self, distance: f32) -> f32 {
        let (lo, hi) = (
            DISTANCE_RANGE.0 * self.radius,
            DISTANCE_RANGE.1 * self.radius,
        );
        if distance.is_nan() {
            hi.min(lo * 1e3)
        } else {
            distance.clamp(lo, hi)
        }
    }

    /// Keeps the distance in range and the target within `DISTANCE_RANGE.1` radii of the
    /// scene centre (so the model can always be found again).
    fn clamp_pose(&mut self) {
        self.pose.distance = self.clamp_distance(self.pose.distance);
        let offset = self.pose.target - self.center;
        self.pose.target = if offset.is_finite() {
            self.center + offset.clamp_length_max(DISTANCE_RANGE.1 * self.radius)
        } else {
            self.center
        };
    }

    /// Near and far planes for an eye looking along `forward` (unit): the sphere's depth
    /// range with a 1% margin, near at least `far * NEAR_FAR_RATIO`.
    fn near_far(&self, eye: Vec3, forward: Vec3) -> (f32, f32) {
        let depth = (self.center - eye).dot(forward);
        let far = (depth + self.radius).max(self.radius * 1e-3) * 1.01;
        let near = (depth - self.radius).max(far * NEAR_FAR_RATIO) * 0.99;
        (near, far)
    }
}
