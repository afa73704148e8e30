//! The number the ray-traced shading is written over: `f32` where it renders, `f64` where
//! it is the reference ([`crate::path::path_image_f64`]). The surface at a hit, its lights
//! and the path tracer's transport are generic over [`Scalar`]; the scene's data (vertices,
//! matrices, textures) are `f32` either way and widen on the way in.

use glam::{DVec3, Mat3, Mat4, Vec3};

use crate::shade::Real;
use crate::shade::Shade;

/// `f32` or `f64`, with the vector operations the traced shading needs beyond
/// [`realist_simd::real::Num`]'s (each one glam's own, so the `f32` copy computes exactly
/// what the `f32` code did).
pub trait Scalar: Shade + Real {
    /// `m * v`.
    fn mat3(m: Mat3, v: Self::V) -> Self::V;
    /// `m` applied to point `p`.
    fn point(m: Mat4, p: Vec3) -> Self::V;
    fn vdiv(v: Self::V, s: Self) -> Self::V;
    fn vmaxv(a: Self::V, b: Self::V) -> Self::V;
    fn vabs(v: Self::V) -> Self::V;
    fn vpowf(v: Self::V, e: Self) -> Self::V;
    fn vfinite(v: Self::V) -> bool;
    fn sin(self) -> Self;
    fn abs(self) -> Self;
    fn copysign(self, sign: Self) -> Self;
    /// Every component 0 (as `v == Vec3::ZERO`).
    fn is_zero(v: Self::V) -> bool;
}

macro_rules! scalar {
    ($t:ty, $v:ty, $m3:expr, $m4:expr, $p:expr, $sin:path) => {
        impl Scalar for $t {
            #[inline(always)]
            fn mat3(m: Mat3, v: $v) -> $v {
                $m3(m) * v
            }
            #[inline(always)]
            fn point(m: Mat4, p: Vec3) -> $v {
                $m4(m).transform_point3($p(p))
            }
            #[inline(always)]
            fn vdiv(v: $v, s: $t) -> $v {
                v / s
            }
            #[inline(always)]
            fn vmaxv(a: $v, b: $v) -> $v {
                a.max(b)
            }
            #[inline(always)]
            fn vabs(v: $v) -> $v {
                v.abs()
            }
            #[inline(always)]
            fn vpowf(v: $v, e: $t) -> $v {
                v.powf(e)
            }
            #[inline(always)]
            fn vfinite(v: $v) -> bool {
                v.is_finite()
            }
            #[inline(always)]
            fn sin(self) -> $t {
                // The `libm` crate's, not the platform's: the same bits everywhere.
                $sin(self)
            }
            #[inline(always)]
            fn abs(self) -> $t {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn copysign(self, sign: $t) -> $t {
                <$t>::copysign(self, sign)
            }
            #[inline(always)]
            fn is_zero(v: $v) -> bool {
                v == <$v>::ZERO
            }
        }
    };
}

scalar!(f32, Vec3, |m| m, |m| m, |p| p, libm::sinf);
scalar!(
    f64,
    DVec3,
    |m: Mat3| m.as_dmat3(),
    |m: Mat4| m.as_dmat4(),
    |p: Vec3| p.as_dvec3(),
    libm::sin
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_f64_copy_widens_before_it_computes() {
        // 1 + 2^-30 is 1 in f32: the f64 copy keeps it, the f32 copy loses it.
        let m = Mat4::from_translation(Vec3::new(1.0, 0.0, 0.0));
        let p = Vec3::new(2f32.powi(-30), 0.0, 0.0);
        assert_eq!(<f32 as Scalar>::point(m, p).x, 1.0);
        assert!(<f64 as Scalar>::point(m, p).x > 1.0);
        let n = Mat3::from_diagonal(Vec3::new(2.0, 3.0, 4.0));
        assert_eq!(
            <f64 as Scalar>::mat3(n, DVec3::ONE),
            DVec3::new(2.0, 3.0, 4.0)
        );
        assert!(<f32 as Scalar>::is_zero(Vec3::new(0.0, -0.0, 0.0)));
        assert!(!<f64 as Scalar>::is_zero(DVec3::new(0.0, f64::NAN, 0.0)));
    }
}
