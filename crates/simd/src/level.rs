//! The instruction sets the lane types are built on: a [`Level`] gives the register types of
//! eight `f32` and eight `i32` lanes and their primitive operations, written with the
//! vector intrinsics of that instruction set, so every lane operation is one (or, in the
//! portable level, two) vector instructions by construction.
//!
//! | level | registers | where |
//! |---|---|---|
//! | [`Portable`] | two SSE2 registers (`__m128`, `__m128i`) | x86-64 without AVX2 (SSE2 is part of every x86-64 CPU) |
//! | [`Portable`] | `[f32; 8]`, `[i32; 8]` | other architectures |
//! | [`Avx2`] | one AVX register (`__m256`, `__m256i`) | the AVX2 and AVX-512 kernels |
//!
//! Why intrinsics: the lane types were `[f32; 8]` arrays with an eight-iteration loop per
//! operation, left to LLVM's vectorizer. In small functions that gave one 256-bit
//! instruction per operation; in the fill and the shaders it did not: LLVM rebuilt values
//! lane by lane, vectorized across the wrong index (four varyings instead of eight pixels),
//! split a vector into loads of 1, 4, 2 and 1 lanes, and computed the perspective division
//! as eight `divss`. Fixing each function by hand did not hold.
//!
//! Every level computes the same bits: each operation is one correctly rounded IEEE
//! operation (no fused multiply-add, no approximate reciprocal), and the few whose edge
//! cases differ between instruction sets are pinned to one definition here: [`Level::fmax`]
//! and [`Level::fmin`] are x86's `maxps`/`minps` (the second operand where either is NaN),
//! [`Level::to_int`] is x86's `cvttps2dq` (truncation; `i32::MIN` where the result does
//! not fit or the input is NaN), [`Level::floor`] is `roundps` toward negative infinity
//! (NaN stays NaN, -0 stays -0).
//!
//! ## Soundness
//! [`Avx2`]'s operations run AVX2 instructions. They are sound because a function generic
//! over a level is only ever instantiated with `Avx2` by [`per_kernel!`](crate::per_kernel)
//! and [`dispatch`](crate::kernel::dispatch), inside a function compiled with the AVX2
//! features and reached only after a run-time check found them. The level types live in
//! [`crate::kernel::__private`]: code outside this crate names them only through those two
//! macros and functions (a `#[doc(hidden)]` module, as macro internals are in other
//! crates).

#![allow(unsafe_code)]

use std::fmt::Debug;

/// Lanes of every level.
pub const LANES: usize = 8;

