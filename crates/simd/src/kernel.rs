//! Kernel choice and dispatch: the one place in the workspace with `unsafe`.
//!
//! The lane code ([`super::lanes`]) is written once; a kernel is the instruction set it is
//! compiled for:
//!
//! | kernel | compiled with |
//! |---|---|
//! | [`KernelKind::Portable`] | the build's baseline (SSE2 on x86-64) |
//! | [`KernelKind::Avx2`] | AVX2 + FMA (+ POPCNT, BMI1/2) |
//! | [`KernelKind::Avx512`] | AVX-512 F/VL/BW/DQ + AVX2 + FMA |
//!
//! Every kernel computes the same bits: the lane code uses no fused multiply-add and no
//! approximate instruction, so a kernel changes only how fast an image is made, never the
//! image (the tests compare the kernels bit for bit).
//!
//! The best kernel the CPU has is detected once ([`KernelKind::best`]); `REALIST_KERNEL=
//! portable|avx2|avx512` or a renderer setting forces one (a kernel the CPU lacks falls back
//! to the portable one, never runs).
//!
//! Two ways to compile code per kernel, both kept small on purpose (a kernel function that
//! inlined the whole fill and every shader grew to 400 KB of machine code, took most of a
//! 26-minute build and spilled registers on every other instruction):
//! - [`per_kernel!`](crate::per_kernel): one function, compiled three times, each copy a
//!   function of its own behind a plain `fn` pointer chosen by kernel. The pixel stages and
//!   the tile fill are written this way: a stage is one function per kernel, called through
//!   a pointer per batch of pixels, never inlined into its caller;
//! - [`dispatch`] with a [`KernelJob`]: a job whose `run` is `#[inline(always)]`, compiled
//!   inside each kernel's entry point (small jobs: projecting vertices, setting up a chunk).
//!
//! ## The `unsafe` policy
//! The workspace denies `unsafe_code`; this module and [`crate::level`] alone allow it, for:
//! - calling a `#[target_feature]` function, which Rust requires to be `unsafe` at a call
//!   site without the features, because running it on a CPU without them is undefined
//!   behaviour. In [`dispatch`] each call is guarded by a run-time CPU-feature check right
//!   next to it; in [`per_kernel!`](crate::per_kernel) the call sits in a private trampoline
//!   that only the macro's `pick` hands out, after the same check. The macro is written here,
//!   once; the crates that use it write no `unsafe` themselves;
//! - [`prefetch`]: the SSE prefetch hint (part of every x86-64 CPU), `unsafe` only because
//!   it is declared with a target feature; it reads nothing and cannot fault;
//! - the lane levels' intrinsics ([`crate::level`], its own module): the AVX2 level's
//!   intrinsics are `unsafe` to call from generic code; they are sound because that level
//!   is only instantiated inside the AVX2 copies made here.
//! - [`edge_signs`]: SSE2's PADDD, POR and MOVMSKPS (every x86-64 CPU) for the coverage
//!   test of a row, which LLVM compiled to scalar code from the portable loop.
//!
//! Each block has a SAFETY comment. No other intrinsics, raw pointers or unchecked indexing
//! are used anywhere: the kernels are the same safe source compiled with different target
//! features. A safe SIMD crate (pulp, fearless_simd) would hide the same `unsafe` inside a
//! dependency of 10-30 thousand lines; the few audited blocks here are smaller to review.

#![allow(unsafe_code)]

use std::sync::OnceLock;

use crate::level::{Avx2, Level, Portable};

/// The kernels (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum KernelKind {
    Portable,
    Avx2,
    Avx512,
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
/// kernel's entry point with that entry point's target features. Keep it small: all of it
/// is copied into each kernel's entry point.
pub trait KernelJob {
    type Output;
    fn run<L: Level>(self) -> Self::Output;
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
    job.run::<Avx2>()
}

