//! The vertex stage: per-vertex (or, for flat shading, per-facet) work that produces clip
//! positions and the varyings of each mode. Runs in parallel over vertices.

use std::borrow::Cow;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::lighting::{illuminate, LightSet, Surface};
use super::render::Inst;
use super::shaders::{Debug, DrawParams, LitVarying};
use super::Shading;
use crate::raster::transform_positions;

const MIN_LEN: usize = 4096;

/// World position and unit world normal of render vertex `k`.
#[inline]
fn world(i: &Inst, k: usize) -> (Vec3, Vec3) {
    let p = i.world.transform_point3(i.tri.positions[k]);
    let n = (i.normal * i.tri.normals[k]).normalize_or_zero();
    (p, n)
}

/// Clip positions and per-pixel-lighting varyings.
pub(super) fn lit<V: LitVarying>(i: &Inst) -> (Vec<Vec4>, Vec<V>) {
    let clip = transform_positions(i.mvp, &i.tri.positions);
    let var = (0..i.tri.positions.len())
        .into_par_iter()
        .with_min_len(MIN_LEN)
        .map(|k| {
            let (p, n) = world(i, k);
            let uv = i.tri.uvs.as_ref().map_or(Vec2::ZERO, |u| u[k]);
            let c = i.tri.colors.as_ref().map_or(Vec4::ONE, |c| c[k]);
            V::new(p, n, uv, c)
        })
        .collect();
    (clip, var)
}

/// Gouraud (lighting per vertex) or flat (lighting per facet, triangles unindexed so every
/// corner carries its facet's colour).
pub(super) fn colour<'a>(
    i: &'a Inst,
    params: &[DrawParams],
    lights: &LightSet,
    eye: Vec3,
) -> (Vec<Vec4>, Vec<Vec4>, Cow<'a, [[u32; 3]]>) {
    let d = &params[i.id as usize];
    let shade = |p: Vec3, mut n: Vec3, c: Vec4| {
        if d.double_sided && n.dot(eye - p) < 0.0 {
            n = -n;
        }
        let base = d.base * c;
        let s = Surface {
            diffuse: base.truncate(),
            ..d.surface
        };
        illuminate::<false>(lights, &s, p, n, eye).extend(base.w)
    };
    let tri = i.tri;
    if i.mode == Shading::Gouraud {
        let clip = transform_positions(i.mvp, &tri.positions);
        let var = (0..tri.positions.len())
            .into_par_iter()
            .with_min_len(MIN_LEN)
            .map(|k| {
                let (p, n) = world(i, k);
                shade(p, n, tri.colors.as_ref().map_or(Vec4::ONE, |c| c[k]))
            })
            .collect();
        return (clip, var, Cow::Borrowed(&tri.triangles));
    }
    // Flat: area-weighted centroid of each facet (its triangles' centroids weighted by area).
    let nf = tri.facet_normals.len();
    let mut centroid = vec![Vec3::ZERO; nf];
    let mut area = vec![0.0f32; nf];
    for (t, f) in tri.triangles.iter().zip(&tri.triangle_facets) {
        let [a, b, c] = t.map(|k| tri.positions[k as usize]);
        let (f, ar) = (*f as usize, (b - a).cross(c - a).length());
        if f < nf && ar.is_finite() {
            centroid[f] += (a + b + c) * (ar / 3.0);
            area[f] += ar;
        }
    }
    let first_color: Vec<Vec4> = match &tri.colors {
        Some(c) => {
            let mut fc = vec![Vec4::ONE; nf];
            for (t, f) in tri
                .triangles
                .iter()
                .rev()
                .zip(tri.triangle_facets.iter().rev())
            {
                if let Some(slot) = fc.get_mut(*f as usize) {
                    *slot = c[t[0] as usize];
                }
            }
            fc
        }
        None => vec![Vec4::ONE; nf],
    };
    let facet_colour: Vec<Vec4> = (0..nf)
        .into_par_iter()
        .with_min_len(MIN_LEN)
        .map(|f| {
            let c = if area[f] > 0.0 {
                centroid[f] / area[f]
            } else {
                Vec3::ZERO
            };
            let p = i.world.transform_point3(c);
            let n = (i.normal * tri.facet_normals[f]).normalize_or_zero();
            shade(p, n, first_color[f])
        })
        .collect();
    let corners: Vec<Vec3> = tri
        .triangles
        .iter()
        .flat_map(|t| t.map(|k| tri.positions[k as usize]))
        .collect();
    let clip = transform_positions(i.mvp, &corners);
    let var = tri
        .triangle_facets
        .iter()
        .flat_map(|&f| [facet_colour.get(f as usize).copied().unwrap_or(Vec4::ZERO); 3])
        .collect();
    let tris = (0..tri.triangles.len() as u32)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    (clip, var, Cow::Owned(tris))
}

/// Debug views: the quantity itself as a Vec3.
pub(super) fn debug(i: &Inst, mode: Debug) -> (Vec<Vec4>, Vec<Vec3>) {
    let clip = transform_positions(i.mvp, &i.tri.positions);
    let var = (0..i.tri.positions.len())
        .into_par_iter()
        .with_min_len(MIN_LEN)
        .map(|k| match mode {
            Debug::Normals => world(i, k).1,
            Debug::Depth => Vec3::splat(-i.view.transform_point3(i.tri.positions[k]).z),
            Debug::Uv => i.tri.uvs.as_ref().map_or(Vec2::ZERO, |u| u[k]).extend(0.0),
        })
        .collect();
    (clip, var)
}
