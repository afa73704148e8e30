//! The lighting equation of seeds 000-003, evaluated in linear RGB:
//!
//! `I = g_amb * m_amb + Σ_i I_i * (K_d * max(N·L_i, 0) + K_s * S_i)`
//!
//! with `S_i = max(R·V, 0)^n`, `R = 2N(N·L) - L` (Phong) or `S_i = max(N·H, 0)^n`,
//! `H = (L + V)/|L + V|` (Blinn). `m_amb = K_a * K_d` (003: the ambient colour follows the
//! diffuse colour, `K_a` scales it). No specular work is done when `K_s = 0`, and none for a
//! light the surface faces away from. Attenuation and spot cones arrive with the full
//! lighting model.

use glam::Vec3;

use crate::raster::{Kernel, F8, V3};
use crate::scene::Light;

/// Lights converted once per frame into the form the shaders loop over.
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    /// Sum of ambient lights.
    pub ambient: Vec3,
    /// (unit direction towards the light, colour)
    pub directional: Vec<(Vec3, Vec3)>,
    /// (position, colour)
    pub point: Vec<(Vec3, Vec3)>,
}

impl LightSet {
    /// Collects lights; non-finite or zero-length directions are dropped.
    #[must_use]
    pub fn new(lights: &[Light]) -> Self {
        let mut set = Self::default();
        for l in lights {
            set.push(l);
        }
        set
    }

    /// Empties the set, keeping its memory (a renderer refills it every frame).
    pub fn clear(&mut self) {
        self.ambient = Vec3::ZERO;
        self.directional.clear();
        self.point.clear();
    }

    /// Adds one light; a non-finite one, or a directional light with a zero-length
    /// direction, is dropped.
    pub fn push(&mut self, light: &Light) {
        match *light {
            Light::Ambient { color } if color.is_finite() => self.ambient += color,
            Light::Directional { direction, color } => {
                let d = -direction.normalize_or_zero();
                if d != Vec3::ZERO && color.is_finite() {
                    self.directional.push((d, color));
                }
            }
            Light::Point { position, color } if position.is_finite() && color.is_finite() => {
                self.point.push((position, color));
            }
            _ => {}
        }
    }
}

/// Phong parameters of a surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Ambient factor on the diffuse colour.
    pub ambient: Vec3,
    /// Exponent n, clamped to 1..=2000 by the caller.
    pub shininess: f32,
}

/// Evaluates the lighting equation at `p` with unit normal `n`, eye at `eye`.
#[must_use]
#[inline(always)]
pub fn illuminate<const BLINN: bool>(
    lights: &LightSet,
    s: &Surface,
    p: Vec3,
    n: Vec3,
    eye: Vec3,
) -> Vec3 {
    let spec = s.specular != Vec3::ZERO;
    // The view vector is only needed for highlights.
    let v = if spec {
        (eye - p).normalize_or_zero()
    } else {
        Vec3::ZERO
    };
    let mut c = lights.ambient * s.ambient * s.diffuse;
    for &(l, color) in &lights.directional {
        c += color * term::<BLINN>(s, n, l, v, spec);
    }
    for &(pos, color) in &lights.point {
        c += color * term::<BLINN>(s, n, (pos - p).normalize_or_zero(), v, spec);
    }
    c
}

/// Diffuse plus specular reflection of one light arriving from unit direction `l`.
#[inline(always)]
fn term<const BLINN: bool>(s: &Surface, n: Vec3, l: Vec3, v: Vec3, spec: bool) -> Vec3 {
    let ndl = n.dot(l);
    if ndl <= 0.0 {
        return Vec3::ZERO;
    }
    let mut t = s.diffuse * ndl;
    if spec {
        let base = if BLINN {
            n.dot((l + v).normalize_or_zero())
        } else {
            (2.0 * ndl * n - l).dot(v)
        };
        if base > 0.0 {
            t += s.specular * base.powf(s.shininess);
        }
    }
    t
}

/// Phong parameters of eight surface points: the diffuse colour per lane (it may come from
/// a texture or vertex colours), the rest shared.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceLanes {
    pub diffuse: V3,
    pub specular: Vec3,
    pub ambient: Vec3,
    pub shininess: f32,
}

/// [`illuminate`] on eight lanes at once: the same equation and the same decisions (no
/// specular term where `N·L <= 0` or `K_s = 0`), evaluated with the kernel's arithmetic and
/// the lane `pow` ([`F8::powf`]); agrees with [`illuminate`] to float rounding (tested).
/// Work for a light is skipped when no lane faces it.
#[must_use]
#[inline(always)]
pub fn illuminate_lanes<K: Kernel>(
    lights: &LightSet,
    s: &SurfaceLanes,
    p: V3,
    n: V3,
    eye: Vec3,
    blinn: bool,
) -> V3 {
    let spec = s.specular != Vec3::ZERO;
    let v = if spec {
        (V3::splat(eye) - p).normalize_or_zero::<K>()
    } else {
        V3::default()
    };
    let mut c = s.diffuse * (lights.ambient * s.ambient);
    for &(l, color) in &lights.directional {
        c = c + term_lanes::<K>(s, n, V3::splat(l), v, spec, blinn) * color;
    }
    for &(pos, color) in &lights.point {
        let l = (V3::splat(pos) - p).normalize_or_zero::<K>();
        c = c + term_lanes::<K>(s, n, l, v, spec, blinn) * color;
    }
    c
}

