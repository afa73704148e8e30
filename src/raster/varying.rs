//! Values interpolated across triangles and along clipped edges.

use glam::{Vec2, Vec3, Vec4};

/// A value the rasterizer can interpolate: a vector space over f32.
///
/// Implemented for `()`, `f32`, `Vec2`, `Vec3`, `Vec4` and tuples of up to four varyings,
/// so a shader composes its varying from these without writing arithmetic.
pub trait Varying: Copy + Send + Sync + 'static {
    /// `self - other`.
    fn sub(&self, other: &Self) -> Self;
    /// `self + d1 * p1 + d2 * p2` (interpolation relative to vertex 0).
    fn mad2(&self, d1: &Self, p1: f32, d2: &Self, p2: f32) -> Self;
    /// `self + (other - self) * t`.
    fn lerp(&self, other: &Self, t: f32) -> Self;
    /// `d1 * p1 + d2 * p2` (a derivative from the differences to vertex 0).
    fn combine2(d1: &Self, p1: f32, d2: &Self, p2: f32) -> Self {
        d1.sub(d1).mad2(d1, p1, d2, p2)
    }
}

impl Varying for () {
    fn sub(&self, _: &Self) -> Self {}
    fn mad2(&self, _: &Self, _: f32, _: &Self, _: f32) -> Self {}
    fn lerp(&self, _: &Self, _: f32) -> Self {}
    fn combine2(_: &Self, _: f32, _: &Self, _: f32) -> Self {}
}

macro_rules! vector_varying {
    ($($t:ty),*) => {$(
        impl Varying for $t {
            #[inline(always)]
            fn sub(&self, other: &Self) -> Self {
                *self - *other
            }
            #[inline(always)]
            fn mad2(&self, d1: &Self, p1: f32, d2: &Self, p2: f32) -> Self {
                *self + *d1 * p1 + *d2 * p2
            }
            #[inline(always)]
            fn lerp(&self, other: &Self, t: f32) -> Self {
                *self + (*other - *self) * t
            }
            #[inline(always)]
            fn combine2(d1: &Self, p1: f32, d2: &Self, p2: f32) -> Self {
                *d1 * p1 + *d2 * p2
            }
        }
    )*};
}
vector_varying!(f32, Vec2, Vec3, Vec4);

macro_rules! tuple_varying {
    ($($n:tt $t:ident),*) => {
        impl<$($t: Varying),*> Varying for ($($t,)*) {
            #[inline(always)]
            fn sub(&self, other: &Self) -> Self {
                ($(self.$n.sub(&other.$n),)*)
            }
            #[inline(always)]
            fn mad2(&self, d1: &Self, p1: f32, d2: &Self, p2: f32) -> Self {
                ($(self.$n.mad2(&d1.$n, p1, &d2.$n, p2),)*)
            }
            #[inline(always)]
            fn lerp(&self, other: &Self, t: f32) -> Self {
                ($(self.$n.lerp(&other.$n, t),)*)
            }
            #[inline(always)]
            fn combine2(d1: &Self, p1: f32, d2: &Self, p2: f32) -> Self {
                ($($t::combine2(&d1.$n, p1, &d2.$n, p2),)*)
            }
        }
    };
}
tuple_varying!(0 A);
tuple_varying!(0 A, 1 B);
tuple_varying!(0 A, 1 B, 2 C);
tuple_varying!(0 A, 1 B, 2 C, 3 D);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tuple_arithmetic() {
        let a = (1.0f32, Vec2::new(1.0, 2.0));
        let b = (3.0f32, Vec2::new(5.0, 2.0));
        let d = b.sub(&a);
        assert_eq!(d, (2.0, Vec2::new(4.0, 0.0)));
        assert_eq!(a.lerp(&b, 0.5), (2.0, Vec2::new(3.0, 2.0)));
        assert_eq!(a.mad2(&d, 0.5, &d, 0.0), (2.0, Vec2::new(3.0, 2.0)));
        assert_eq!(
            <(f32, Vec2)>::combine2(&a, 2.0, &d, 0.5),
            (3.0, Vec2::new(4.0, 4.0))
        );
    }
}