/// An instruction set for eight lanes of `f32` and `i32` (see the module docs). A mask is
/// an `I` whose lanes are all ones (true) or all zeros (false).
pub trait Level: Copy + Default + Debug + Send + Sync + 'static {
    /// Eight `f32`.
    type F: Copy + Send + Sync + 'static;
    /// Eight `i32`, or a mask.
    type I: Copy + Send + Sync + 'static;

    const F_ZERO: Self::F;
    const F_ONE: Self::F;
    /// 0, 1, ..., 7.
    const F_RAMP: Self::F;
    const I_ZERO: Self::I;

    fn splat(x: f32) -> Self::F;
    fn from_array(a: [f32; 8]) -> Self::F;
    fn to_array(a: Self::F) -> [f32; 8];
    fn add(a: Self::F, b: Self::F) -> Self::F;
    fn sub(a: Self::F, b: Self::F) -> Self::F;
    fn mul(a: Self::F, b: Self::F) -> Self::F;
    fn div(a: Self::F, b: Self::F) -> Self::F;
    /// `a > b ? a : b` per lane (`b` where either is NaN).
    fn fmax(a: Self::F, b: Self::F) -> Self::F;
    /// `a < b ? a : b` per lane (`b` where either is NaN).
    fn fmin(a: Self::F, b: Self::F) -> Self::F;
    fn sqrt(a: Self::F) -> Self::F;
    /// Toward negative infinity; NaN stays NaN, -0 stays -0.
    fn floor(a: Self::F) -> Self::F;
    /// Ordered comparisons (false where either is NaN).
    fn lt(a: Self::F, b: Self::F) -> Self::I;
    fn le(a: Self::F, b: Self::F) -> Self::I;
    fn eq(a: Self::F, b: Self::F) -> Self::I;
    /// `a` where the mask `m` is set, else `b`.
    fn select(m: Self::I, a: Self::F, b: Self::F) -> Self::F;
    /// The bits of the floats as integers, and back.
    fn bits(a: Self::F) -> Self::I;
    fn from_bits(a: Self::I) -> Self::F;
    /// Truncated toward zero; `i32::MIN` where the result does not fit or `a` is NaN.
    fn to_int(a: Self::F) -> Self::I;
    /// Rounded to the nearest float (ties to even).
    fn to_float(a: Self::I) -> Self::F;

    fn isplat(x: i32) -> Self::I;
    fn ifrom_array(a: [i32; 8]) -> Self::I;
    fn ito_array(a: Self::I) -> [i32; 8];
    fn iadd(a: Self::I, b: Self::I) -> Self::I;
    fn isub(a: Self::I, b: Self::I) -> Self::I;
    /// The low 32 bits of the product.
    fn imul(a: Self::I, b: Self::I) -> Self::I;
    fn and(a: Self::I, b: Self::I) -> Self::I;
    fn or(a: Self::I, b: Self::I) -> Self::I;
    fn xor(a: Self::I, b: Self::I) -> Self::I;
    /// `!a & b`.
    fn andnot(a: Self::I, b: Self::I) -> Self::I;
    fn shl<const N: i32>(a: Self::I) -> Self::I;
    /// Arithmetic (sign-filling) shift right.
    fn sra<const N: i32>(a: Self::I) -> Self::I;
    /// Logical shift right.
    fn srl<const N: i32>(a: Self::I) -> Self::I;
    fn ieq(a: Self::I, b: Self::I) -> Self::I;
    fn igt(a: Self::I, b: Self::I) -> Self::I;
    /// `a` where the mask `m` is set, else `b`.
    fn iselect(m: Self::I, a: Self::I, b: Self::I) -> Self::I;
    /// Bit `i` = the sign bit of lane `i`.
    fn movemask(a: Self::I) -> u32;
    /// The mask whose lane `i` is set where bit `i` of `bits` is.
    fn mask_of(bits: u32) -> Self::I;
}

/// The portable level (see the module docs).
#[derive(Clone, Copy, Debug, Default)]
pub struct Portable;

/// The AVX2 level (see the module docs, "Soundness").
#[derive(Clone, Copy, Debug, Default)]
pub struct Avx2;

