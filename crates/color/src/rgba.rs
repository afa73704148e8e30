//! [`Rgba`]: the float colour with alpha of the textbook (its `CFloatColor`), in linear light.
//!
//! Lighting sums colours freely, so components may leave [0, 1]. There are three ways back
//! into range, and the textbook's chapter shows why the choice matters: clamping (1, 2, 1) gives
//! white and loses the hue, dividing by the largest component gives (0.5, 1, 0.5) and keeps
//! it; tone mapping (Reinhard) compresses all values smoothly.

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Sub};

/// A linear-light RGBA colour with f32 components. Alpha is straight (not premultiplied).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rgba {
    pub r: f32,
    pub g: f32,
    pub b: f32,
    pub a: f32,
}

impl Rgba {
    pub const BLACK: Self = Self::new(0.0, 0.0, 0.0, 1.0);
    pub const WHITE: Self = Self::new(1.0, 1.0, 1.0, 1.0);
    pub const TRANSPARENT: Self = Self::new(0.0, 0.0, 0.0, 0.0);

    #[must_use]
    pub const fn new(r: f32, g: f32, b: f32, a: f32) -> Self {
        Self { r, g, b, a }
    }

    /// Opaque colour.
    #[must_use]
    pub const fn rgb(r: f32, g: f32, b: f32) -> Self {
        Self::new(r, g, b, 1.0)
    }

    /// From 8-bit encoded sRGB with alpha (alpha is linear already).
    #[must_use]
    pub fn from_srgb8(c: [u8; 4]) -> Self {
        let d = crate::transfer::srgb8_decode;
        Self::new(d(c[0]), d(c[1]), d(c[2]), f32::from(c[3]) / 255.0)
    }

    /// To 8-bit encoded sRGB with alpha, clamping to [0, 1] first (NaN becomes 0).
    #[must_use]
    pub fn to_srgb8(self) -> [u8; 4] {
        let e = |v: f32| crate::transfer::srgb8_f64(f64::from(v));
        [
            e(self.r),
            e(self.g),
            e(self.b),
            crate::transfer::unorm8(self.a),
        ]
    }

    /// The largest of r, g and b.
    #[must_use]
    pub fn max_component(self) -> f32 {
        self.r.max(self.g).max(self.b)
    }

    /// Every component (alpha included) clamped to [0, 1]; NaN becomes 0.
    #[must_use]
    pub fn clamped(self) -> Self {
        let c = |v: f32| finite_or_zero(v).clamp(0.0, 1.0);
        Self::new(c(self.r), c(self.g), c(self.b), c(self.a))
    }

    /// Divides r, g, b by the largest of them when it exceeds 1, keeping the hue and
    /// saturation (negative components are then clamped to 0); alpha is clamped.
    #[must_use]
    pub fn normalized_max(self) -> Self {
        let m = self.max_component();
        let s = if m > 1.0 { 1.0 / m } else { 1.0 };
        Self::new(self.r * s, self.g * s, self.b * s, self.a).clamped()
    }

    /// Reinhard tone mapping of the luminance, L / (1 + L), scaling r, g, b alike so the
    /// hue is kept; the result is then brought into range with [`Rgba::normalized_max`].
    #[must_use]
    pub fn reinhard(self) -> Self {
        let l = self.luminance();
        if l.is_nan() || l <= 0.0 || !l.is_finite() {
            return self.normalized_max();
        }
        let s = 1.0 / (1.0 + l);
        Self::new(self.r * s, self.g * s, self.b * s, self.a).normalized_max()
    }

    /// Relative luminance Y of linear BT.709/sRGB primaries.
    #[must_use]
    pub fn luminance(self) -> f32 {
        0.2126 * self.r + 0.7152 * self.g + 0.0722 * self.b
    }

    /// Linear interpolation `self + (other - self) * t`, alpha included.
    #[must_use]
    pub fn lerp(self, other: Self, t: f32) -> Self {
        self + (other - self) * t
    }

    /// Porter-Duff "source over": `self` drawn over `dst` (straight alpha).
    #[must_use]
    pub fn over(self, dst: Self) -> Self {
        let a = self.a + dst.a * (1.0 - self.a);
        if a <= 0.0 {
            return Self::TRANSPARENT;
        }
        let mix = |s: f32, d: f32| (s * self.a + d * dst.a * (1.0 - self.a)) / a;
        Self::new(
            mix(self.r, dst.r),
            mix(self.g, dst.g),
            mix(self.b, dst.b),
            a,
        )
    }
}

fn finite_or_zero(v: f32) -> f32 {
    if v.is_finite() {
        v
    } else if v == f32::INFINITY {
        f32::MAX
    } else {
        0.0
    }
}

impl Add for Rgba {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.r + o.r, self.g + o.g, self.b + o.b, self.a + o.a)
    }
}

impl AddAssign for Rgba {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Sub for Rgba {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.r - o.r, self.g - o.g, self.b - o.b, self.a - o.a)
    }
}

/// Component-wise product (modulation, e.g. light colour times material colour).
impl Mul for Rgba {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self::new(self.r * o.r, self.g * o.g, self.b * o.b, self.a * o.a)
    }
}

/// Scales every component, alpha included.
impl Mul<f32> for Rgba {
    type Output = Self;
    fn mul(self, s: f32) -> Self {
        Self::new(self.r * s, self.g * s, self.b * s, self.a * s)
    }
}

impl MulAssign<f32> for Rgba {
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}

impl Div<f32> for Rgba {
    type Output = Self;
    fn div(self, s: f32) -> Self {
        Self::new(self.r / s, self.g / s, self.b / s, self.a / s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_range_handling_keeps_hue_unless_clamped() {
        let c = Rgba::rgb(1.0, 2.0, 1.0);
        assert_eq!(c.clamped(), Rgba::WHITE);
        assert_eq!(c.normalized_max(), Rgba::rgb(0.5, 1.0, 0.5));
        let t = c.reinhard();
        assert!(
            t.max_component() <= 1.0 && (t.r - t.b).abs() < 1e-6 && t.g > t.r,
            "{t:?}"
        );
        assert!((t.g / t.r - 2.0).abs() < 1e-5, "ratios kept: {t:?}");
        assert_eq!(
            Rgba::rgb(f32::NAN, 0.5, 2.0).clamped(),
            Rgba::rgb(0.0, 0.5, 1.0)
        );
    }

    #[test]
    fn arithmetic_and_blending() {
        let a = Rgba::new(0.2, 0.4, 0.6, 1.0);
        let b = Rgba::new(0.5, 0.5, 0.5, 0.5);
        assert_eq!(a * b, Rgba::new(0.1, 0.2, 0.3, 0.5));
        assert_eq!((a + a) / 2.0, a);
        assert_eq!(a.lerp(b, 0.0), a);
        let o = b.over(a);
        assert!((o.r - 0.35).abs() < 1e-6 && o.a == 1.0, "{o:?}");
        assert_eq!(Rgba::TRANSPARENT.over(Rgba::TRANSPARENT), Rgba::TRANSPARENT);
        for v in [0u8, 1, 10, 128, 200, 255] {
            let c = Rgba::from_srgb8([v, v, v, v]);
            assert_eq!(c.to_srgb8(), [v; 4]);
        }
    }
}
