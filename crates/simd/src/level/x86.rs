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
