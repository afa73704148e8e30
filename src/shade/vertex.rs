//! The vertex stage: per-vertex (or, for flat shading, per-facet) work that produces clip
//! positions and the varyings of each mode. Runs in parallel over vertices.

use std::borrow::Cow;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::lighting::{illuminate, LightSet, Surface};
use super::render::Inst;
use super::shaders::{Debug, DrawParams, LitVarying};
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

/// The lighting equation at a vertex or facet centroid, seen from the side `n` points to.
fn lit_colour(d: &DrawParams, lights: &LightSet, eye: Vec3, p: Vec3, n: Vec3, c: Vec4) -> Vec4 {
    let base = d.base * c;
    let s = Surface {
        diffuse: base.truncate(),
        ..d.surface
    };
    illuminate::<false>(lights, &s, p, n, eye).extend(base.w)
}

/// Gouraud: lighting per vertex, colours interpolated. Double-sided materials also get the
/// colour of the back side (normal flipped), chosen per triangle by the shader.
pub(super) fn gouraud(
    i: &Inst,
    params: &[DrawParams],
    lights: &LightSet,
    eye: Vec3,
) -> (Vec<Vec4>, Vec<(Vec4, Vec4)>) {
    let d = &params[i.id as usize];
    let tri = i.tri;
    let clip = transform_positions(i.mvp, &tri.positions);
    let var = (0..tri.positions.len())
        .into_par_iter()
        .with_min_len(MIN_LEN)
        .map(|k| {
            let (p, n) = world(i, k);
            let c = tri.colors.as_ref().map_or(Vec4::ONE, |c| c[k]);
            let front = lit_colour(d, lights, eye, p, n, c);
            let back = if d.double_sided {
                lit_colour(d, lights, eye, p, -n, c)
            } else {
                front
            };
            (front, back)
        })
        .collect();
    (clip, var)
}

/// Flat: one lighting evaluation per facet, at its area-weighted centroid with its plane
/// normal turned towards the eye on double-sided materials; triangles are unindexed so every
/// corner carries its facet's colour.
pub(super) fn flat<'a>(
    i: &'a Inst,
    params: &[DrawParams],
    lights: &LightSet,
    eye: Vec3,
) -> (Vec<Vec4>, Vec<Vec4>, Cow<'a, [[u32; 3]]>) {
    let d = &params[i.id as usize];
    let tri = i.tri;
    // Area-weighted centroid of each facet (its triangles' centroids weighted by area).
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
    // Seed 000: the facet takes the colour of its first vertex.
    let mut first_color = vec![Vec4::ONE; nf];
    if let Some(c) = &tri.colors {
        for (t, f) in tri
            .triangles
            .iter()
            .rev()
            .zip(tri.triangle_facets.iter().rev())
        {
            if let Some(slot) = first_color.get_mut(*f as usize) {
                *slot = c[t[0] as usize];
            }
        }
    }
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
            let mut n = (i.normal * tri.facet_normals[f]).normalize_or_zero();
            if d.double_sided && n.dot(eye - p) < 0.0 {
                n = -n;
            }
            lit_colour(d, lights, eye, p, n, first_color[f])
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
