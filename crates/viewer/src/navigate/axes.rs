//! The axes and directions of navigation: rotation [`Mode`], world [`UpAxis`], f3d's named
//! [`View`]s, turntable angles to orientations, and pixel to NDC conversion. Conventions as in
//! the parent module: angles in radians, pixels y down, NDC y up.

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use glam::{Quat, Vec2, Vec3};

/// How a drag rotates the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// Yaw about the world up axis and pitch about the camera's right axis, pitch limited to
    /// [`PITCH_LIMIT_DEGREES`](super::PITCH_LIMIT_DEGREES); the horizon stays level (no roll).
    #[default]
    Turntable,
    /// Free rotation about the axis perpendicular to the drag; the camera's up vector turns
    /// too, so the model can be rolled and turned upside down.
    Trackball,
}

/// The world's up axis. With [`UpAxis::Y`] (glTF) front looks along -Z; with [`UpAxis::Z`]
/// (many CAD and scanned models) front looks along +Y. Right is +X for both.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum UpAxis {
    #[default]
    Y,
    Z,
}

impl From<crate::scene::Up> for UpAxis {
    fn from(up: crate::scene::Up) -> Self {
        match up {
            crate::scene::Up::Y => Self::Y,
            crate::scene::Up::Z => Self::Z,
        }
    }
}

impl UpAxis {
    /// The world up vector.
    #[must_use]
    pub fn up(self) -> Vec3 {
        match self {
            Self::Y => Vec3::Y,
            Self::Z => Vec3::Z,
        }
    }

    /// Rotation from the Y-up frame (right X, up Y, towards the front viewer Z) to this one.
    pub(super) fn frame(self) -> Quat {
        match self {
            Self::Y => Quat::IDENTITY,
            // X stays, Y -> Z, Z -> -Y.
            Self::Z => Quat::from_rotation_x(FRAC_PI_2),
        }
    }
}

/// f3d's named views; the direction looked along, for up = Y / up = Z.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Along -Z / +Y.
    Front,
    /// Along +Z / -Y.
    Back,
    /// From the right: along -X / -X.
    Right,
    /// From the left: along +X / +X.
    Left,
    /// Down: along -Y / -Z, screen up towards the back (-Z / +Y).
    Top,
    /// Up: along +Y / +Z, screen up towards the front (+Z / -Y).
    Bottom,
    /// From the front-right-top corner: along -(1, 1, 1) / (-1, 1, -1), normalized.
    Isometric,
}

impl View {
    pub const ALL: [View; 7] = [
        View::Front,
        View::Back,
        View::Right,
        View::Left,
        View::Top,
        View::Bottom,
        View::Isometric,
    ];

    /// (yaw, pitch) in radians: yaw turns the eye from the front towards the right about the
    /// up axis, pitch raises it above the horizon.
    pub(super) fn yaw_pitch(self) -> (f32, f32) {
        match self {
            Self::Front => (0.0, 0.0),
            Self::Back => (PI, 0.0),
            Self::Right => (FRAC_PI_2, 0.0),
            Self::Left => (-FRAC_PI_2, 0.0),
            Self::Top => (0.0, FRAC_PI_2),
            Self::Bottom => (0.0, -FRAC_PI_2),
            Self::Isometric => (FRAC_PI_4, libm::atanf(std::f32::consts::FRAC_1_SQRT_2)),
        }
    }
}

/// Pointer position in pixels (origin top left, y down) to NDC (-1..1, y up).
#[must_use]
pub fn pixel_to_ndc(pos_px: Vec2, viewport_px: Vec2) -> Vec2 {
    let size = viewport_px.max(Vec2::ONE);
    Vec2::new(pos_px.x / size.x * 2.0 - 1.0, 1.0 - pos_px.y / size.y * 2.0)
}

/// Camera orientation for turntable angles (radians) about `up_axis`.
pub(super) fn orientation(up_axis: UpAxis, yaw: f32, pitch: f32) -> Quat {
    (up_axis.frame() * Quat::from_rotation_y(yaw) * Quat::from_rotation_x(-pitch)).normalize()
}
