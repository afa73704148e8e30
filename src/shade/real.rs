//! The scalar number types the lighting model is written over: `f32` (the renderer's vertex
//! stage and pixel probe) and `f64` (the references in [`crate::quality`]). The eight-lane
//! kernels have their own arithmetic ([`crate::raster::F8`]) and are tested against the
//! scalar model.

use std::ops::{Add, Div, Mul, Neg, Sub};

use glam::{DVec3, Vec3};

/// A float type with a matching 3-vector.
pub trait Real:
    Copy
    + PartialOrd
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Send
    + Sync
    + 'static
{
    /// The 3-vector of this precision (`Vec3` or `DVec3`).
    type V: Copy
        + std::fmt::Debug
        + PartialEq
        + Add<Output = Self::V>
        + Sub<Output = Self::V>
        + Mul<Output = Self::V>
        + Mul<Self, Output = Self::V>
        + Neg<Output = Self::V>;

    const ZERO: Self;
    const ONE: Self;

    fn of(x: f32) -> Self;
    fn of64(x: f64) -> Self;
    fn to_f64(self) -> f64;
    fn vec(v: Vec3) -> Self::V;
    fn to_vec3(v: Self::V) -> Vec3;
    fn splat(x: Self) -> Self::V;
    fn dot(a: Self::V, b: Self::V) -> Self;
    fn cross(a: Self::V, b: Self::V) -> Self::V;
    fn new3(x: Self, y: Self, z: Self) -> Self::V;
    fn normalize_or_zero(a: Self::V) -> Self::V;
    fn sqrt(self) -> Self;
    fn powf(self, e: Self) -> Self;
    fn is_finite(self) -> bool;
    fn vmax(a: Self::V) -> Self;

    #[inline(always)]
    fn max(self, o: Self) -> Self {
        if self > o {
            self
        } else {
            o
        }
    }

    #[inline(always)]
    fn min(self, o: Self) -> Self {
        if self < o {
            self
        } else {
            o
        }
    }

    #[inline(always)]
    fn clamp01(self) -> Self {
        self.max(Self::ZERO).min(Self::ONE)
    }

    #[inline(always)]
    fn length(a: Self::V) -> Self {
        Self::dot(a, a).sqrt()
    }
}

macro_rules! real {
    ($t:ty, $v:ty, $from:expr, $to:expr) => {
        impl Real for $t {
            type V = $v;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline(always)]
            fn of(x: f32) -> Self {
                x as $t
            }
            #[inline(always)]
            fn of64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn vec(v: Vec3) -> $v {
                $from(v)
            }
            #[inline(always)]
            fn to_vec3(v: $v) -> Vec3 {
                $to(v)
            }
            #[inline(always)]
            fn splat(x: Self) -> $v {
                <$v>::splat(x)
            }
            #[inline(always)]
            fn dot(a: $v, b: $v) -> Self {
                a.dot(b)
            }
            #[inline(always)]
            fn cross(a: $v, b: $v) -> $v {
                a.cross(b)
            }
            #[inline(always)]
            fn new3(x: Self, y: Self, z: Self) -> $v {
                <$v>::new(x, y, z)
            }
            #[inline(always)]
            fn normalize_or_zero(a: $v) -> $v {
                a.normalize_or_zero()
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn powf(self, e: Self) -> Self {
                <$t>::powf(self, e)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn vmax(a: $v) -> Self {
                a.max_element()
            }
        }
    };
}

real!(f32, Vec3, |v| v, |v| v);
real!(f64, DVec3, |v: Vec3| v.as_dvec3(), |v: DVec3| v.as_vec3());