#[inline(always)]
fn term_lanes<K: Kernel>(s: &SurfaceLanes, n: V3, l: V3, v: V3, spec: bool, blinn: bool) -> V3 {
    let ndl = n.dot::<K>(l);
    let lit = ndl.gt(F8::ZERO);
    if lit.bits() == 0 {
        return V3::default();
    }
    let ndl = F8::select(lit, ndl, F8::ZERO);
    let mut t = s.diffuse.scale(ndl);
    if spec {
        let base = if blinn {
            n.dot::<K>((l + v).normalize_or_zero::<K>())
        } else {
            (n.scale(ndl + ndl) - l).dot::<K>(v)
        };
        let lobe = base.powf::<K>(F8::splat(s.shininess));
        let lobe = F8::select(lit, lobe, F8::ZERO);
        t = t + V3::splat(s.specular).scale(lobe);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn white() -> Surface {
        Surface {
            diffuse: Vec3::ONE,
            specular: Vec3::ONE,
            ambient: Vec3::ONE,
            shininess: 10.0,
        }
    }

    #[test]
    fn lambert_and_mirror_highlight() {
        let lights = LightSet::new(&[Light::Directional {
            direction: -Vec3::Z,
            color: Vec3::ONE,
        }]);
        // Light and eye straight above the surface: N.L = 1, R.V = 1.
        let c = illuminate::<false>(&lights, &white(), Vec3::ZERO, Vec3::Z, Vec3::Z * 5.0);
        assert!((c - Vec3::splat(2.0)).abs().max_element() < 1e-6, "{c}");
        // Light at 60 degrees: diffuse 0.5; eye on the mirror direction: specular 1.
        let l = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
        let lights = LightSet::new(&[Light::Directional {
            direction: -l,
            color: Vec3::ONE,
        }]);
        let eye = Vec3::new(-l.x, 0.0, l.z) * 4.0;
        let c = illuminate::<false>(&lights, &white(), Vec3::ZERO, Vec3::Z, eye);
        assert!((c.x - 1.5).abs() < 1e-5, "{c}");
        let b = illuminate::<true>(&lights, &white(), Vec3::ZERO, Vec3::Z, eye);
        assert!((b.x - 1.5).abs() < 1e-5, "{b}");
    }

    /// The lane form against the scalar one on random surfaces, lights and views.
    #[test]
    fn lanes_agree_with_scalar() {
        use crate::raster::{kernel::Portable, Kernel};
        fn check<K: Kernel>() {
            let mut seed = 7u64;
            let mut r = move || {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((seed >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
            };
            let mut worst = 0f32;
            for case in 0..400 {
                let lights = LightSet::new(&[
                    Light::Ambient {
                        color: Vec3::splat(0.1),
                    },
                    Light::Directional {
                        direction: Vec3::new(r(), r(), r()),
                        color: Vec3::new(0.9, 0.8, 0.7),
                    },
                    Light::Point {
                        position: Vec3::new(r(), r(), r()) * 3.0,
                        color: Vec3::ONE,
                    },
                ]);
                let s = Surface {
                    diffuse: Vec3::new(0.8, 0.5, 0.2),
                    specular: Vec3::splat(0.5),
                    ambient: Vec3::ONE,
                    shininess: [1.0, 8.0, 32.0, 200.0][case % 4],
                };
                let eye = Vec3::new(r(), r(), r()) * 4.0;
                let mut p = [Vec3::ZERO; 8];
                let mut n = [Vec3::ZERO; 8];
                for i in 0..8 {
                    p[i] = Vec3::new(r(), r(), r());
                    n[i] = Vec3::new(r(), r(), r()).normalize_or_zero();
                }
                let lanes = |f: &dyn Fn(Vec3) -> f32, v: &[Vec3; 8]| F8(v.map(f));
                let pv = V3::new(
                    lanes(&|v| v.x, &p),
                    lanes(&|v| v.y, &p),
                    lanes(&|v| v.z, &p),
                );
                let nv = V3::new(
                    lanes(&|v| v.x, &n),
                    lanes(&|v| v.y, &n),
                    lanes(&|v| v.z, &n),
                );
                let sl = SurfaceLanes {
                    diffuse: V3::splat(s.diffuse),
                    specular: s.specular,
                    ambient: s.ambient,
                    shininess: s.shininess,
                };
                for blinn in [false, true] {
                    let got = illuminate_lanes::<K>(&lights, &sl, pv, nv, eye, blinn);
                    for i in 0..8 {
                        let want = if blinn {
                            illuminate::<true>(&lights, &s, p[i], n[i], eye)
                        } else {
                            illuminate::<false>(&lights, &s, p[i], n[i], eye)
                        };
                        let g = Vec3::new(got.x.0[i], got.y.0[i], got.z.0[i]);
                        let err = (g - want).abs().max_element();
                        worst = worst.max(err);
                        assert!(err < 2e-5 * (1.0 + want.max_element()), "{g} vs {want}");
                    }
                }
            }
            assert!(worst < 2e-5, "worst {worst}");
        }
        check::<Portable>();
        check::<crate::raster::kernel::Avx2>();
    }

    #[test]
    fn back_lit_gets_only_ambient() {
        let lights = LightSet::new(&[
            Light::Ambient {
                color: Vec3::splat(0.1),
            },
            Light::Directional {
                direction: Vec3::Z,
                color: Vec3::ONE,
            },
        ]);
        let c = illuminate::<true>(&lights, &white(), Vec3::ZERO, Vec3::Z, Vec3::Z);
        assert!((c - Vec3::splat(0.1)).abs().max_element() < 1e-7);
    }
}
