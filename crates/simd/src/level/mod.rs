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
mod x86;

#[cfg(not(target_arch = "x86_64"))]
mod arrays;