/// The lane masks of bits 0..8, for [`Level::mask_of`].
const BIT_LANES: [i32; 8] = [1, 2, 4, 8, 16, 32, 64, 128];

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::{Avx2, Level, Portable, BIT_LANES};

    /// Two SSE registers.
    #[derive(Clone, Copy)]
    #[repr(C, align(32))]
    pub struct F4x2(__m128, __m128);

    #[derive(Clone, Copy)]
    #[repr(C, align(32))]
    pub struct I4x2(__m128i, __m128i);

    // SAFETY (every `transmute` below): `[f32; 8]`, `[i32; 8]`, `__m256`, `__m256i`, `F4x2`
    // and `I4x2` are 32 bytes of plain data with no invalid bit patterns; each transmute
    // reinterprets one as another of the same size.

    macro_rules! two {
        ($f:ident, $a:expr) => {
            unsafe { F4x2($f($a.0), $f($a.1)) }
        };
        ($f:ident, $a:expr, $b:expr) => {
            unsafe { F4x2($f($a.0, $b.0), $f($a.1, $b.1)) }
        };
    }
    macro_rules! itwo {
        ($f:ident, $a:expr) => {
            unsafe { I4x2($f($a.0), $f($a.1)) }
        };
        ($f:ident, $a:expr, $b:expr) => {
            unsafe { I4x2($f($a.0, $b.0), $f($a.1, $b.1)) }
        };
    }

    /// `floor` on SSE2 (no `roundps`): truncation corrected where it rounded up, the sign of
    /// the input kept (for -0), and the input itself where it is already whole (|x| >=
    /// 2^23, infinities) or NaN: `roundps`'s results, bit for bit.
    #[inline(always)]
    unsafe fn floor4(x: __m128) -> __m128 {
        let sign = _mm_set1_ps(-0.0);
        let t = _mm_cvtepi32_ps(_mm_cvttps_epi32(x));
        let up = _mm_and_ps(_mm_cmpgt_ps(t, x), _mm_set1_ps(1.0));
        let r = _mm_or_ps(_mm_sub_ps(t, up), _mm_and_ps(x, sign));
        let small = _mm_cmplt_ps(_mm_andnot_ps(sign, x), _mm_set1_ps(8_388_608.0));
        _mm_or_ps(_mm_and_ps(small, r), _mm_andnot_ps(small, x))
    }

    /// `pmulld` on SSE2: the low halves of two `pmuludq` products interleaved.
    #[inline(always)]
    unsafe fn mullo4(a: __m128i, b: __m128i) -> __m128i {
        let even = _mm_mul_epu32(a, b);
        let odd = _mm_mul_epu32(_mm_srli_epi64::<32>(a), _mm_srli_epi64::<32>(b));
        _mm_unpacklo_epi32(
            _mm_shuffle_epi32::<0b00_00_10_00>(even),
            _mm_shuffle_epi32::<0b00_00_10_00>(odd),
        )
    }

    #[inline(always)]
    unsafe fn select4(m: __m128i, a: __m128, b: __m128) -> __m128 {
        let m = _mm_castsi128_ps(m);
        _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b))
    }

    #[inline(always)]
    unsafe fn iselect4(m: __m128i, a: __m128i, b: __m128i) -> __m128i {
        _mm_or_si128(_mm_and_si128(m, a), _mm_andnot_si128(m, b))
    }

    #[inline(always)]
    unsafe fn cmplt(a: __m128, b: __m128) -> __m128i {
        _mm_castps_si128(_mm_cmplt_ps(a, b))
    }
    #[inline(always)]
    unsafe fn cmple(a: __m128, b: __m128) -> __m128i {
        _mm_castps_si128(_mm_cmple_ps(a, b))
    }
    #[inline(always)]
    unsafe fn cmpeq(a: __m128, b: __m128) -> __m128i {
        _mm_castps_si128(_mm_cmpeq_ps(a, b))
    }

    // SAFETY (every `unsafe` block in this impl and in the helpers above it): SSE and SSE2
    // are part of every x86-64 CPU (the baseline every x86-64 build targets); the
    // intrinsics only compute on registers.
    impl Level for Portable {
        type F = F4x2;
        type I = I4x2;

        const F_ZERO: F4x2 = unsafe { std::mem::transmute([0.0f32; 8]) };
        const F_ONE: F4x2 = unsafe { std::mem::transmute([1.0f32; 8]) };
        const F_RAMP: F4x2 =
            unsafe { std::mem::transmute([0.0f32, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]) };
        const I_ZERO: I4x2 = unsafe { std::mem::transmute([0i32; 8]) };

        #[inline(always)]
        fn splat(x: f32) -> F4x2 {
            unsafe {
                let v = _mm_set1_ps(x);
                F4x2(v, v)
            }
        }
        #[inline(always)]
        fn from_array(a: [f32; 8]) -> F4x2 {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn to_array(a: F4x2) -> [f32; 8] {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn add(a: F4x2, b: F4x2) -> F4x2 {
            two!(_mm_add_ps, a, b)
        }
        #[inline(always)]
        fn sub(a: F4x2, b: F4x2) -> F4x2 {
            two!(_mm_sub_ps, a, b)
        }
        #[inline(always)]
        fn mul(a: F4x2, b: F4x2) -> F4x2 {
            two!(_mm_mul_ps, a, b)
        }
        #[inline(always)]
        fn div(a: F4x2, b: F4x2) -> F4x2 {
            two!(_mm_div_ps, a, b)
        }
        #[inline(always)]
        fn fmax(a: F4x2, b: F4x2) -> F4x2 {
            two!(_mm_max_ps, a, b)
        }
        #[inline(always)]
        fn fmin(a: F4x2, b: F4x2) -> F4x2 {
            two!(_mm_min_ps, a, b)
        }
        #[inline(always)]
        fn sqrt(a: F4x2) -> F4x2 {
            two!(_mm_sqrt_ps, a)
        }
        #[inline(always)]
        fn floor(a: F4x2) -> F4x2 {
            two!(floor4, a)
        }
        #[inline(always)]
        fn lt(a: F4x2, b: F4x2) -> I4x2 {
            unsafe { I4x2(cmplt(a.0, b.0), cmplt(a.1, b.1)) }
        }
        #[inline(always)]
        fn le(a: F4x2, b: F4x2) -> I4x2 {
            unsafe { I4x2(cmple(a.0, b.0), cmple(a.1, b.1)) }
        }
        #[inline(always)]
        fn eq(a: F4x2, b: F4x2) -> I4x2 {
            unsafe { I4x2(cmpeq(a.0, b.0), cmpeq(a.1, b.1)) }
        }
        #[inline(always)]
        fn select(m: I4x2, a: F4x2, b: F4x2) -> F4x2 {
            unsafe { F4x2(select4(m.0, a.0, b.0), select4(m.1, a.1, b.1)) }
        }
        #[inline(always)]
        fn bits(a: F4x2) -> I4x2 {
            unsafe { I4x2(_mm_castps_si128(a.0), _mm_castps_si128(a.1)) }
        }
        #[inline(always)]
        fn from_bits(a: I4x2) -> F4x2 {
            unsafe { F4x2(_mm_castsi128_ps(a.0), _mm_castsi128_ps(a.1)) }
        }
        #[inline(always)]
        fn to_int(a: F4x2) -> I4x2 {
            unsafe { I4x2(_mm_cvttps_epi32(a.0), _mm_cvttps_epi32(a.1)) }
        }
        #[inline(always)]
        fn to_float(a: I4x2) -> F4x2 {
            unsafe { F4x2(_mm_cvtepi32_ps(a.0), _mm_cvtepi32_ps(a.1)) }
        }
        #[inline(always)]
        fn isplat(x: i32) -> I4x2 {
            unsafe {
                let v = _mm_set1_epi32(x);
                I4x2(v, v)
            }
        }
        #[inline(always)]
        fn ifrom_array(a: [i32; 8]) -> I4x2 {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn ito_array(a: I4x2) -> [i32; 8] {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn iadd(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_add_epi32, a, b)
        }
        #[inline(always)]
        fn isub(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_sub_epi32, a, b)
        }
        #[inline(always)]
        fn imul(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(mullo4, a, b)
        }
        #[inline(always)]
        fn and(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_and_si128, a, b)
        }
        #[inline(always)]
        fn or(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_or_si128, a, b)
        }
        #[inline(always)]
        fn xor(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_xor_si128, a, b)
        }
        #[inline(always)]
        fn andnot(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_andnot_si128, a, b)
        }
        #[inline(always)]
        fn shl<const N: i32>(a: I4x2) -> I4x2 {
            unsafe { I4x2(_mm_slli_epi32::<N>(a.0), _mm_slli_epi32::<N>(a.1)) }
        }
        #[inline(always)]
        fn sra<const N: i32>(a: I4x2) -> I4x2 {
            unsafe { I4x2(_mm_srai_epi32::<N>(a.0), _mm_srai_epi32::<N>(a.1)) }
        }
        #[inline(always)]
        fn srl<const N: i32>(a: I4x2) -> I4x2 {
            unsafe { I4x2(_mm_srli_epi32::<N>(a.0), _mm_srli_epi32::<N>(a.1)) }
        }
        #[inline(always)]
        fn ieq(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_cmpeq_epi32, a, b)
        }
        #[inline(always)]
        fn igt(a: I4x2, b: I4x2) -> I4x2 {
            itwo!(_mm_cmpgt_epi32, a, b)
        }
        #[inline(always)]
        fn iselect(m: I4x2, a: I4x2, b: I4x2) -> I4x2 {
            unsafe { I4x2(iselect4(m.0, a.0, b.0), iselect4(m.1, a.1, b.1)) }
        }
        #[inline(always)]
        fn movemask(a: I4x2) -> u32 {
            unsafe {
                let lo = _mm_movemask_ps(_mm_castsi128_ps(a.0)) as u32;
                let hi = _mm_movemask_ps(_mm_castsi128_ps(a.1)) as u32;
                lo | hi << 4
            }
        }
        #[inline(always)]
        fn mask_of(bits: u32) -> I4x2 {
            let b = Self::isplat(bits as i32);
            let lanes = Self::ifrom_array(BIT_LANES);
            Self::ieq(Self::and(b, lanes), lanes)
        }
    }

    // SAFETY (every `unsafe` block in this impl): the AVX and AVX2 intrinsics need a CPU
    // with those features. `Avx2` is instantiated only inside functions that
    // `per_kernel!` and `dispatch` compile with AVX2 enabled and call only after
    // `KernelKind::Avx2.available()` (or `Avx512.available()`, which implies it) found the
    // CPU has them (see the module docs, "Soundness").
    impl Level for Avx2 {
        type F = __m256;
        type I = __m256i;

        const F_ZERO: __m256 = unsafe { std::mem::transmute([0.0f32; 8]) };
        const F_ONE: __m256 = unsafe { std::mem::transmute([1.0f32; 8]) };
        const F_RAMP: __m256 =
            unsafe { std::mem::transmute([0.0f32, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]) };
        const I_ZERO: __m256i = unsafe { std::mem::transmute([0i32; 8]) };

        #[inline(always)]
        fn splat(x: f32) -> __m256 {
            unsafe { _mm256_set1_ps(x) }
        }
        #[inline(always)]
        fn from_array(a: [f32; 8]) -> __m256 {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn to_array(a: __m256) -> [f32; 8] {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn add(a: __m256, b: __m256) -> __m256 {
            unsafe { _mm256_add_ps(a, b) }
        }
        #[inline(always)]
        fn sub(a: __m256, b: __m256) -> __m256 {
            unsafe { _mm256_sub_ps(a, b) }
        }
        #[inline(always)]
        fn mul(a: __m256, b: __m256) -> __m256 {
            unsafe { _mm256_mul_ps(a, b) }
        }
        #[inline(always)]
        fn div(a: __m256, b: __m256) -> __m256 {
            unsafe { _mm256_div_ps(a, b) }
        }
        #[inline(always)]
        fn fmax(a: __m256, b: __m256) -> __m256 {
            unsafe { _mm256_max_ps(a, b) }
        }
        #[inline(always)]
        fn fmin(a: __m256, b: __m256) -> __m256 {
            unsafe { _mm256_min_ps(a, b) }
        }
        #[inline(always)]
        fn sqrt(a: __m256) -> __m256 {
            unsafe { _mm256_sqrt_ps(a) }
        }
        #[inline(always)]
        fn floor(a: __m256) -> __m256 {
            unsafe { _mm256_floor_ps(a) }
        }
        #[inline(always)]
        fn lt(a: __m256, b: __m256) -> __m256i {
            unsafe { _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(a, b)) }
        }
        #[inline(always)]
        fn le(a: __m256, b: __m256) -> __m256i {
            unsafe { _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(a, b)) }
        }
        #[inline(always)]
        fn eq(a: __m256, b: __m256) -> __m256i {
            unsafe { _mm256_castps_si256(_mm256_cmp_ps::<_CMP_EQ_OQ>(a, b)) }
        }
        #[inline(always)]
        fn select(m: __m256i, a: __m256, b: __m256) -> __m256 {
            unsafe { _mm256_blendv_ps(b, a, _mm256_castsi256_ps(m)) }
        }
        #[inline(always)]
        fn bits(a: __m256) -> __m256i {
            unsafe { _mm256_castps_si256(a) }
        }
        #[inline(always)]
        fn from_bits(a: __m256i) -> __m256 {
            unsafe { _mm256_castsi256_ps(a) }
        }
        #[inline(always)]
        fn to_int(a: __m256) -> __m256i {
            unsafe { _mm256_cvttps_epi32(a) }
        }
        #[inline(always)]
        fn to_float(a: __m256i) -> __m256 {
            unsafe { _mm256_cvtepi32_ps(a) }
        }
        #[inline(always)]
        fn isplat(x: i32) -> __m256i {
            unsafe { _mm256_set1_epi32(x) }
        }
        #[inline(always)]
        fn ifrom_array(a: [i32; 8]) -> __m256i {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn ito_array(a: __m256i) -> [i32; 8] {
            unsafe { std::mem::transmute(a) }
        }
        #[inline(always)]
        fn iadd(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_add_epi32(a, b) }
        }
        #[inline(always)]
        fn isub(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_sub_epi32(a, b) }
        }
        #[inline(always)]
        fn imul(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_mullo_epi32(a, b) }
        }
        #[inline(always)]
        fn and(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_and_si256(a, b) }
        }
        #[inline(always)]
        fn or(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_or_si256(a, b) }
        }
        #[inline(always)]
        fn xor(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_xor_si256(a, b) }
        }
        #[inline(always)]
        fn andnot(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_andnot_si256(a, b) }
        }
        #[inline(always)]
        fn shl<const N: i32>(a: __m256i) -> __m256i {
            unsafe { _mm256_slli_epi32::<N>(a) }
        }
        #[inline(always)]
        fn sra<const N: i32>(a: __m256i) -> __m256i {
            unsafe { _mm256_srai_epi32::<N>(a) }
        }
        #[inline(always)]
        fn srl<const N: i32>(a: __m256i) -> __m256i {
            unsafe { _mm256_srli_epi32::<N>(a) }
        }
        #[inline(always)]
        fn ieq(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_cmpeq_epi32(a, b) }
        }
        #[inline(always)]
        fn igt(a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_cmpgt_epi32(a, b) }
        }
        #[inline(always)]
        fn iselect(m: __m256i, a: __m256i, b: __m256i) -> __m256i {
            unsafe { _mm256_blendv_epi8(b, a, m) }
        }
        #[inline(always)]
        fn movemask(a: __m256i) -> u32 {
            unsafe { _mm256_movemask_ps(_mm256_castsi256_ps(a)) as u32 }
        }
        #[inline(always)]
        fn mask_of(bits: u32) -> __m256i {
            let b = Self::isplat(bits as i32);
            let lanes = Self::ifrom_array(BIT_LANES);
            Self::ieq(Self::and(b, lanes), lanes)
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod arrays {
    //! The portable level off x86-64: arrays and a loop per operation, with x86's
    //! definitions of the edge cases (see the module docs).
    use super::{Avx2, Level, Portable, BIT_LANES};

    macro_rules! lanes {
        (|$($a:ident),*| $e:expr) => {{
            let mut r = [Default::default(); 8];
            for i in 0..8 {
                $(let $a = $a[i];)*
                r[i] = $e;
            }
            r
        }};
    }

    fn floor1(x: f32) -> f32 {
        x.floor()
    }

    impl Level for Portable {
        type F = [f32; 8];
        type I = [i32; 8];
        const F_ZERO: [f32; 8] = [0.0; 8];
        const F_ONE: [f32; 8] = [1.0; 8];
        const F_RAMP: [f32; 8] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        const I_ZERO: [i32; 8] = [0; 8];
        fn splat(x: f32) -> [f32; 8] {
            [x; 8]
        }
        fn from_array(a: [f32; 8]) -> [f32; 8] {
            a
        }
        fn to_array(a: [f32; 8]) -> [f32; 8] {
            a
        }
        fn add(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            lanes!(|a, b| a + b)
        }
        fn sub(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            lanes!(|a, b| a - b)
        }
        fn mul(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            lanes!(|a, b| a * b)
        }
        fn div(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            lanes!(|a, b| a / b)
        }
        fn fmax(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            lanes!(|a, b| if a > b { a } else { b })
        }
        fn fmin(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            lanes!(|a, b| if a < b { a } else { b })
        }
        fn sqrt(a: [f32; 8]) -> [f32; 8] {
            lanes!(|a| a.sqrt())
        }
        fn floor(a: [f32; 8]) -> [f32; 8] {
            lanes!(|a| floor1(a))
        }
        fn lt(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
            lanes!(|a, b| -i32::from(a < b))
        }
        fn le(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
            lanes!(|a, b| -i32::from(a <= b))
        }
        fn eq(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
            lanes!(|a, b| -i32::from(a == b))
        }
        fn select(m: [i32; 8], a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            lanes!(|m, a, b| if m < 0 { a } else { b })
        }
        fn bits(a: [f32; 8]) -> [i32; 8] {
            lanes!(|a| a.to_bits() as i32)
        }
        fn from_bits(a: [i32; 8]) -> [f32; 8] {
            lanes!(|a| f32::from_bits(a as u32))
        }
        fn to_int(a: [f32; 8]) -> [i32; 8] {
            lanes!(|a| if a > -2147483904.0 && a < 2147483648.0 {
                a as i32
            } else {
                i32::MIN
            })
        }
        fn to_float(a: [i32; 8]) -> [f32; 8] {
            lanes!(|a| a as f32)
        }
        fn isplat(x: i32) -> [i32; 8] {
            [x; 8]
        }
        fn ifrom_array(a: [i32; 8]) -> [i32; 8] {
            a
        }
        fn ito_array(a: [i32; 8]) -> [i32; 8] {
            a
        }
        fn iadd(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| a.wrapping_add(b))
        }
        fn isub(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| a.wrapping_sub(b))
        }
        fn imul(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| a.wrapping_mul(b))
        }
        fn and(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| a & b)
        }
        fn or(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| a | b)
        }
        fn xor(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| a ^ b)
        }
        fn andnot(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| !a & b)
        }
        fn shl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
            lanes!(|a| a << N)
        }
        fn sra<const N: i32>(a: [i32; 8]) -> [i32; 8] {
            lanes!(|a| a >> N)
        }
        fn srl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
            lanes!(|a| ((a as u32) >> N) as i32)
        }
        fn ieq(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| -i32::from(a == b))
        }
        fn igt(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|a, b| -i32::from(a > b))
        }
        fn iselect(m: [i32; 8], a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            lanes!(|m, a, b| if m < 0 { a } else { b })
        }
        fn movemask(a: [i32; 8]) -> u32 {
            let mut b = 0;
            for (i, v) in a.iter().enumerate() {
                b |= u32::from(*v < 0) << i;
            }
            b
        }
        fn mask_of(bits: u32) -> [i32; 8] {
            lanes!(|BIT_LANES| -i32::from(bits as i32 & BIT_LANES != 0))
        }
    }

    /// Off x86-64 the AVX2 level is never instantiated (no kernel uses it); it repeats the
    /// portable one so generic code compiles.
    impl Level for Avx2 {
        type F = [f32; 8];
        type I = [i32; 8];
        const F_ZERO: [f32; 8] = Portable::F_ZERO;
        const F_ONE: [f32; 8] = Portable::F_ONE;
        const F_RAMP: [f32; 8] = Portable::F_RAMP;
        const I_ZERO: [i32; 8] = Portable::I_ZERO;
        fn splat(x: f32) -> [f32; 8] {
            Portable::splat(x)
        }
        fn from_array(a: [f32; 8]) -> [f32; 8] {
            a
        }
        fn to_array(a: [f32; 8]) -> [f32; 8] {
            a
        }
        fn add(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            Portable::add(a, b)
        }
        fn sub(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            Portable::sub(a, b)
        }
        fn mul(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            Portable::mul(a, b)
        }
        fn div(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            Portable::div(a, b)
        }
        fn fmax(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            Portable::fmax(a, b)
        }
        fn fmin(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            Portable::fmin(a, b)
        }
        fn sqrt(a: [f32; 8]) -> [f32; 8] {
            Portable::sqrt(a)
        }
        fn floor(a: [f32; 8]) -> [f32; 8] {
            Portable::floor(a)
        }
        fn lt(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
            Portable::lt(a, b)
        }
        fn le(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
            Portable::le(a, b)
        }
        fn eq(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
            Portable::eq(a, b)
        }
        fn select(m: [i32; 8], a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
            Portable::select(m, a, b)
        }
        fn bits(a: [f32; 8]) -> [i32; 8] {
            Portable::bits(a)
        }
        fn from_bits(a: [i32; 8]) -> [f32; 8] {
            Portable::from_bits(a)
        }
        fn to_int(a: [f32; 8]) -> [i32; 8] {
            Portable::to_int(a)
        }
        fn to_float(a: [i32; 8]) -> [f32; 8] {
            Portable::to_float(a)
        }
        fn isplat(x: i32) -> [i32; 8] {
            [x; 8]
        }
        fn ifrom_array(a: [i32; 8]) -> [i32; 8] {
            a
        }
        fn ito_array(a: [i32; 8]) -> [i32; 8] {
            a
        }
        fn iadd(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::iadd(a, b)
        }
        fn isub(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::isub(a, b)
        }
        fn imul(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::imul(a, b)
        }
        fn and(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::and(a, b)
        }
        fn or(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::or(a, b)
        }
        fn xor(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::xor(a, b)
        }
        fn andnot(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::andnot(a, b)
        }
        fn shl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
            Portable::shl::<N>(a)
        }
        fn sra<const N: i32>(a: [i32; 8]) -> [i32; 8] {
            Portable::sra::<N>(a)
        }
        fn srl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
            Portable::srl::<N>(a)
        }
        fn ieq(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::ieq(a, b)
        }
        fn igt(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::igt(a, b)
        }
        fn iselect(m: [i32; 8], a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
            Portable::iselect(m, a, b)
        }
        fn movemask(a: [i32; 8]) -> u32 {
            Portable::movemask(a)
        }
        fn mask_of(bits: u32) -> [i32; 8] {
            Portable::mask_of(bits)
        }
    }
}
