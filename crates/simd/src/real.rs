//! The number types the lighting model is written over, behind one trait ([`Num`]):
//!
//! - `f32`: the renderer's vertex stage and pixel probe;
//! - `f64`: the references in [`crate::quality`];
//! - [`Lanes<K>`]: eight f32 lanes compiled for kernel `K`, what the pixel shaders run.
//!
//! Code over [`Num`] is written the way lane code must be: a comparison gives a mask
//! ([`Num::M`], `bool` for scalars, [`M8`] for lanes), a decision is a [`Num::select`], and
//! an early exit asks whether [`Num::any`] lane needs the work. For `f32` and `f64` these
//! compile to the plain `if` they replace. [`Real`] adds what only a scalar has (ordering,
//! conversion to `f64`), for code that is never run on lanes.

use std::marker::PhantomData;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use glam::{DVec3, Vec3};

use super::lanes::{Kernel, F8, M8, V3};

/// A float type (scalar or lanes) with a matching 3-vector and mask.
pub trait Num:
    Copy
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
    /// The 3-vector of this type (`Vec3`, `DVec3` or [`V3`]).
    type V: Copy
        + std::fmt::Debug
        + Add<Output = Self::V>
        + Sub<Output = Self::V>
        + Mul<Output = Self::V>
        + Mul<Self, Output = Self::V>
        + Neg<Output = Self::V>;
    /// The result of a comparison (`bool`, or [`M8`] for lanes).
    type M: Copy
        + std::fmt::Debug
        + BitAnd<Output = Self::M>
        + BitOr<Output = Self::M>
        + Not<Output = Self::M>;

    const ZERO: Self;
    const ONE: Self;

    fn of(x: f32) -> Self;
    fn of64(x: f64) -> Self;
    fn vec(v: Vec3) -> Self::V;
    fn splat(x: Self) -> Self::V;
    fn dot(a: Self::V, b: Self::V) -> Self;
    fn cross(a: Self::V, b: Self::V) -> Self::V;
    fn new3(x: Self, y: Self, z: Self) -> Self::V;
    /// The components of `v`.
    fn xyz(v: Self::V) -> [Self; 3];
    fn normalize_or_zero(a: Self::V) -> Self::V;
    fn sqrt(self) -> Self;
    /// `self^e` for `self > 0`; the value for `self <= 0` is unspecified (select it away).
    fn powf(self, e: Self) -> Self;
    /// `self^n` for a whole `n` and `self > 0` (for `self <= 0` unspecified: select it
    /// away), by repeated squaring with every factor clamped at 2^-60, in every type: the
    /// steps of [`F8::powi`], so scalar f32 (the vertex stage) and lanes agree bit for bit.
    fn powi(self, n: u32) -> Self;
    fn gt(self, o: Self) -> Self::M;
    fn ge(self, o: Self) -> Self::M;
    /// Where the value is finite.
    fn finite(self) -> Self::M;
    /// `a` where `m` holds, else `b`.
    fn select(m: Self::M, a: Self, b: Self) -> Self;
    /// Whether `m` holds anywhere (in any lane).
    fn any(m: Self::M) -> bool;
    /// `a * b + c`, fused where the lanes' kernel has FMA (scalars: not fused, so scalar
    /// results do not depend on the build's target features).
    #[inline(always)]
    fn mul_add(a: Self, b: Self, c: Self) -> Self {
        a * b + c
    }

    /// `1 / self`.
    #[inline(always)]
    fn recip(self) -> Self {
        Self::ONE / self
    }

    #[inline(always)]
    fn lt(self, o: Self) -> Self::M {
        o.gt(self)
    }

    #[inline(always)]
    fn le(self, o: Self) -> Self::M {
        o.ge(self)
    }

    /// `a` where `m` holds, else `b`, per component.
    #[inline(always)]
    fn vselect(m: Self::M, a: Self::V, b: Self::V) -> Self::V {
        let (a, b) = (Self::xyz(a), Self::xyz(b));
        Self::new3(
            Self::select(m, a[0], b[0]),
            Self::select(m, a[1], b[1]),
            Self::select(m, a[2], b[2]),
        )
    }

    /// The larger of the two; `NaN` in `self` gives `o`.
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Self::select(self.gt(o), self, o)
    }

    /// The smaller of the two; `NaN` in `self` gives `o`.
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        Self::select(o.gt(self), self, o)
    }

    /// Clamped to [0, 1]; `NaN` gives 0.
    #[inline(always)]
    fn clamp01(self) -> Self {
        self.max(Self::ZERO).min(Self::ONE)
    }

    #[inline(always)]
    fn length(a: Self::V) -> Self {
        Self::dot(a, a).sqrt()
    }

    /// The largest component.
    #[inline(always)]
    fn vmax(a: Self::V) -> Self {
        let [x, y, z] = Self::xyz(a);
        x.max(y).max(z)
    }
}

/// A scalar [`Num`]: ordered, convertible to `f64`.
pub trait Real: Num<M = bool> + PartialOrd {
    fn to_f64(self) -> f64;
    fn to_vec3(v: Self::V) -> Vec3;
    #[inline(always)]
    fn is_finite(self) -> bool {
        self.finite()
    }
}

