use super::*;
use crate::level::Portable;
use crate::KernelKind;

type P = F8<Portable>;

#[test]
fn powi_matches_f64_within_n_roundings() {
    let tiny = 2f64.powi(-60);
    for n in 0..=128u32 {
        for i in 0..=4000 {
            let x = i as f32 / 4000.0;
            let got = f64::from(P::splat(x).powi(n).lane(3));
            let want = f64::from(x).powi(n as i32);
            if n == 0 {
                assert_eq!(got, 1.0);
            } else if want < tiny {
                assert!(got <= tiny * 1.000_001 && got > 0.0, "{x}^{n}: {got}");
            } else {
                let rel = (got - want).abs() / want;
                assert!(
                    rel <= f64::from(n - 1) * 1.2e-7 + 1e-9,
                    "{x}^{n}: {got} vs {want}"
                );
            }
        }
    }
    // The scalar steps (`Num::powi` for f32) give the same bits.
    for n in [1u32, 2, 5, 32, 100, 128] {
        for i in 0..=1000 {
            let x = i as f32 / 1000.0;
            let lane = P::splat(x).powi(n).lane(5);
            assert_eq!(crate::Num::powi(x, n).to_bits(), lane.to_bits(), "{x}^{n}");
        }
    }
    // Above 1 (N·H rounded up) and the exponent's bits one by one.
    for n in [1u32, 2, 3, 5, 7, 31, 32, 33, 64, 127, 128] {
        let x = 1.000_001f32;
        let got = f64::from(P::splat(x).powi(n).lane(0));
        let want = f64::from(x).powi(n as i32);
        assert!((got - want).abs() / want < 2e-5, "{x}^{n}: {got} vs {want}");
    }
}

fn check_pow() {
    let mut worst: f64 = 0.0;
    for i in 1..2000 {
        let x = i as f32 / 2000.0;
        for e in [1.0f32, 2.5, 8.0, 32.0, 128.0, 1000.0] {
            let got = P::splat(x).powf(P::splat(e)).lane(0);
            let want = libm::pow(f64::from(x), f64::from(e));
            if want < 1e-30 {
                assert!(got < 1e-29, "{x}^{e} = {got}");
                continue;
            }
            let rel = ((f64::from(got) - want) / want).abs();
            let bound = 4e-7 * (1.0 + (f64::from(e) * libm::log2(f64::from(x))).abs());
            assert!(rel < bound, "{x}^{e}: {got} vs {want}, rel {rel}");
            worst = worst.max(rel / bound);
        }
    }
    assert_eq!(P::splat(0.0).powf(P::splat(3.0)).lane(0), 0.0);
    assert_eq!(P::splat(-1.0).powf(P::splat(3.0)).lane(0), 0.0);
    assert_eq!(P::splat(1.0).powf(P::splat(500.0)).lane(0), 1.0);
    assert!(worst > 0.0);
}

#[test]
fn acos_and_atan2_match_f64() {
    let (mut worst_acos, mut worst_atan) = (0.0f64, 0.0f64);
    for k in 0..=4000 {
        let x = -1.0 + 2.0 * k as f32 / 4000.0;
        let a = P::splat(x).acos().lane(0);
        worst_acos = worst_acos.max((f64::from(a) - libm::acos(f64::from(x))).abs());
    }
    for k in 0..720 {
        let phi = (k as f64 + 0.25).to_radians() * 0.5 - std::f64::consts::PI;
        for r in [1e-3f64, 0.5, 1.0, 300.0] {
            let (y, x) = ((libm::sin(phi) * r) as f32, (libm::cos(phi) * r) as f32);
            let a = P::splat(y).atan2(P::splat(x)).lane(0);
            let want = libm::atan2(f64::from(y), f64::from(x));
            worst_atan = worst_atan.max((f64::from(a) - want).abs());
        }
    }
    let zero = P::ZERO.atan2(P::ZERO).lane(0);
    assert_eq!(zero, 0.0);
    assert!(worst_acos < 1e-6, "acos {worst_acos:e}");
    assert!(worst_atan < 2e-5, "atan2 {worst_atan:e}");
}

#[test]
fn pow_matches_f64() {
    check_pow();
}

#[test]
fn log2_and_exp2_over_wide_ranges() {
    for k in -120..120 {
        for m in [1.0f32, 1.1, 1.41, 1.42, 1.9] {
            let x = m * 2f32.powi(k);
            let got = P::splat(x).log2().lane(0);
            let want = libm::log2(f64::from(x));
            assert!(
                (f64::from(got) - want).abs() < 2e-6 * want.abs().max(1.0),
                "{x}"
            );
        }
    }
    for i in -1200..1200 {
        let x = i as f32 / 10.0;
        let got = f64::from(P::splat(x).exp2().lane(0));
        let want = libm::pow(2f64, f64::from(x));
        assert!(((got - want) / want).abs() < 3e-7, "{x}: {got} {want}");
    }
}

