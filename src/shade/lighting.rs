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
