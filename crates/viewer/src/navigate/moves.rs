//! The pointer-driven motions of [`Navigator`]: orbit, pan, dolly (to the cursor) and
//! re-centring. Pixels are y down, NDC y up, angles radians (see the parent module).

use std::f32::consts::TAU;

use glam::{Quat, Vec2, Vec3};

use super::{
    orientation, Mode, Navigator, DOLLY_PER_STEP, ORBIT_RADIANS_PER_HEIGHT, PITCH_LIMIT_DEGREES,
};

impl Navigator {
    /// Rotates the camera about the target by a pointer drag (`dx_px` right, `dy_px` down) at
    /// [`ORBIT_RADIANS_PER_HEIGHT`]: dragging right moves the eye to its left (the model turns
    /// right with the cursor), dragging down raises the eye.
    pub fn orbit(&mut self, dx_px: f32, dy_px: f32, viewport_height_px: f32) {
        if !(dx_px.is_finite() && dy_px.is_finite() && viewport_height_px > 0.0) {
            return;
        }
        let per_px = ORBIT_RADIANS_PER_HEIGHT / viewport_height_px;
        match self.mode {
            Mode::Turntable => {
                let (yaw, pitch) = self.yaw_pitch();
                let limit = PITCH_LIMIT_DEGREES.to_radians();
                let new_pitch =
                    (pitch + dy_px * per_px).clamp((-limit).min(pitch), limit.max(pitch));
                let new_yaw = (yaw - dx_px * per_px).rem_euclid(TAU);
                if !new_yaw.is_finite() {
                    return;
                }
                self.pose.rotation = orientation(self.up_axis, new_yaw, new_pitch);
            }
            Mode::Trackball => {
                let scale = dx_px.abs().max(dy_px.abs());
                let Some(axis) = (Vec3::new(dy_px, dx_px, 0.0) / scale).try_normalize() else {
                    return;
                };
                let angle = (libm::hypotf(dx_px, dy_px) * per_px).rem_euclid(TAU);
                if !angle.is_finite() {
                    return;
                }
                let turn = Quat::from_axis_angle(axis, -angle);
                self.pose.rotation = (self.pose.rotation * turn).normalize();
            }
        }
    }

    /// Moves the target (and eye) in the view plane so that points at the target's depth
    /// follow the cursor: `dx_px` right, `dy_px` down, one viewport height moving
    /// `2 * distance * tan(yfov / 2)` world units (twice the orthographic half-height).
    pub fn pan(&mut self, dx_px: f32, dy_px: f32, viewport_height_px: f32) {
        if !(dx_px.is_finite() && dy_px.is_finite() && viewport_height_px > 0.0) {
            return;
        }
        let per_px = 2.0 * self.half_height() / viewport_height_px;
        let right = self.pose.rotation * Vec3::X;
        let up = self.pose.rotation * Vec3::Y;
        self.pose.target += (up * dy_px - right * dx_px) * per_px;
        self.clamp_pose();
    }

    /// Exponential dolly towards the target: distance (and orthographic half-height) times
    /// `DOLLY_PER_STEP ^ steps`; steps > 0 move in, fractions allowed.
    pub fn dolly(&mut self, steps: f32) {
        self.dolly_at(steps, Vec2::ZERO, 1.0);
    }

    /// Dolly towards the point under the cursor (`cursor_ndc`, y up) for a viewport of
    /// `aspect`: the eye moves along the cursor's ray and the target stays on the line of
    /// sight at the new distance, so everything under the cursor at the target's depth stays
    /// under it (three.js `zoomToCursor`; exact for any depth in orthographic mode).
    pub fn dolly_at(&mut self, steps: f32, cursor_ndc: Vec2, aspect: f32) {
        if !(steps.is_finite() && cursor_ndc.is_finite() && aspect.is_finite() && aspect > 0.0) {
            return;
        }
        // A cursor far outside the viewport is an input glitch, not a request.
        let cursor_ndc = cursor_ndc.clamp(Vec2::splat(-10.0), Vec2::splat(10.0));
        let old = self.pose.distance;
        let new = self.clamp_distance(old * libm::powf(DOLLY_PER_STEP, steps.clamp(-1e3, 1e3)));
        let half = self.half_height();
        let right = self.pose.rotation * Vec3::X;
        let up = self.pose.rotation * Vec3::Y;
        // Where the cursor's ray crosses the plane through the target facing the camera.
        let under = self.pose.target + (right * (cursor_ndc.x * aspect) + up * cursor_ndc.y) * half;
        self.pose.target = under + (self.pose.target - under) * (new / old);
        self.pose.distance = new;
        self.clamp_pose();
    }

    /// Makes `point` the orbit centre f3d style: the camera translates so the target lands
    /// on it, keeping the view direction, roll and distance (the point moves to the centre of
    /// the view, the model's apparent size at the point stays the same).
    pub fn center_on(&mut self, point: Vec3) {
        if point.is_finite() {
            self.pose.target = point;
            self.clamp_pose();
        }
    }
}