#[test]
fn exp_and_cos_match_f64() {
    // exp over the range where it is neither ~0 nor ~inf, relative.
    for i in -870..=880 {
        let x = i as f32 / 10.0;
        let got = f64::from(P::splat(x).exp().lane(0));
        let want = libm::exp(f64::from(x));
        let bound = 3e-7 + 1.2e-7 * f64::from(x).abs();
        assert!(((got - want) / want).abs() < bound, "exp {x}: {got} {want}");
    }
    // cos, absolute, of f32 inputs (so the reduction, not the input's rounding, is tested),
    // finely near 0 and every quadrant boundary, coarsely out to 8000.
    let mut worst: f64 = 0.0;
    for i in -200_000..=200_000 {
        let x = i as f32 * 1e-4;
        let got = f64::from(P::splat(x).cos().lane(0));
        worst = worst.max((got - libm::cos(f64::from(x))).abs());
    }
    for i in -400_000..=400_000 {
        let x = i as f32 * 0.02 + 0.001;
        let got = f64::from(P::splat(x).cos().lane(0));
        worst = worst.max((got - libm::cos(f64::from(x))).abs());
    }
    assert!(worst < 2e-7, "cos: worst absolute error {worst}");
}

#[test]
fn masks_and_selects() {
    let a = P::RAMP;
    let m = a.gt(P::splat(3.5));
    assert_eq!(m.bits(), 0b1111_0000);
    assert_eq!(M8::<Portable>::from_bits(0b1010).bits(), 0b1010);
    let s = P::select(m, a, -a);
    assert_eq!(s.to_array(), [0.0, -1.0, -2.0, -3.0, 4.0, 5.0, 6.0, 7.0]);
    assert_eq!((m & !m).bits(), 0);
    assert_eq!((m | !m).bits(), 0xff);
    let mut n = [f32::NAN; 8];
    n[1] = 2.0;
    assert_eq!(P::from_array(n).clamp(0.0, 1.0).to_array()[..2], [0.0, 1.0]);
    let v = V3::<Portable>::new(P::splat(3.0), P::splat(4.0), P::ZERO).normalize_or_zero();
    assert_eq!((v.x.lane(0), v.y.lane(0)), (0.6, 0.8));
    let z = V3::<Portable>::default().normalize_or_zero();
    assert_eq!(z.x.to_array(), [0.0; 8]);
}

/// Inputs for the kernel comparison: ordinary values, halves, large and tiny ones,
/// signed zeros, infinities and NaN.
fn awkward() -> Vec<Lane> {
    let special = [
        0.0f32,
        -0.0,
        0.5,
        -0.5,
        1.5,
        -1.5,
        2.5,
        -2.5,
        1e-30,
        -1e-30,
        8_388_607.5,
        -8_388_607.5,
        8_388_609.0,
        1e10,
        -1e10,
        3e9,
        -3e9,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        f32::MIN_POSITIVE,
        0.999_999_94,
        -0.999_999_94,
        123.456,
    ];
    let mut seed = 0x1234_5678u32;
    let mut out: Vec<Lane> = special
        .chunks(8)
        .map(|c| {
            let mut l = [0.0; 8];
            l[..c.len()].copy_from_slice(c);
            Lane(l)
        })
        .collect();
    for _ in 0..64 {
        let mut l = [0.0; 8];
        for x in &mut l {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            *x = f32::from_bits(seed % 0x7f00_0000) * if seed & 1 == 0 { 1.0 } else { -1.0 };
        }
        out.push(Lane(l));
    }
    out
}

crate::per_kernel! {
    /// Every primitive and function of the lanes applied to `a` and `b`, as bits.
    fn battery<L>(a: &[Lane], b: &[Lane], out: &mut Vec<u32>) {
        for (x, y) in a.iter().zip(b) {
            let (x, y) = (x.get::<L>(), y.get::<L>());
            let f = [
                x + y,
                x - y,
                x * y,
                x / y,
                x.max(y),
                x.min(y),
                x.abs().sqrt(),
                x.floor(),
                x.to_int().to_f32(),
                x.abs().log2(),
                (x * 0.001).exp2(),
                x.abs().powf(y.abs().min(F8::splat(40.0))),
                x.abs().powi(7),
                (x * 1e-9).acos(),
                x.atan2(y),
                -x,
                F8::select(x.gt(y), x, y),
                (x.bits() * I8::splat(31) + y.bits().sra::<3>()).to_f32(),
            ];
            for v in f {
                out.extend(v.to_array().map(f32::to_bits));
            }
            let m = [x.gt(y), x.ge(y), x.lt(y), x.le(y), x.eq(y), x.bits().gt(y.bits())];
            out.extend(m.map(M8::bits));
            out.extend(x.to_int().to_array().map(|i| i as u32));
            let k = (x.bits().to_array()[0] as u32) & 0xff;
            out.push(M8::<L>::from_bits(k).bits());
        }
    }
}

/// Every kernel computes the same bits, edge cases included (the levels pin `max`,
/// `min`, `floor` and the float-to-int conversion to one definition).
#[test]
fn every_kernel_computes_the_same_bits() {
    let a = awkward();
    let mut b = a.clone();
    b.rotate_left(3);
    let mut want = Vec::new();
    battery::pick(KernelKind::Portable)(&a, &b, &mut want);
    assert!(want.len() > 10_000);
    for k in KernelKind::available_kinds() {
        let mut got = Vec::new();
        battery::pick(k)(&a, &b, &mut got);
        assert_eq!(got, want, "{k:?}");
    }
    // The portable floor and conversion agree with Rust's scalar definitions.
    for l in &a {
        let v = l.get::<Portable>();
        for (i, x) in l.0.iter().enumerate() {
            let f = v.floor().lane(i);
            assert!(
                f.to_bits() == x.floor().to_bits() || (f.is_nan() && x.is_nan()),
                "floor {x}: {f}"
            );
            let t = v.to_int().to_array()[i];
            let want = if x.abs() < 2_147_483_648.0 {
                *x as i32
            } else {
                i32::MIN
            };
            assert_eq!(t, want, "trunc {x}");
        }
    }
}
