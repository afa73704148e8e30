//! Kernel choice and dispatch: the one place in the crate with `unsafe`.
//!
//! The fill loop and the shaders are written once, generic over a [`Kernel`] type, against
//! the eight-lane values of [`super::lanes`]. A kernel is the instruction set that generic
//! code is compiled for:
//!
//! | kernel | compiled with | FMA |
//! |---|---|---|
//! | [`KernelKind::Portable`] | the build's baseline (SSE2 on x86-64) | no |
//! | [`KernelKind::Avx2`] | AVX2 + FMA (+ POPCNT, BMI1/2) | yes |
//! | [`KernelKind::Avx512`] | AVX-512 F/VL/BW/DQ + AVX2 + FMA | yes |
//!
//! The best kernel the CPU has is detected once ([`KernelKind::best`]); `REALIST_KERNEL=
//! portable|avx2|avx512` or a renderer setting forces one (a kernel the CPU lacks falls back
//! to the portable one, never runs). The test suite renders its goldens, coverage properties
//! and stability cases on every kernel the machine has.
//!
//! ## The `unsafe` policy
//! The crate denies `unsafe_code`; this module alone allows it, for two purposes:
//! - calling a `#[target_feature]` function, which Rust requires to be `unsafe` at a call
//!   site without the features, because running it on a CPU without them is undefined
//!   behaviour. Each call is guarded by a run-time CPU-feature check right next to it;
//! - [`prefetch`]: the SSE prefetch hint (part of every x86-64 CPU), `unsafe` only because
//!   it is declared with a target feature; it reads nothing and cannot fault;
//! - [`sign_bits`]: SSE's MOVMSKPS (every x86-64 CPU), `unsafe` for the same reason. LLVM
//!   does not turn a portable "sign bit i to bit i" loop into it: behind a lane compare it
//!   scalarised the whole compare (about 30 instructions instead of 5), in the depth test of
//!   every row and in every shader select.
//! - [`edge_signs`]: SSE2's PADDD, POR and MOVMSKPS (every x86-64 CPU) for the coverage
//!   test of a row, which LLVM compiled to scalar code from the portable loop.
//!
//! Each block has a SAFETY comment. No other
//! intrinsics, raw pointers or unchecked indexing are used anywhere: the kernels are the same
//! safe source compiled with different target features (the eight-lane loops vectorise into
//! 256-bit instructions). A safe SIMD crate (pulp, fearless_simd) would hide the same
//! `unsafe` inside a dependency of 10-30 thousand lines; two audited blocks here are
//! smaller to review than that.

#![allow(unsafe_code)]

use std::sync::OnceLock;

use super::lanes::Kernel;

/// The kernels (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum KernelKind {
    Portable,
    Avx2,
    Avx512,
}

/// Portable kernel: the baseline target, no FMA.
#[derive(Clone, Copy, Debug, Default)]
pub struct Portable;
impl Kernel for Portable {
    const FMA: bool = false;
}

/// AVX2 + FMA kernel.
#[derive(Clone, Copy, Debug, Default)]
pub struct Avx2;
impl Kernel for Avx2 {
    const FMA: bool = true;
}

/// AVX-512 kernel (eight lanes, compiled with AVX-512 enabled: masked moves and wider
/// registers for the compiler, the same arithmetic as [`Avx2`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Avx512;
impl Kernel for Avx512 {
    const FMA: bool = true;
}

