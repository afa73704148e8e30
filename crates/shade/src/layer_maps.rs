//! The textures of the `KHR_materials_*` extensions ([`Slot::LAYERS`]): what each reads
//! from its texel and how the values change a point's [`Pbr`] parameters, written once for
//! the pixel shader (on lanes), the pixel probe (`f32`) and the f64 reference.
//!
//! | slot | channel | multiplies |
//! |---|---|---|
//! | `specularTexture` | A | `specularFactor`: the dielectric lobe's `F0` and `F90` |
//! | `specularColorTexture` | RGB | `specularColorFactor`: `F0 = min(F0_ior · colour, 1) · specular` |
//! | `clearcoatTexture` | R | `clearcoatFactor` |
//! | `clearcoatRoughnessTexture` | G | `clearcoatRoughnessFactor` |
//! | `clearcoatNormalTexture` | RGB | the coat's own normal map (the caller perturbs the coat normal with [`crate::maps`]) |
//! | `sheenColorTexture` | RGB | `sheenColorFactor` |
//! | `sheenRoughnessTexture` | A | `sheenRoughnessFactor` |
//! | `iridescenceTexture` | R | `iridescenceFactor` |
//! | `iridescenceThicknessTexture` | G | the film's thickness: `mix(minimum, maximum, G)` (without it, the maximum) |
//! | `diffuseTransmissionTexture` | A | `diffuseTransmissionFactor` |
//! | `diffuseTransmissionColorTexture` | RGB | `diffuseTransmissionColorFactor` |
//! | `transmissionTexture` | R | `transmissionFactor` |
//! | `thicknessTexture` | G | `thicknessFactor` |
//! | `anisotropyTexture` | RGB | RG the direction in the tangent frame, B `anisotropyStrength` ([`LayerTexels::anisotropy`]) |
//!
//! The channels are the extensions' own (so one image can pack the clear coat in R and its
//! roughness in G, or the sheen colour in RGB and its roughness in A).

use crate::brdf::{self, Pbr};
use crate::lighting::PbrParams;
use crate::scene::Slot;
use crate::simd::Num;

/// How many values the extensions' textures give a point (see [`LayerTexels::values`]).
pub const LAYER_VALUES: usize = 21;

/// Where the texel of a slot of [`Slot::LAYERS`] goes: its first channel, how many
/// channels, and the index of the first in [`LayerTexels::values`]; `None` for the coat's
/// normal map, which is not a factor.
#[must_use]
pub const fn channels(slot: Slot) -> Option<(usize, usize, usize)> {
    match slot {
        Slot::SpecularStrength => Some((3, 1, 0)),
        Slot::SpecularColor => Some((0, 3, 1)),
        Slot::Clearcoat => Some((0, 1, 4)),
        Slot::ClearcoatRoughness => Some((1, 1, 5)),
        Slot::SheenColor => Some((0, 3, 6)),
        Slot::SheenRoughness => Some((3, 1, 9)),
        Slot::Iridescence => Some((0, 1, 10)),
        Slot::IridescenceThickness => Some((1, 1, 11)),
        Slot::Anisotropy => Some((0, 3, 12)),
        Slot::DiffuseTransmission => Some((3, 1, 15)),
        Slot::DiffuseTransmissionColor => Some((0, 3, 16)),
        Slot::Transmission => Some((0, 1, 19)),
        Slot::Thickness => Some((1, 1, 20)),
        _ => None,
    }
}

/// What the extensions' textures read at a point: the values of the slots in `mask` (bit
/// `i` for `Slot::LAYERS[i]`), the others unread.
#[derive(Clone, Copy, Debug)]
pub struct LayerTexels<T: Num> {
    pub mask: u8,
    /// Specular strength, specular colour (3), clear coat, its roughness, sheen colour (3),
    /// sheen roughness, iridescence, its thickness, anisotropy direction (2) and strength,
    /// diffuse transmission and its colour (3), transmission, thickness.
    pub values: [T; LAYER_VALUES],
}

impl<T: Num> Default for LayerTexels<T> {
    fn default() -> Self {
        Self {
            mask: 0,
            values: [T::ONE; LAYER_VALUES],
        }
    }
}

impl<T: Num> LayerTexels<T> {
    /// Whether the point read `slot`.
    #[inline(always)]
    #[must_use]
    pub fn has(&self, slot: Slot) -> bool {
        slot.layer_index()
            .is_some_and(|i| self.mask & (1 << i) != 0)
    }

    /// Takes `texel`, read from `slot`'s texture ([`channels`]).
    #[inline(always)]
    pub fn read(&mut self, slot: Slot, texel: [T; 4]) {
        let (Some(i), Some((from, n, to))) = (slot.layer_index(), channels(slot)) else {
            return;
        };
        self.mask |= 1 << i;
        self.values[to..to + n].copy_from_slice(&texel[from..from + n]);
    }

