//! The lit stages: the surface at each lane, the ambient (or image-based) term with the
//! emission, and each light's share.

use glam::Vec3;

use super::{anisotropic, coat_normal, position, Cx, Regs};
use crate::brdf::Pbr;
use crate::layer_maps::LayerTexels;
use crate::lighting::{ambient_at, contribution, emission_seen, view_vector, PbrParams, SurfaceAt};
use crate::raster::Batch;
use crate::shaders::DrawParams;
use crate::simd::{Level, F8, V3};

/// The surface of draw `d` at the lanes of `r` (after the maps); `PBR` false for a draw
/// of the Phong modes (its surface has no `pbr` part: said statically, the compiler leaves
/// the BRDF's code out of the caller).
#[inline(always)]
pub(super) fn surface<L: Level, const PBR: bool>(
    d: &DrawParams,
    r: &Regs,
    mask: u8,
) -> SurfaceAt<F8<L>> {
    let mut s = d
        .surface
        .at::<F8<L>>(V3::new(r.base[0].get(), r.base[1].get(), r.base[2].get()));
    if !PBR {
        s.pbr = None;
    }
    s.ks = V3::get(&r.ks);
    s.occlusion = d.occlusion.is_some().then(|| r.occlusion.get());
    s.emitted = (d.emissive != Vec3::ZERO).then(|| V3::get(&r.emitted));
    // Everything else is the `pbr` mode's: one test for the others.
    if let (Some(p), Some(params)) = (&mut s.pbr, &d.surface.pbr) {
        pbr_at(d, params, r, p, mask);
    }
    s
}

/// The `pbr` parameters of draw `d` at the lanes of `r`: the metallic-roughness texture,
/// the extensions' textures (`mask`: [`DrawParams::layer_mask`], taken once per stage), the
/// anisotropy's frame, the coat's normal.
#[inline(always)]
fn pbr_at<L: Level>(d: &DrawParams, params: &PbrParams, r: &Regs, p: &mut Pbr<F8<L>>, mask: u8) {
    if d.metal_rough.is_some() {
        p.roughness *= r.rough.get();
        p.metallic *= r.metal.get();
    }
    if mask != 0 {
        let mut t = LayerTexels::<F8<L>> {
            mask,
            ..LayerTexels::default()
        };
        for (v, lane) in t.values.iter_mut().zip(&r.layer) {
            *v = lane.get();
        }
        t.apply(params, p);
    }
    if anisotropic(d) {
        let t = V3::get(&r.aniso_t);
        p.anisotropy = Some(crate::brdf::Anisotropy {
            strength: r.aniso_strength.get(),
            t,
            b: V3::get(&r.n).cross(t),
        });
    }
    if let (Some(y), true) = (p.layers.as_mut(), coat_normal(d)) {
        y.coat_normal = Some(V3::get(&r.nc));
    }
}

crate::simd::per_kernel! {
    /// The normal turned to the side seen, the view vector, and the ambient term (Phong's,
    /// or `pbr`'s image-based light) plus the emission.
    pub(super) fn ambient_stage<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        // Two copies of the loop: the Phong modes' without the BRDF's code.
        if cx.d.surface.pbr.is_some() {
            ambient_groups::<L, true>(b, regs, cx);
        } else {
            ambient_groups::<L, false>(b, regs, cx);
        }
    }
}

/// [`ambient_stage`]'s loop, for a `pbr` draw or not (`PBR`).
#[inline(always)]
fn ambient_groups<L: Level, const PBR: bool>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>) {
    let eye = V3::<L>::splat(cx.s.eye);
    let mask = cx.d.layer_mask();
    for (g, r) in regs.iter_mut().enumerate() {
        let mut n = V3::<L>::get(&r.n);
        if !b.front {
            n = -n;
            n.set(&mut r.n);
            if PBR && coat_normal(cx.d) {
                (-V3::<L>::get(&r.nc)).set(&mut r.nc);
            }
        }
        let mut s = surface::<L, PBR>(cx.d, r, mask);
        let v = view_vector(&s, position(b, g), eye);
        v.set(&mut r.v);
        let mut c = ambient_at(cx.s.lights, &mut s, n, v);
        if let Some(p) = &s.pbr {
            r.ess.set(p.ess);
            if let Some(y) = &p.layers {
                r.coat_keep.set(y.coat_keep);
                r.sheen_ev.set(y.sheen_ev);
            }
            if let Some(i) = &p.iridescence {
                i.dielectric.set(&mut r.film_dielectric);
                i.metal.set(&mut r.film_metal);
            }
        }
        if let Some(e) = s.emitted {
            c = c + emission_seen(&s, e);
        }
        c.set(&mut r.c);
    }
}

crate::simd::per_kernel! {
    /// Light `arg`'s share (an index into the frame's sources).
    pub(super) fn light<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, arg: u32) {
        let Some(src) = cx.s.lights.sources.get(arg as usize) else {
            return;
        };
        if cx.d.surface.pbr.is_some() {
            light_groups::<L, true>(b, regs, cx, src);
        } else {
            light_groups::<L, false>(b, regs, cx, src);
        }
    }
}

/// [`light`]'s loop, for a `pbr` draw or not (`PBR`).
#[inline(always)]
fn light_groups<L: Level, const PBR: bool>(
    b: &mut Batch,
    regs: &mut [Regs],
    cx: &Cx<'_>,
    src: &crate::lighting::Source,
) {
    let (set, blinn, mask) = (cx.s.lights, cx.d.blinn, cx.d.layer_mask());
    for (g, r) in regs.iter_mut().enumerate() {
        let mut s = surface::<L, PBR>(cx.d, r, mask);
        if let Some(p) = &mut s.pbr {
            p.ess = r.ess.get();
            if let Some(y) = &mut p.layers {
                y.coat_keep = r.coat_keep.get();
                y.sheen_ev = r.sheen_ev.get();
            }
            if let Some(i) = &mut p.iridescence {
                i.dielectric = V3::get(&r.film_dielectric);
                i.metal = V3::get(&r.film_metal);
            }
        }
        let (n, v) = (V3::get(&r.n), V3::get(&r.v));
        let c = V3::<L>::get(&r.c) + contribution(set, src, &s, position(b, g), n, v, blinn);
        c.set(&mut r.c);
    }
}
