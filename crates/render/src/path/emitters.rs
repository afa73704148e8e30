//! The scene's emissive triangles as the path tracer's lights (next-event estimation):
//! drawn in proportion to their power, a point uniformly on the chosen one.

use glam::Vec3;

use super::super::whitted::Tracer;
use super::sampling::{luminance, Rng};
use crate::scalar::Scalar;

/// The scene's emissive triangles as lights: drawn in proportion to their power (area
/// times the luminance of their emission), a point uniformly on the chosen one.
#[derive(Debug)]
pub(crate) struct Emitters {
    tris: Vec<Emitter>,
    /// Cumulative power share.
    cdf: Vec<f32>,
    /// Each triangle's chance, by (instance key, triangle).
    index: std::collections::HashMap<(u64, u32), usize>,
}

/// One emissive triangle: world corners, emission (for an emissive texture, its estimate
/// at the centroid: the point drawn is shaded for its own), area, and for a textured one
/// its instance key and triangle.
#[derive(Debug)]
struct Emitter {
    corners: [Vec3; 3],
    emitted: Vec3,
    area: f32,
    /// Instance key and triangle.
    key: (u64, u32),
    textured: bool,
}

/// A point drawn on an emitter: the unit direction to it, its distance, its emission (for
/// a textured emitter, shaded at the point by the caller from `textured`) and the density
/// per unit solid angle.
pub(super) struct Drawn<T: Scalar> {
    pub(super) dir: T::V,
    pub(super) dist: T,
    pub(super) emitted: Vec3,
    pub(super) pdf: T,
    /// The emitter's instance key and triangle.
    pub(super) key: (u64, u32),
    pub(super) textured: Option<realist_trace::Hit>,
}

/// Share of the emission factor's luminance a textured triangle is drawn with at least,
/// whatever its centroid shows: every point that may emit keeps a chance to be drawn.
const TEXTURED_FLOOR: f32 = 1.0 / 16.0;

impl Emitters {
    /// Every shown triangle whose material emits. A triangle under an emissive texture is
    /// drawn in proportion to its area times the emission at its centroid (at least
    /// [`TEXTURED_FLOOR`] of the factor's), and the point drawn is shaded for its own
    /// emission, so the estimate stays unbiased.
    pub(super) fn new(t: &Tracer) -> Self {
        let mut tris = Vec::new();
        for (k, inst) in t.scene.instances.iter().enumerate() {
            let Some(r) = t.resolved.get(k).and_then(Option::as_ref) else {
                continue;
            };
            let e = r.params.emissive;
            if r.params.unlit || luminance::<f32>(e) <= 0.0 || !e.is_finite() {
                continue;
            }
            let textured = r.params.emissive_map.is_some();
            let mesh = &t.scene.meshes[inst.mesh].tri;
            for copy in 0..inst.copy_count() {
                let world = inst.placement(copy);
                let key = (k as u64) << 32 | copy as u64;
                for (i, tr) in mesh.triangles.iter().enumerate() {
                    let c = tr.map(|v| {
                        mesh.positions
                            .get(v as usize)
                            .map_or(Vec3::NAN, |p| world.transform_point3(*p))
                    });
                    let area = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).length();
                    if !(area > 0.0 && area.is_finite()) {
                        continue;
                    }
                    let emitted = if textured {
                        let seen = centroid_emission(t, key, i as u32, c).unwrap_or(Vec3::ZERO);
                        seen.max(e * TEXTURED_FLOOR)
                    } else {
                        e
                    };
                    tris.push(Emitter {
                        corners: c,
                        emitted,
                        area,
                        key: (key, i as u32),
                        textured,
                    });
                }
            }
        }
        let mut cdf = Vec::with_capacity(tris.len());
        let mut sum = 0.0f64;
        for e in &tris {
            sum += f64::from(luminance::<f32>(e.emitted) * e.area);
            cdf.push(sum as f32);
        }
        if sum > 0.0 {
            for c in &mut cdf {
                *c /= sum as f32;
            }
        }
        let index = tris.iter().enumerate().map(|(i, e)| (e.key, i)).collect();
        Self { tris, cdf, index }
    }

    fn chance(&self, i: usize) -> f32 {
        self.cdf[i] - if i > 0 { self.cdf[i - 1] } else { 0.0 }
    }

    /// A point on an emitter seen from `p` (both sides emit).
    pub(super) fn sample<T: Scalar>(&self, p: T::V, rng: &mut Rng) -> Option<Drawn<T>> {
        if self.tris.is_empty() {
            return None;
        }
        let u = rng.f();
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.tris.len() - 1);
        let em = &self.tris[i];
        let [a, b, c] = em.corners;
        let (r1, r2) = (rng.f().sqrt(), rng.f());
        let bary = [1.0 - r1, r1 * (1.0 - r2), r1 * r2];
        let [ta, tb, tc] = [a, b, c].map(T::vec);
        let q = ta * T::of(bary[0]) + tb * T::of(bary[1]) + tc * T::of(bary[2]);
        let d = q - p;
        let dist2 = T::dot(d, d);
        let dist = dist2.sqrt();
        let w = T::vdiv(d, dist);
        let n = T::normalize_or_zero(T::cross(tb - ta, tc - ta));
        let cos = T::dot(n, w).abs();
        if !(cos > T::ZERO && dist > T::ZERO) {
            return None;
        }
        let (key, triangle) = em.key;
        let textured = em.textured.then_some(realist_trace::Hit {
            t: T::to_f64(dist) as f32,
            instance: 0,
            key,
            triangle,
            bary,
            front: T::dot(n, w) < T::ZERO,
        });
        Some(Drawn {
            dir: w,
            dist,
            emitted: em.emitted,
            pdf: T::of(self.chance(i)) / T::of(em.area) * dist2 / cos,
            key: em.key,
            textured,
        })
    }

    /// The density [`Emitters::sample`] gives the direction towards triangle `tri` of
    /// instance `key`, met at distance `t` at cosine `cos`.
    pub(super) fn pdf<T: Scalar>(&self, key: u64, tri: u32, t: T, cos: T) -> Option<T> {
        let &i = self.index.get(&(key, tri))?;
        let area = T::of(self.tris[i].area);
        (cos > T::ZERO).then(|| T::of(self.chance(i)) / area * t * t / cos)
    }
}

/// The emission of triangle `triangle` of instance `key` (world corners `c`) at its
/// centroid, seen from a unit in front of it.
fn centroid_emission(t: &Tracer, key: u64, triangle: u32, c: [Vec3; 3]) -> Option<Vec3> {
    let centre = (c[0] + c[1] + c[2]) / 3.0;
    let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero();
    let hit = realist_trace::Hit {
        t: 1.0,
        instance: 0,
        key,
        triangle,
        bary: [1.0 / 3.0; 3],
        front: true,
    };
    let (pt, _) = t.point::<f32>(&hit, centre + n, -n)?;
    Some(pt.emitted).filter(|e| e.is_finite())
}
