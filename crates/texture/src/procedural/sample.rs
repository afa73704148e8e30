//! [`SamplePoint`]: where a procedural texture is evaluated and over what footprint, and
//! the footprint's conversion to the box the 2D patterns integrate over.

use glam::{DVec3, Vec2, Vec3};

/// Where a procedural texture is evaluated, and over what footprint. Fill in what the
/// texture's [`Domain`](super::Domain) reads; the rest is ignored.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SamplePoint {
    /// Texture coordinates (origin top left, v downwards).
    pub uv: Vec2,
    /// Change of `uv` from one pixel to the next in x (screen-space derivative).
    pub duv_dx: Vec2,
    /// Change of `uv` from one pixel to the next in y.
    pub duv_dy: Vec2,
    /// Object-space position (solid textures).
    pub position: Vec3,
    /// Footprint width at `position` in object units, e.g. `max(|dP/dx|, |dP/dy|)`.
    pub width: f32,
}

impl SamplePoint {
    /// A point sample at `uv`.
    #[must_use]
    pub fn uv(uv: Vec2) -> Self {
        Self::uv_grad(uv, Vec2::ZERO, Vec2::ZERO)
    }

    /// A sample at `uv` filtered over the pixel footprint given by the UV derivatives.
    #[must_use]
    pub fn uv_grad(uv: Vec2, duv_dx: Vec2, duv_dy: Vec2) -> Self {
        Self {
            uv,
            duv_dx,
            duv_dy,
            ..Self::default()
        }
    }

    /// A sample at object-space `position`, filtered over `width` object units (0 = point).
    #[must_use]
    pub fn position(position: Vec3, width: f32) -> Self {
        Self {
            position,
            width,
            ..Self::default()
        }
    }

    /// The footprint box `[lo, hi]` per UV axis, scaled by `scale` (cells per unit).
    pub(super) fn uv_box(&self, scale: f64) -> Option<((f64, f64), (f64, f64))> {
        if !self.uv.is_finite() {
            return None;
        }
        let half = |a: f32, b: f32| 0.5 * f64::from(a.abs().max(b.abs())) * scale;
        let axis = |c: f32, h: f64| {
            let h = if h.is_nan() { 0.0 } else { h };
            let c = f64::from(c) * scale;
            (c - h, c + h)
        };
        Some((
            axis(self.uv.x, half(self.duv_dx.x, self.duv_dy.x)),
            axis(self.uv.y, half(self.duv_dx.y, self.duv_dy.y)),
        ))
    }

    pub(super) fn object(&self) -> (DVec3, f64) {
        let w = if self.width.is_nan() {
            0.0
        } else {
            self.width.abs()
        };
        (self.position.as_dvec3(), f64::from(w))
    }
}