impl KernelKind {
    pub const ALL: [KernelKind; 3] = [KernelKind::Portable, KernelKind::Avx2, KernelKind::Avx512];

    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            KernelKind::Portable => "portable",
            KernelKind::Avx2 => "avx2",
            KernelKind::Avx512 => "avx512",
        }
    }

    /// Whether this CPU can run the kernel.
    #[must_use]
    pub fn available(self) -> bool {
        match self {
            KernelKind::Portable => true,
            #[cfg(target_arch = "x86_64")]
            KernelKind::Avx2 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
                    && std::arch::is_x86_feature_detected!("popcnt")
                    && std::arch::is_x86_feature_detected!("bmi1")
                    && std::arch::is_x86_feature_detected!("bmi2")
            }
            #[cfg(target_arch = "x86_64")]
            KernelKind::Avx512 => {
                KernelKind::Avx2.available()
                    && std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx512vl")
                    && std::arch::is_x86_feature_detected!("avx512bw")
                    && std::arch::is_x86_feature_detected!("avx512dq")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The kernels this CPU can run.
    pub fn available_kinds() -> impl Iterator<Item = KernelKind> {
        Self::ALL.into_iter().filter(|k| k.available())
    }

    /// The default kernel: `REALIST_KERNEL` if set to an available kernel, else the fastest
    /// available. Detected once per process.
    #[must_use]
    pub fn best() -> KernelKind {
        static BEST: OnceLock<KernelKind> = OnceLock::new();
        *BEST.get_or_init(|| {
            if let Ok(name) = std::env::var("REALIST_KERNEL") {
                if let Ok(k) = name.parse::<KernelKind>() {
                    if k.available() {
                        return k;
                    }
                }
            }
            // AVX-512 measured no faster than AVX2 on eight-lane blocks (see the README's
            // kernel table), so the default stops at AVX2.
            if KernelKind::Avx2.available() {
                KernelKind::Avx2
            } else {
                KernelKind::Portable
            }
        })
    }

    /// This kernel if the CPU has it, else the portable one.
    #[must_use]
    pub fn or_portable(self) -> KernelKind {
        if self.available() {
            self
        } else {
            KernelKind::Portable
        }
    }
}

impl std::str::FromStr for KernelKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "portable" | "scalar" => Ok(KernelKind::Portable),
            "avx2" => Ok(KernelKind::Avx2),
            "avx512" => Ok(KernelKind::Avx512),
            _ => Err(format!(
                "unknown kernel '{s}' (expected portable, avx2 or avx512)"
            )),
        }
    }
}

/// Work compiled once per kernel: `run` must be `#[inline(always)]` (and so must everything
/// it calls that should use the kernel's instructions), so its body is compiled inside the
/// kernel's entry point with that entry point's target features.
pub trait KernelJob {
    type Output;
    fn run<K: Kernel>(self) -> Self::Output;
}

