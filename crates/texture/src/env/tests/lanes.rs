//! The eight-lane reads (`lanes.rs`) against the one-point reads they replace: bit for bit
//! on every kernel this machine runs, over coordinates that include the seams, the poles and
//! the ends of the roughness range.

use crate::simd::kernel::{dispatch, KernelJob};
use crate::simd::{KernelKind, Lane, Level, F8, LANES};

use super::*;

/// One batch of eight reads: image coordinates, roughness and `N·V`.
struct Case<'a> {
    env: &'a Prefiltered,
    u: Lane,
    v: Lane,
    r: Lane,
    nv: Lane,
}

impl KernelJob for &Case<'_> {
    /// Specular, irradiance, sheen (three channels each), then the table's three values.
    type Output = [[Lane; 3]; 4];
    #[inline(always)]
    fn run<L: Level>(self) -> [[Lane; 3]; 4] {
        let (u, v, r): (F8<L>, F8<L>, F8<L>) = (self.u.get(), self.v.get(), self.r.get());
        let lanes = |c: [F8<L>; 3]| [Lane::from(c[0]), Lane::from(c[1]), Lane::from(c[2])];
        [
            lanes(self.env.specular_lanes(u, v, r)),
            lanes(self.env.irradiance_lanes(u, v)),
            lanes(self.env.sheen_lanes(u, v, r)),
            lanes(brdf_lut().lookup_ess_lanes(self.nv.get(), r)),
        ]
    }
}

/// Coordinates in `[0, 1]` with the ends and the texel centres of small images over-drawn.
fn coordinate(k: u64) -> f32 {
    const SPECIAL: [f32; 8] = [0.0, 1.0, 0.5, 1e-7, 1.0 - 1e-7, 0.25, 1.0 / 3.0, 0.999];
    let h = k.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (k >> 7);
    if h.is_multiple_of(4) {
        SPECIAL[(h >> 8) as usize % SPECIAL.len()]
    } else {
        ((h >> 11) as f64 / (1u64 << 53) as f64) as f32
    }
}

#[test]
fn lane_reads_match_the_one_point_reads_on_every_kernel() {
    let img = EnvImage::builtin("studio").expect("built-in");
    let env = Prefiltered::build(img);
    let lut = brdf_lut();
    let mut checked = 0;
    for kind in KernelKind::available_kinds() {
        for batch in 0..400u64 {
            let at = |j: u64, i: usize| coordinate(batch * 64 + j * 8 + i as u64);
            let (mut u, mut v, mut r, mut nv) =
                ([0.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]);
            for i in 0..LANES {
                (u[i], v[i], r[i], nv[i]) = (at(0, i), at(1, i), at(2, i), at(3, i));
            }
            let case = Case {
                env: &env,
                u: Lane(u),
                v: Lane(v),
                r: Lane(r),
                nv: Lane(nv),
            };
            let [s, e, sh, t] = dispatch(kind, &case);
            for i in 0..LANES {
                let want = [
                    env.specular_uv(u[i], v[i], r[i]),
                    env.irradiance_uv(u[i], v[i]),
                    env.sheen_uv(u[i], v[i], r[i]),
                ];
                let (a, b, c) = lut.lookup_ess(nv[i], r[i]);
                let want_t = [a, b, c];
                for ch in 0..3 {
                    let at = format!("{kind:?} u {} v {} r {} nv {}", u[i], v[i], r[i], nv[i]);
                    assert_eq!(s[ch].0[i].to_bits(), want[0][ch].to_bits(), "specular {at}");
                    assert_eq!(
                        e[ch].0[i].to_bits(),
                        want[1][ch].to_bits(),
                        "irradiance {at}"
                    );
                    assert_eq!(sh[ch].0[i].to_bits(), want[2][ch].to_bits(), "sheen {at}");
                    assert_eq!(t[ch].0[i].to_bits(), want_t[ch].to_bits(), "table {at}");
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 3200, "{checked} points compared");
}