/// Compiles one function once per kernel, each copy a function of its own, and gives a
/// `pick(kind) -> fn(...)` that returns the copy for a kernel the CPU has (the portable one
/// otherwise). The function is generic over the lane level `L` (a [`Level`]): each copy
/// instantiates it with its kernel's level (the portable one, or AVX2 for the AVX2 and
/// AVX-512 kernels) and compiles it with the kernel's target features. The body should
/// call `#[inline(always)]` code (the lane operations are), so that it is compiled with the
/// copy's instructions; the copies are never inlined into their callers, so a caller that
/// runs a list of such functions stays small. Parameter and return types must not name
/// `L`: lanes cross between functions in their level-free form ([`Lane`](crate::Lane)).
///
/// ```ignore
/// realist_simd::per_kernel! {
///     /// Doubles the lanes.
///     pub fn double<L>(v: &mut [Lane]) {
///         for x in v {
///             x.set(x.get::<L>() * 2.0);
///         }
///     }
/// }
/// let f = double::pick(KernelKind::best());
/// f(&mut lanes);
/// ```
///
/// Expands to a module named after the function holding the body, the three copies, the
/// private trampolines that call the target-feature copies (the only `unsafe`, guarded by
/// `pick`'s CPU check), and `pick`. Parameters must be plain identifiers.
#[macro_export]
macro_rules! per_kernel {
    ($(#[$meta:meta])* $vis:vis fn $name:ident<$l:ident>($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block) => {
        $(#[$meta])*
        #[allow(clippy::too_many_arguments)]
        $vis mod $name {
            #[allow(unused_imports)]
            use super::*;

            #[inline(always)]
            #[allow(clippy::too_many_arguments)]
            fn body<$l: $crate::Level>($($arg: $ty),*) $(-> $ret)? $body

            #[inline(never)]
            #[allow(clippy::too_many_arguments)]
            fn portable($($arg: $ty),*) $(-> $ret)? {
                body::<$crate::kernel::__private::Portable>($($arg),*)
            }

            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2,fma,popcnt,bmi1,bmi2")]
            #[inline(never)]
            #[allow(clippy::too_many_arguments)]
            fn avx2_copy($($arg: $ty),*) $(-> $ret)? {
                body::<$crate::kernel::__private::Avx2>($($arg),*)
            }

            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,popcnt,bmi1,bmi2")]
            #[inline(never)]
            #[allow(clippy::too_many_arguments)]
            fn avx512_copy($($arg: $ty),*) $(-> $ret)? {
                body::<$crate::kernel::__private::Avx2>($($arg),*)
            }

            #[cfg(target_arch = "x86_64")]
            #[allow(clippy::too_many_arguments)]
            fn avx2($($arg: $ty),*) $(-> $ret)? {
                // SAFETY: this trampoline is private to the module and handed out only by
                // `pick`, after `KernelKind::Avx2.available()` found the CPU has every
                // feature `avx2_copy` is compiled with.
                #[allow(unsafe_code)]
                unsafe {
                    avx2_copy($($arg),*)
                }
            }

            #[cfg(target_arch = "x86_64")]
            #[allow(clippy::too_many_arguments)]
            fn avx512($($arg: $ty),*) $(-> $ret)? {
                // SAFETY: as for `avx2`, after `KernelKind::Avx512.available()`.
                #[allow(unsafe_code)]
                unsafe {
                    avx512_copy($($arg),*)
                }
            }

            /// The copy for kernel `kind` (the portable one if the CPU lacks `kind`).
            #[allow(dead_code)]
            pub fn pick(kind: $crate::KernelKind) -> fn($($ty),*) $(-> $ret)? {
                match kind {
                    #[cfg(target_arch = "x86_64")]
                    $crate::KernelKind::Avx2 if $crate::KernelKind::Avx2.available() => avx2,
                    #[cfg(target_arch = "x86_64")]
                    $crate::KernelKind::Avx512 if $crate::KernelKind::Avx512.available() => avx512,
                    _ => portable,
                }
            }
        }
    };
}

/// The level types, for [`per_kernel!`](crate::per_kernel) and [`dispatch`] only: code that
/// names them directly could run AVX2 instructions on a CPU without them (see
/// [`crate::level`], "Soundness"). Not part of the API.
#[doc(hidden)]
pub mod __private {
    pub use crate::level::{Avx2, Portable};
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
    use crate::lanes::{Lane, F8};

    struct Mad(Lane, Lane, Lane);
    impl KernelJob for Mad {
        type Output = Lane;
        #[inline(always)]
        fn run<L: Level>(self) -> Lane {
            let (a, b, c) = (self.0.get::<L>(), self.1.get::<L>(), self.2.get::<L>());
            Lane::from(crate::lanes::mad(a, b, c))
        }
    }

    crate::per_kernel! {
        /// A per-kernel function for the test below.
        fn sum_of_products<L>(a: &[Lane], b: &[Lane]) -> Lane {
            let mut s = F8::<L>::ZERO;
            for (x, y) in a.iter().zip(b) {
                s += x.get::<L>() * y.get::<L>();
            }
            Lane::from(s)
        }
    }

    #[test]
    fn every_available_kernel_runs_and_names_parse() {
        let (a, b, c) = (
            Lane::splat(1.0 + 1e-7),
            Lane::splat(1.0 - 1e-7),
            Lane::splat(-1.0),
        );
        for k in KernelKind::available_kinds() {
            // Never fused: (1 + 1e-7)(1 - 1e-7) rounds to 1 in f32 before -1 is added, in
            // every kernel.
            let r = dispatch(k, Mad(a, b, c));
            assert_eq!(r.0[0], 0.0, "{k:?}");
            let v: Vec<Lane> = (0..37)
                .map(|i| Lane::from(F8::<Portable>::RAMP * (i as f32 * 0.37 + 0.1)))
                .collect();
            let want = sum_of_products::pick(KernelKind::Portable)(&v, &v[1..]);
            let got = sum_of_products::pick(k)(&v, &v[1..]);
            assert_eq!(got.0.map(f32::to_bits), want.0.map(f32::to_bits), "{k:?}");
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