macro_rules! real {
    ($t:ty, $v:ty, $from:expr, $to:expr) => {
        impl Num for $t {
            type V = $v;
            type M = bool;
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
            fn vec(v: Vec3) -> $v {
                $from(v)
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
            fn xyz(v: $v) -> [Self; 3] {
                v.to_array()
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
            fn powi(self, n: u32) -> Self {
                // The steps of `F8::powi`, one value at a time (so scalar f32 and lanes
                // agree bit for bit; f64 rounds 2^-29 times finer).
                let tiny = <$t>::from(super::lanes::TINY_FACTOR);
                let floor = |v: $t| if v > tiny { v } else { tiny };
                super::lanes::powi_by_squaring(self, n, floor, 1.0)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> bool {
                self > o
            }
            #[inline(always)]
            fn ge(self, o: Self) -> bool {
                self >= o
            }
            #[inline(always)]
            fn finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn select(m: bool, a: Self, b: Self) -> Self {
                if m {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn vselect(m: bool, a: $v, b: $v) -> $v {
                if m {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn any(m: bool) -> bool {
                m
            }
            #[inline(always)]
            fn vmax(a: $v) -> Self {
                a.max_element()
            }
        }

        impl Real for $t {
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn to_vec3(v: $v) -> Vec3 {
                $to(v)
            }
        }
    };
}

real!(f32, Vec3, |v| v, |v| v);
real!(f64, DVec3, |v: Vec3| v.as_dvec3(), |v: DVec3| v.as_vec3());

/// Eight f32 lanes as a [`Num`], compiled for kernel `K` (which decides whether
/// [`Num::mul_add`], the dot product and `pow` use FMA). A thin wrapper: `Lanes(f8)` and
/// `.0` convert for free, and its vector is the kernel-free [`V3`].
pub struct Lanes<K>(pub F8, pub PhantomData<K>);

impl<K> Clone for Lanes<K> {
    #[inline(always)]
    fn clone(&self) -> Self {
        *self
    }
}

impl<K> Copy for Lanes<K> {}

impl<K> std::fmt::Debug for Lanes<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl<K> Lanes<K> {
    #[inline(always)]
    #[must_use]
    pub fn new(f: F8) -> Self {
        Lanes(f, PhantomData)
    }
}

impl<K: Kernel> From<F8> for Lanes<K> {
    #[inline(always)]
    fn from(f: F8) -> Self {
        Lanes::new(f)
    }
}

macro_rules! lane_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<K: Kernel> $tr for Lanes<K> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                Lanes::new(self.0 $op o.0)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl<K: Kernel> Neg for Lanes<K> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Lanes::new(-self.0)
    }
}

/// A vector scaled per lane.
impl<K: Kernel> Mul<Lanes<K>> for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, s: Lanes<K>) -> V3 {
        self.scale(s.0)
    }
}

impl<K: Kernel> Num for Lanes<K> {
    type V = V3;
    type M = M8;
    const ZERO: Self = Lanes(F8::ZERO, PhantomData);
    const ONE: Self = Lanes(F8::ONE, PhantomData);
    #[inline(always)]
    fn of(x: f32) -> Self {
        Lanes::new(F8::splat(x))
    }
    #[inline(always)]
    fn of64(x: f64) -> Self {
        Lanes::new(F8::splat(x as f32))
    }
    #[inline(always)]
    fn vec(v: Vec3) -> V3 {
        V3::splat(v)
    }
    #[inline(always)]
    fn splat(x: Self) -> V3 {
        V3::new(x.0, x.0, x.0)
    }
    #[inline(always)]
    fn dot(a: V3, b: V3) -> Self {
        Lanes::new(a.dot::<K>(b))
    }
    #[inline(always)]
    fn cross(a: V3, b: V3) -> V3 {
        a.cross::<K>(b)
    }
    #[inline(always)]
    fn new3(x: Self, y: Self, z: Self) -> V3 {
        V3::new(x.0, y.0, z.0)
    }
    #[inline(always)]
    fn xyz(v: V3) -> [Self; 3] {
        [Lanes::new(v.x), Lanes::new(v.y), Lanes::new(v.z)]
    }
    #[inline(always)]
    fn normalize_or_zero(a: V3) -> V3 {
        a.normalize_or_zero::<K>()
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Lanes::new(self.0.sqrt())
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        Lanes::new(self.0.powf::<K>(e.0))
    }
    #[inline(always)]
    fn powi(self, n: u32) -> Self {
        Lanes::new(self.0.powi(n))
    }
    #[inline(always)]
    fn gt(self, o: Self) -> M8 {
        self.0.gt(o.0)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> M8 {
        self.0.ge(o.0)
    }
    #[inline(always)]
    fn finite(self) -> M8 {
        self.0.abs().lt(F8::splat(f32::INFINITY))
    }
    #[inline(always)]
    fn select(m: M8, a: Self, b: Self) -> Self {
        Lanes::new(F8::select(m, a.0, b.0))
    }
    #[inline(always)]
    fn any(m: M8) -> bool {
        m.bits() != 0
    }
    #[inline(always)]
    fn mul_add(a: Self, b: Self, c: Self) -> Self {
        Lanes::new(K::fma(a.0, b.0, c.0))
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Lanes::new(self.0.max(o.0))
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        Lanes::new(self.0.min(o.0))
    }
}