/// Runs `job` with kernel `kind` (the portable kernel if the CPU lacks `kind`).
#[inline]
pub fn dispatch<J: KernelJob>(kind: KernelKind, job: J) -> J::Output {
    match kind {
        #[cfg(target_arch = "x86_64")]
        KernelKind::Avx2 if KernelKind::Avx2.available() => {
            // SAFETY: the CPU has AVX2, FMA, POPCNT, BMI1 and BMI2 (checked on this line's
            // guard), the features `run_avx2` is compiled with.
            unsafe { run_avx2(job) }
        }
        #[cfg(target_arch = "x86_64")]
        KernelKind::Avx512 if KernelKind::Avx512.available() => {
            // SAFETY: the CPU has AVX-512 F/VL/BW/DQ and everything of AVX2 (checked on
            // this line's guard), the features `run_avx512` is compiled with.
            unsafe { run_avx512(job) }
        }
        _ => job.run::<Portable>(),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2")]
fn run_avx2<J: KernelJob>(job: J) -> J::Output {
    job.run::<Avx2>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,popcnt,bmi1,bmi2")]
fn run_avx512<J: KernelJob>(job: J) -> J::Output {
    job.run::<Avx512>()
}

/// Asks the CPU to bring the cache lines of `value` towards L1 (a hint: no effect on
/// results; a no-op off x86-64). The fill prefetches the next triangles of a tile's list,
/// which setup wrote on whichever thread set them up.
#[inline(always)]
pub fn prefetch<T: ?Sized>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = (value as *const T).cast::<i8>();
        let n = std::mem::size_of_val(value);
        let mut off = 0;
        while off < n {
            // SAFETY: PREFETCHT0 is SSE, which every x86-64 CPU has; it is a hint that
            // neither reads memory architecturally nor faults, and `p + off` stays inside
            // `value` (wrapping_add: no pointer arithmetic UB either way).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(off)) };
            off += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// Bit `i` = the sign bit of `lanes[i]` (MOVMSKPS on x86-64).
#[inline(always)]
pub(crate) fn sign_bits(lanes: [u32; 8]) -> u32 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    {
        use std::arch::x86_64::{_mm_movemask_ps, _mm_set_ps};
        let f = |i: usize| f32::from_bits(lanes[i]);
        // SAFETY: SSE is part of every x86-64 CPU (and `target_feature = "sse"` is on at
        // compile time); both intrinsics only move register bits.
        unsafe {
            let lo = _mm_set_ps(f(3), f(2), f(1), f(0));
            let hi = _mm_set_ps(f(7), f(6), f(5), f(4));
            (_mm_movemask_ps(lo) | (_mm_movemask_ps(hi) << 4)) as u32
        }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    {
        let mut b = 0;
        for (i, v) in lanes.iter().enumerate() {
            b |= (v >> 31) << i;
        }
        b
    }
}

/// Bit `i` set where lane `i` is outside any of three edges: the sign bit of
/// `(row[0] + lanes[0][i]) | (row[1] + lanes[1][i]) | (row[2] + lanes[2][i])` (wrapping
/// adds; the fill keeps them exact, see `raster::fill`'s `narrow`). The coverage test of
/// every eight-pixel row.
///
/// SSE2 on x86-64 (PADDD, POR, MOVMSKPS on two halves; inlined into an AVX2 kernel LLVM may
/// join them). The same loop in portable Rust was compiled to scalar code: LLVM split the
/// per-lane offsets into 24 scalars, added and ORed them in general registers and rebuilt
/// the vector with eight inserts before MOVMSKPS, about 11% of a Phong frame.
#[inline(always)]
#[allow(clippy::needless_range_loop)]
pub fn edge_signs(row: [i32; 3], lanes: &[[i32; 8]; 3]) -> u32 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
    {
        use std::arch::x86_64::{
            __m128i, _mm_add_epi32, _mm_castsi128_ps, _mm_loadu_si128, _mm_movemask_ps,
            _mm_or_si128, _mm_set1_epi32,
        };
        // SAFETY: SSE2 is part of every x86-64 CPU (and `target_feature = "sse2"` is on at
        // compile time). Each load reads the 16 bytes of four `i32` inside one `[i32; 8]`
        // borrowed for the call (`half` is 0 or 4; unaligned loads); the rest only moves
        // and adds register bits.
        unsafe {
            let half = |h: usize| {
                let mut acc: Option<__m128i> = None;
                for k in 0..3 {
                    let l = _mm_loadu_si128(lanes[k][h..h + 4].as_ptr().cast::<__m128i>());
                    let v = _mm_add_epi32(_mm_set1_epi32(row[k]), l);
                    acc = Some(match acc {
                        Some(a) => _mm_or_si128(a, v),
                        None => v,
                    });
                }
                acc.map_or(0, |a| _mm_movemask_ps(_mm_castsi128_ps(a)) as u32)
            };
            half(0) | (half(4) << 4)
        }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
    {
        let mut b = 0;
        for i in 0..8 {
            let v = row[0].wrapping_add(lanes[0][i])
                | row[1].wrapping_add(lanes[1][i])
                | row[2].wrapping_add(lanes[2][i]);
            b |= ((v as u32) >> 31) << i;
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::F8;

    struct Fma(F8, F8, F8);
    impl KernelJob for Fma {
        type Output = F8;
        #[inline(always)]
        fn run<K: Kernel>(self) -> F8 {
            K::fma(self.0, self.1, self.2)
        }
    }

    #[test]
    fn every_available_kernel_runs_and_names_parse() {
        let (a, b, c) = (
            F8::splat(1.0 + 1e-7),
            F8::splat(1.0 - 1e-7),
            F8::splat(-1.0),
        );
        for k in KernelKind::available_kinds() {
            let r = dispatch(k, Fma(a, b, c));
            // Exact: -1e-14 (fused), or rounded to 0 / -2^-46 (unfused).
            assert!(r.0[0].abs() < 1e-12, "{k:?}: {}", r.0[0]);
            assert_eq!(k.name().parse::<KernelKind>().unwrap(), k);
        }
        assert!(KernelKind::best().available());
        assert!("sse9".parse::<KernelKind>().is_err());
        assert!(KernelKind::Portable.available());
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn edge_signs_match_the_lane_loop() {
        // A fixed xorshift sequence: values near zero (the sign boundary), near the i32 range
        // the fill allows (2^30 plus offsets under 2^28) and wrapping ones.
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for case in 0..20_000 {
            let pick = |v: u64| -> i32 {
                match case % 4 {
                    0 => (v % 64) as i32 - 32,
                    1 => ((v % (1 << 31)) as i64 - (1 << 30)) as i32,
                    2 => v as i32,
                    _ => ((v % (1 << 29)) as i32) - (1 << 28),
                }
            };
            let row = [pick(next()), pick(next()), pick(next())];
            let mut lanes = [[0i32; 8]; 3];
            for l in lanes.iter_mut().flatten() {
                *l = pick(next());
            }
            let mut want = 0;
            for i in 0..8 {
                let v = row[0].wrapping_add(lanes[0][i])
                    | row[1].wrapping_add(lanes[1][i])
                    | row[2].wrapping_add(lanes[2][i]);
                want |= u32::from(v < 0) << i;
            }
            assert_eq!(edge_signs(row, &lanes), want, "{row:?} {lanes:?}");
        }
    }
}