    /// The base's anisotropy at a point of unit normal `n` and interpolated tangent
    /// `tangent` (handedness `w`), from the material's `params` and the anisotropy
    /// texture's values if read; `None` for an isotropic material.
    #[inline(always)]
    #[must_use]
    pub fn anisotropy(
        &self,
        params: &PbrParams,
        n: T::V,
        tangent: T::V,
        w: T,
    ) -> Option<brdf::Anisotropy<T>> {
        if params.anisotropy <= 0.0 {
            return None;
        }
        let (s, c) = libm::sincosf(params.anisotropy_rotation);
        let strength = T::of(params.anisotropy);
        let (dir, strength) = if self.has(Slot::Anisotropy) {
            let v = &self.values;
            let two = T::of(2.0);
            (
                [v[12] * two - T::ONE, v[13] * two - T::ONE],
                strength * v[14],
            )
        } else {
            ([T::ONE, T::ZERO], strength)
        };
        Some(brdf::Anisotropy::at(n, tangent, w, dir, [c, s], strength))
    }

    /// Applies the values read to `p`, the point's parameters from the material's factors
    /// `params` (see the module's table).
    #[inline(always)]
    pub fn apply(&self, params: &PbrParams, p: &mut Pbr<T>) {
        if self.mask == 0 {
            return;
        }
        let v = &self.values;
        let strength = v[0];
        if self.has(Slot::SpecularColor) {
            let [r, g, b] = T::xyz(T::vec(params.f0_tint) * T::new3(v[1], v[2], v[3]));
            let s = T::of(params.f90) * strength;
            p.f0 = T::new3(r.min(T::ONE) * s, g.min(T::ONE) * s, b.min(T::ONE) * s);
        } else if self.has(Slot::SpecularStrength) {
            p.f0 = p.f0 * strength;
        }
        if self.has(Slot::SpecularStrength) {
            p.f90 = p.f90 * strength;
        }
        if let Some(t) = &mut p.transmission {
            if self.has(Slot::Transmission) {
                t.factor = t.factor * v[19];
            }
            if self.has(Slot::Thickness) {
                t.thickness = t.thickness * v[20];
            }
        }
        if let Some(tr) = &mut p.translucency {
            if self.has(Slot::DiffuseTransmission) {
                tr.factor = tr.factor * v[15];
            }
            if self.has(Slot::DiffuseTransmissionColor) {
                tr.color = tr.color * T::new3(v[16], v[17], v[18]);
            }
        }
        if let Some(i) = &mut p.iridescence {
            if self.has(Slot::Iridescence) {
                i.factor = i.factor * v[10];
            }
            if self.has(Slot::IridescenceThickness) {
                let [lo, hi] = params.iridescence_thickness;
                i.thickness = crate::iridescence::thickness(T::of(lo), T::of(hi), Some(v[11]));
            }
        }
        let Some(y) = &mut p.layers else {
            return;
        };
        if self.has(Slot::Clearcoat) {
            y.coat = y.coat * v[4];
        }
        if self.has(Slot::ClearcoatRoughness) {
            y.coat_roughness = y.coat_roughness * v[5];
            y.coat_alpha = brdf::alpha(y.coat_roughness);
        }
        if self.has(Slot::SheenColor) {
            y.sheen = y.sheen * T::new3(v[6], v[7], v[8]);
            y.sheen_max = T::vmax(y.sheen);
        }
        if self.has(Slot::SheenRoughness) {
            y.sheen_roughness = y.sheen_roughness * v[9];
            y.sheen_alpha = crate::sheen::alpha(y.sheen_roughness);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Every slot but the coat's normal map has its values, and no two share one.
    #[test]
    fn the_slots_values_do_not_overlap() {
        let mut used = [false; LAYER_VALUES];
        for slot in Slot::LAYERS {
            let Some((from, n, to)) = channels(slot) else {
                assert_eq!(slot, Slot::ClearcoatNormal);
                continue;
            };
            assert!(from + n <= 4, "{slot:?}");
            for u in &mut used[to..to + n] {
                assert!(!*u, "{slot:?} overlaps");
                *u = true;
            }
        }
        assert!(used.iter().all(|&u| u));
    }

    /// The specification's formulas for the dielectric lobe, in f64 from the factors.
    #[test]
    fn specular_textures_multiply_the_factors_as_the_specification_says() {
        let ior = 1.5f64;
        let f0_ior = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let (specular, color) = (0.8f64, [2.0f64, 10.0, 0.5]);
        let (st, ct) = (0.5f64, [0.9f64, 0.8, 0.2]);
        let params = PbrParams {
            f0: Vec3::ZERO,
            f0_tint: Vec3::from_array(color.map(|c| (c * f0_ior) as f32)),
            f90: specular as f32,
            ..PbrParams::default()
        };
        let surface = crate::Surface {
            diffuse: Vec3::ONE,
            specular: Vec3::ZERO,
            ambient: Vec3::ONE,
            shininess: 1.0,
            pbr: Some(params),
        };
        let mut s = surface.at::<f64>(glam::DVec3::ONE);
        let p = s.pbr.as_mut().unwrap();
        let mut t = LayerTexels::<f64>::default();
        t.read(Slot::SpecularStrength, [0.0, 0.0, 0.0, st]);
        t.read(Slot::SpecularColor, [ct[0], ct[1], ct[2], 1.0]);
        t.apply(&params, p);
        for k in 0..3 {
            let want = (f0_ior * color[k] * ct[k]).min(1.0) * specular * st;
            assert!(
                (p.f0[k] - want).abs() < 1e-6,
                "F0[{k}] {} != {want}",
                p.f0[k]
            );
        }
        assert!((p.f90 - specular * st).abs() < 1e-6);
    }
}
