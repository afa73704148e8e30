//! The material, light and camera properties a pose animates (`KHR_animation_pointer`),
//! set from the pose and returned to their rest values before the next one.

use std::sync::Arc;

use glam::{Vec3, Vec4};

use super::PreparedScene;
use crate::scene::Pose;

impl PreparedScene {
    /// Sets the material, light and camera properties `pose` animates (clamped to their
    /// ranges; a non-finite value leaves the rest value), after returning those the last
    /// pose changed to rest. Field by field, so posing allocates nothing.
    pub(super) fn pose_values(&mut self, pose: &Pose) {
        use crate::scene::anim::{Property as P, Target};
        let rest = Arc::clone(&self.scene);
        for (kind, k) in self.animated.drain(..) {
            match kind {
                Target::Material => {
                    if let (Some(m), Some(r)) = (self.materials.get_mut(k), rest.materials.get(k)) {
                        m.base_color = r.base_color;
                        m.emissive = r.emissive;
                        m.metallic = r.metallic;
                        m.roughness = r.roughness;
                        if let (Some(p), Some(q)) = (&mut m.pbr, &r.pbr) {
                            p.emissive_strength = q.emissive_strength;
                            p.clearcoat = q.clearcoat;
                            p.clearcoat_roughness = q.clearcoat_roughness;
                            p.sheen_color = q.sheen_color;
                            p.sheen_roughness = q.sheen_roughness;
                        }
                        for slot in crate::scene::Slot::ALL {
                            if let (Some(t), Some(q)) = (m.slot_mut(slot).as_mut(), r.slot(slot)) {
                                t.transform = q.transform;
                            }
                        }
                    }
                }
                Target::Light => {
                    if let (Some(l), Some(r)) = (self.lights.get_mut(k), rest.lights.get(k)) {
                        l.color = r.color;
                        l.intensity = r.intensity;
                        l.inner = r.inner;
                        l.outer = r.outer;
                    }
                }
                Target::Camera => {
                    if let (Some(c), Some(r)) = (self.cameras.get_mut(k), rest.cameras.get(k)) {
                        c.yfov = r.yfov;
                    }
                }
                Target::Node => {}
            }
        }
        let finite = |x: f32| x.is_finite().then_some(x);
        let rgb = |v: [f32; 4]| Some(Vec3::new(v[0], v[1], v[2])).filter(|c| c.is_finite());
        let half_pi = std::f32::consts::FRAC_PI_2;
        for &(k, property, v) in &pose.values {
            let kind = property.target();
            match kind {
                // Only the scene's own materials (not the default or the ground after them).
                Target::Material if k < rest.materials.len() => {
                    let Some(m) = self.materials.get_mut(k) else {
                        continue;
                    };
                    match property {
                        P::BaseColor => {
                            if v.iter().all(|x| x.is_finite()) {
                                m.base_color = Vec4::from_array(v).clamp(Vec4::ZERO, Vec4::ONE);
                            }
                        }
                        P::Emissive => {
                            if let Some(e) = rgb(v) {
                                m.emissive = e.max(Vec3::ZERO);
                            }
                        }
                        P::Metallic => {
                            m.metallic = finite(v[0]).map_or(m.metallic, |x| x.clamp(0.0, 1.0));
                        }
                        P::Roughness => {
                            m.roughness = finite(v[0]).map_or(m.roughness, |x| x.clamp(0.0, 1.0));
                        }
                        P::EmissiveStrength => {
                            if let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) {
                                p.emissive_strength = x.max(0.0);
                            }
                        }
                        P::ClearcoatFactor
                        | P::ClearcoatRoughness
                        | P::SheenColor
                        | P::SheenRoughness => {
                            let Some(p) = &mut m.pbr else { continue };
                            let unit = |x: f32| finite(x).map(|x| x.clamp(0.0, 1.0));
                            match property {
                                P::ClearcoatFactor => {
                                    p.clearcoat = unit(v[0]).unwrap_or(p.clearcoat);
                                }
                                P::ClearcoatRoughness => {
                                    p.clearcoat_roughness =
                                        unit(v[0]).unwrap_or(p.clearcoat_roughness);
                                }
                                P::SheenRoughness => {
                                    p.sheen_roughness = unit(v[0]).unwrap_or(p.sheen_roughness);
                                }
                                _ => {
                                    if let Some(c) = rgb(v) {
                                        p.sheen_color = c.clamp(Vec3::ZERO, Vec3::ONE);
                                    }
                                }
                            }
                        }
                        P::IridescenceFactor
                        | P::IridescenceIor
                        | P::IridescenceThicknessMin
                        | P::IridescenceThicknessMax => {
                            let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) else {
                                continue;
                            };
                            match property {
                                P::IridescenceFactor => p.iridescence = x.clamp(0.0, 1.0),
                                P::IridescenceIor => p.iridescence_ior = x.max(1.0),
                                P::IridescenceThicknessMin => {
                                    p.iridescence_thickness[0] = x.max(0.0);
                                }
                                _ => p.iridescence_thickness[1] = x.max(0.0),
                            }
                        }
                        P::TransmissionFactor
                        | P::ThicknessFactor
                        | P::AttenuationDistance
                        | P::Dispersion => {
                            let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) else {
                                continue;
                            };
                            match property {
                                P::TransmissionFactor => p.transmission = x.clamp(0.0, 1.0),
                                P::ThicknessFactor => p.thickness = x.max(0.0),
                                P::AttenuationDistance if x > 0.0 => p.attenuation_distance = x,
                                P::Dispersion => p.dispersion = x.max(0.0),
                                _ => {}
                            }
                        }
                        P::AttenuationColor => {
                            if let (Some(p), Some(c)) = (&mut m.pbr, rgb(v)) {
                                p.attenuation_color = c.clamp(Vec3::ZERO, Vec3::ONE);
                            }
                        }
                        P::DiffuseTransmission => {
                            if let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) {
                                p.diffuse_transmission = x.clamp(0.0, 1.0);
                            }
                        }
                        P::DiffuseTransmissionColor => {
                            if let (Some(p), Some(c)) = (&mut m.pbr, rgb(v)) {
                                p.diffuse_transmission_color = c.clamp(Vec3::ZERO, Vec3::ONE);
                            }
                        }
                        P::AnisotropyStrength | P::AnisotropyRotation => {
                            let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) else {
                                continue;
                            };
                            if property == P::AnisotropyStrength {
                                p.anisotropy = x.clamp(0.0, 1.0);
                            } else {
                                p.anisotropy_rotation = x;
                            }
                        }
                        P::TexOffset(slot) | P::TexRotation(slot) | P::TexScale(slot) => {
                            let Some(t) = m.slot_mut(slot).as_mut() else {
                                continue;
                            };
                            let pair = glam::Vec2::new(v[0], v[1]);
                            match property {
                                P::TexOffset(_) if pair.is_finite() => t.transform.offset = pair,
                                P::TexScale(_) if pair.is_finite() => t.transform.scale = pair,
                                P::TexRotation(_) if v[0].is_finite() => {
                                    t.transform.rotation = v[0];
                                }
                                _ => {}
                            }
                        }
                        _ => continue,
                    }
                }
                Target::Light => {
                    let Some(l) = self.lights.get_mut(k) else {
                        continue;
                    };
                    match property {
                        P::LightColor => {
                            if let Some(c) = rgb(v) {
                                l.color = c.max(Vec3::ZERO);
                            }
                        }
                        P::LightIntensity => {
                            l.intensity = finite(v[0]).map_or(l.intensity, |x| x.max(0.0));
                        }
                        // The cone: outer in (0, π/2], inner in [0, outer].
                        P::SpotOuter => {
                            if let Some(x) = finite(v[0]).filter(|x| *x > 0.0) {
                                l.outer = x.min(half_pi);
                                l.inner = l.inner.min(l.outer);
                            }
                        }
                        P::SpotInner => {
                            if let Some(x) = finite(v[0]) {
                                l.inner = x.clamp(0.0, l.outer);
                            }
                        }
                        _ => continue,
                    }
                }
                Target::Camera => {
                    let Some(c) = self.cameras.get_mut(k) else {
                        continue;
                    };
                    if let (P::CameraYfov, Some(x)) = (property, finite(v[0])) {
                        c.yfov = x.clamp(1e-3, std::f32::consts::PI - 1e-3);
                    } else {
                        continue;
                    }
                }
                Target::Material | Target::Node => continue,
            }
            self.animated.push((kind, k));
        }
    }
}
