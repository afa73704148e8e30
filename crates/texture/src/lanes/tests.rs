use super::*;
use crate::simd::kernel::__private::Portable;
use crate::simd::kernel::{dispatch, KernelJob};
use crate::simd::{KernelKind, Lane};
use glam::{Vec2, Vec4};

/// splitmix64.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[(self.next() % xs.len() as u64) as usize]
    }
}

fn noise(w: u32, h: u32, srgb: bool, rng: &mut Rng) -> Texture {
    let texels = (0..w * h)
        .map(|_| {
            let b = rng.next().to_le_bytes();
            [b[0], b[1], b[2], b[3]]
        })
        .collect();
    Texture::new("noise", w, h, texels, srgb).unwrap()
}

const SPECIAL: [f32; 12] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    1e-30,
    1e30,
    -1e30,
    f32::MAX,
    f32::MIN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
];

/// A texture coordinate: mostly ordinary, sometimes on texel edges, huge or special.
fn coord(rng: &mut Rng, n: u32) -> f32 {
    match rng.next() % 8 {
        0 => rng.pick(&SPECIAL),
        1 => (rng.next() % (4 * u64::from(n) + 1)) as f32 / n as f32 - 1.5,
        2 => (rng.unit() - 0.5) * 2e6,
        3 => (rng.unit() - 0.5) * 1e-3,
        _ => (rng.unit() - 0.5) * 6.0,
    }
}

/// A derivative: log-uniform magnitude from 2^-16 to 2^4, random sign; sometimes special.
fn deriv(rng: &mut Rng) -> f32 {
    if rng.next().is_multiple_of(10) {
        return rng.pick(&SPECIAL);
    }
    let m = libm::exp2f(rng.unit() * 20.0 - 16.0);
    if rng.next().is_multiple_of(2) {
        m
    } else {
        -m
    }
}

struct Case<'a> {
    t: &'a Texture,
    uv: [Lane; 2],
    d: [Lane; 4],
    mask: u32,
    s: Sampler,
    grad: bool,
}

impl KernelJob for &Case<'_> {
    type Output = [Lane; 4];
    #[inline(always)]
    fn run<L: Level>(self) -> [Lane; 4] {
        let [u, v] = self.uv.map(|x| x.get::<L>());
        let [a, b, c, d] = self.d.map(|x| x.get::<L>());
        let r = if self.grad {
            self.t
                .sample_grad_lanes(u, v, a, b, c, d, self.mask, self.s)
        } else {
            self.t.sample_lanes(u, v, self.mask, self.s)
        };
        r.map(Lane::from)
    }
}

/// Largest difference from the scalar sampler over random cases, per filter, on kernel
/// `kind`; nearest and bilinear must be bit-identical.
fn compare(kind: KernelKind) -> f32 {
    let mut rng = Rng(42);
    let wraps = [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge];
    let filters = [
        Filter::Nearest,
        Filter::Bilinear,
        Filter::Trilinear,
        Filter::Anisotropic(2),
        Filter::Anisotropic(5),
        Filter::Anisotropic(16),
    ];
    let mut worst = 0.0f32;
    let mut lanes = 0;
    for (w, h) in [
        (1, 1),
        (1, 9),
        (9, 1),
        (2, 2),
        (5, 3),
        (37, 20),
        (64, 64),
        (256, 4),
        (100, 100),
    ] {
        for srgb in [true, false] {
            let t = noise(w, h, srgb, &mut rng);
            for wrap_u in wraps {
                for wrap_v in wraps {
                    for filter in filters {
                        let s = Sampler {
                            wrap_u,
                            wrap_v,
                            filter,
                        };
                        for _ in 0..40 {
                            let mut uv = [Lane::ZERO; 2];
                            let mut d = [Lane::ZERO; 4];
                            for i in 0..LANES {
                                uv[0].0[i] = coord(&mut rng, w);
                                uv[1].0[i] = coord(&mut rng, h);
                                for x in &mut d {
                                    x.0[i] = deriv(&mut rng);
                                }
                            }
                            let mask = (rng.next() as u32 | rng.next() as u32) & 0xff;
                            for grad in [false, true] {
                                let case = Case {
                                    t: &t,
                                    uv,
                                    d,
                                    mask,
                                    s,
                                    grad,
                                };
                                let got = dispatch(kind, &case);
                                for i in 0..LANES {
                                    let g = Vec4::new(
                                        got[0].0[i],
                                        got[1].0[i],
                                        got[2].0[i],
                                        got[3].0[i],
                                    );
                                    assert!(g.is_finite(), "lane {i}: {g}");
                                    if mask >> i & 1 == 0 {
                                        continue;
                                    }
                                    let p = Vec2::new(uv[0].0[i], uv[1].0[i]);
                                    let want = if grad {
                                        let dx = Vec2::new(d[0].0[i], d[1].0[i]);
                                        let dy = Vec2::new(d[2].0[i], d[3].0[i]);
                                        t.sample_grad_with(p, dx, dy, s)
                                    } else {
                                        t.sample_with(p, s)
                                    };
                                    let err = (g - want).abs().max_element();
                                    let exact = !grad || !filter.mipmapped();
                                    assert!(
                                        if exact { g == want } else { err < 1e-5 },
                                        "{kind:?} {w}x{h} srgb {srgb} {s:?} grad {grad} \
                                         uv {p} d {d:?} lane {i}: {g} vs {want}"
                                    );
                                    worst = worst.max(err);
                                    lanes += 1;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(lanes > 100_000, "{lanes}");
    worst
}

#[test]
fn lanes_match_the_scalar_sampler_on_every_kernel() {
    for kind in KernelKind::available_kinds() {
        let worst = compare(kind);
        eprintln!("{kind:?}: largest difference {worst:e}");
        assert!(worst < 1e-5, "{kind:?}: {worst}");
    }
}

#[test]
fn lane_floors_and_remainders() {
    let xs = [
        0.0,
        -0.0,
        0.5,
        -0.5,
        1.0,
        -1.0,
        2.5,
        -2.5,
        1e-30,
        -1e-30,
        8388607.5,
        -8388607.5,
        8388608.0,
        -8388609.0,
        1e30,
        -1e30,
        0.49999997,
        -0.49999997,
        1.5,
        -1.5,
        4194303.5,
        -4194303.5,
        3.999,
        -3.001,
    ];
    for c in xs.chunks(LANES) {
        let x = F8::<Portable>::load(c);
        let (f, r) = (
            x.floor().to_array(),
            reduce(x, Wrap::MirroredRepeat).to_array(),
        );
        let fi = floor_i(x).to_array();
        for i in 0..LANES {
            assert_eq!(f[i].to_bits(), c[i].floor().to_bits(), "floor {}", c[i]);
            assert_eq!(r[i], c[i].rem_euclid(2.0), "rem {}", c[i]);
            if c[i].abs() < 4e6 {
                assert_eq!(fi[i], c[i].floor() as i32, "{}", c[i]);
            }
        }
    }
    let nan = F8::<Portable>::splat(f32::NAN).floor();
    assert!(nan.lane(0).is_nan());
    assert_eq!(
        F8::<Portable>::splat(f32::INFINITY).floor().lane(0),
        f32::INFINITY
    );
}
