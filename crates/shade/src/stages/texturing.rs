//! The stages that read textures: each slot's texels, what the maps change (colour, gloss,
//! normal, occlusion, emission, metal-roughness), the extensions' slots and the anisotropy.

use super::{coat_normal, first_derivative, get4, set4, slots, Cx, Regs};
use crate::layer_maps::{self, LayerTexels};
use crate::maps::perturb_lanes;
use crate::raster::{Batch, Fragments};
use crate::scene::{Slot, TextureSource};
use crate::shaders::SlotParams;
use crate::simd::{Level, F8, V3};
use crate::texlab;

crate::simd::per_kernel! {
    /// The texels of slot `arg` (filtered by its sampler; a procedural texture evaluated
    /// lane by lane, outside the kernel: `texlab`).
    pub(super) fn sample<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, arg: u32) {
        let k = arg as usize;
        let Some(Some(t)) = slots(cx.d).get(k).copied() else {
            return;
        };
        let first = first_derivative(cx.d);
        let lod = cx.s.lod_scale;
        for (g, r) in regs.iter_mut().enumerate() {
            let texel = sample_slot::<L>(t, &b.group(g), lod, first);
            set4(&mut r.texel[k], texel);
        }
    }
}

/// Samples slot `t` on the lanes of `f` from the draw's varyings, with the exact UV
/// derivatives when the fill computed them, scaled by `lod_scale`; `first` is the first
/// varying with derivatives.
#[inline(always)]
fn sample_slot<L: Level>(
    t: &SlotParams,
    f: &Fragments<'_>,
    lod_scale: f32,
    first: usize,
) -> [F8<L>; 4] {
    let k = t.uv_at as usize;
    let texture = match &t.source {
        TextureSource::Image(texture) => texture,
        TextureSource::Procedural(p) => {
            return texlab::procedural_lanes(p, f, k, first, lod_scale);
        }
    };
    let v = f.var;
    let (u, w) = (v[k].get(), v[k + 1].get());
    let d = k.wrapping_sub(first);
    match (f.ddx.get(d..d + 2), f.ddy.get(d..d + 2)) {
        (Some([dudx, dvdx]), Some([dudy, dvdy])) => texture.sample_grad_lanes(
            u,
            w,
            dudx.get::<L>() * lod_scale,
            dvdx.get::<L>() * lod_scale,
            dudy.get::<L>() * lod_scale,
            dvdy.get::<L>() * lod_scale,
            f.mask,
            t.sampler,
        ),
        _ => texture.sample_lanes(u, w, f.mask, t.sampler),
    }
}

crate::simd::per_kernel! {
    /// What the sampled slots change: the base-colour texture the base colour and alpha, the
    /// gloss map `K_s`, the normal map and the bump map the normal, occlusion the ambient
    /// term, the emissive map the emission, the metallic-roughness texture its factors.
    pub(super) fn maps<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        let d = cx.d;
        let first = first_derivative(d);
        for (g, r) in regs.iter_mut().enumerate() {
            // Each slot's texel loaded where it is used (a `map` over all six was compiled
            // out of line, copying 24 lanes through the stack per group).
            let [base_t, gloss_t, normal_t, occlusion_t, emissive_t, mr_t] = &r.texel;
            if d.metal_rough.is_some() {
                let mr_t = get4::<L>(mr_t);
                r.rough.set(mr_t[1]);
                r.metal.set(mr_t[2]);
            }
            if d.base_map.is_some() {
                let mut c = get4::<L>(&r.base);
                for (c, t) in c.iter_mut().zip(get4::<L>(base_t)) {
                    *c *= t;
                }
                set4(&mut r.base, c);
            }
            if d.gloss.is_some() {
                let ks = d.surface.specular;
                let gloss_t = get4::<L>(gloss_t);
                V3::new(gloss_t[0] * ks.x, gloss_t[1] * ks.y, gloss_t[2] * ks.z).set(&mut r.ks);
            }
            let f = b.group(g);
            let mut n = V3::<L>::get(&r.n);
            if coat_normal(d) {
                n.set(&mut r.nc);
            }
            if let Some(map) = &d.normal_map {
                let normal_t = get4::<L>(normal_t);
                n = match d.layout.tangent_at() {
                    Some(k) => {
                        let v = f.var;
                        let t = V3::new(v[k].get(), v[k + 1].get(), v[k + 2].get());
                        perturb_lanes(n, t, v[k + 3].get(), normal_t, map.scale)
                    }
                    // A mesh without tangents: the frame from the derivatives, per lane.
                    None => texlab::derived_normal_lanes(map, &f, first, &normal_t, n),
                };
            }
            if let Some(bump) = &d.bump {
                n = texlab::bump_lanes(bump, &f, first, cx.s.lod_scale, n);
            }
            n.set(&mut r.n);
            // glTF: ao = 1 + strength (r - 1), on the ambient (indirect) light only.
            if let Some(o) = &d.occlusion {
                r.occlusion.set(F8::ONE + (occlusion_t[0].get::<L>() - F8::ONE) * o.scale);
            }
            if d.emissive_map.is_some() {
                let emissive_t = get4::<L>(emissive_t);
                (V3::new(emissive_t[0], emissive_t[1], emissive_t[2]) * d.emissive)
                    .set(&mut r.emitted);
            }
        }
    }
}

crate::simd::per_kernel! {
    /// The texels of the extensions' slot `arg` (an index into `Slot::LAYERS`): the values
    /// it gives ([`layer_maps::channels`]), or the clear coat's normal map applied to the
    /// coat's normal.
    pub(super) fn layer_sample<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, arg: u32) {
        let d = cx.d;
        let k = arg as usize;
        let (Some(Some(t)), Some(&slot)) = (d.layer_maps.get(k), Slot::LAYERS.get(k)) else {
            return;
        };
        let first = first_derivative(d);
        let lod = cx.s.lod_scale;
        for (g, r) in regs.iter_mut().enumerate() {
            let f = b.group(g);
            let texel = sample_slot::<L>(t, &f, lod, first);
            match layer_maps::channels(slot) {
                Some((from, n, to)) => {
                    for j in 0..n {
                        r.layer[to + j].set(texel[from + j]);
                    }
                }
                None => {
                    let nc = V3::<L>::get(&r.nc);
                    let nc = match d.layout.tangent_at() {
                        Some(k) => {
                            let v = f.var;
                            let tangent = V3::new(v[k].get(), v[k + 1].get(), v[k + 2].get());
                            perturb_lanes(nc, tangent, v[k + 3].get(), texel, t.scale)
                        }
                        None => texlab::derived_normal_lanes(t, &f, first, &texel, nc),
                    };
                    nc.set(&mut r.nc);
                }
            }
        }
    }
}

crate::simd::per_kernel! {
    /// The anisotropy's direction at each pixel, from the mapped normal, the interpolated
    /// tangent and the anisotropy texture's values if any.
    pub(super) fn anisotropy<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        let d = cx.d;
        let (Some(params), Some(k)) = (&d.surface.pbr, d.layout.tangent_at()) else {
            return;
        };
        let mask = d.layer_mask();
        for (g, r) in regs.iter_mut().enumerate() {
            let v = &b.var[g];
            let tangent = V3::<L>::new(v[k].get(), v[k + 1].get(), v[k + 2].get());
            let mut t = LayerTexels::<F8<L>> {
                mask,
                ..LayerTexels::default()
            };
            for (x, lane) in t.values.iter_mut().zip(&r.layer) {
                *x = lane.get();
            }
            if let Some(a) = t.anisotropy(params, V3::get(&r.n), tangent, v[k + 3].get()) {
                a.t.set(&mut r.aniso_t);
                r.aniso_strength.set(a.strength);
            }
        }
    }
}
