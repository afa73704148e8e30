//! The transmission stage (`KHR_materials_transmission`, `KHR_materials_dispersion`): the
//! frame's opaque surfaces seen through the surface along the refracted ray.

use glam::Vec3;

use super::shading::surface;
use super::{position, Cx, Regs};
use crate::brdf::Pbr;
use crate::lighting::PbrParams;
use crate::raster::Batch;
use crate::shaders::Backdrop;
use crate::simd::{Level, F8, V3};

crate::simd::per_kernel! {
    /// The light through a transmissive base (`KHR_materials_transmission`): the frame's
    /// opaque surfaces seen along the refracted ray ([`transmitted`]).
    pub(super) fn transmit<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        let (Some(backdrop), Some(params)) = (cx.s.backdrop, &cx.d.surface.pbr) else {
            return;
        };
        let mask = cx.d.layer_mask();
        for (g, r) in regs.iter_mut().enumerate() {
            let s = surface::<L, true>(cx.d, r, mask);
            let (Some(p), n, v) = (&s.pbr, V3::get(&r.n), V3::get(&r.v)) else {
                continue;
            };
            let light = transmitted::<L>(
                backdrop,
                params,
                p,
                s.kd,
                [n, v, position(b, g)],
                cx.d.model_scale,
                b.mask[g],
            );
            (V3::<L>::get(&r.c) + light).set(&mut r.c);
        }
    }
}

/// The light through a transmissive base at the lanes of `mask` (unit normal `n` and view
/// `v` at world position `p`), as three.js and the Khronos sample viewer draw it in a
/// rasterizer: the ray refracted into the surface (IOR `ior`, or per channel with
/// `KHR_materials_dispersion`'s spread `(ior - 1) 0.025 dispersion`) leaves the volume after
/// `thickness` (times the model's scale; thin-walled: at once), where `backdrop` is read at
/// the level `log2(width) roughness clamp(2 ior - 2, 0, 1)`; Beer's law `c^(distance / d)`
/// absorbs it, and it is `factor (1 - F) baseColor (1 - metallic)` of that, `F` the
/// dielectric's split-sum Fresnel at the view.
#[inline(always)]
fn transmitted<L: Level>(
    backdrop: &Backdrop,
    params: &PbrParams,
    p: &Pbr<F8<L>>,
    kd: V3<L>,
    [n, v, at]: [V3<L>; 3],
    model_scale: Vec3,
    mask: u32,
) -> V3<L> {
    let Some(t) = &p.transmission else {
        return V3::splat(Vec3::ZERO);
    };
    let nv = n.dot(v).max(F8::splat(1e-4));
    let (a, bias, _) = <F8<L> as crate::lighting::Shade>::brdf_lut(nv, p.roughness);
    let f90 = p.f90 * bias;
    let fresnel = p.f0 * a + V3::new(f90, f90, f90);
    let weight = (V3::splat(Vec3::ONE) - fresnel) * kd * ((F8::ONE - p.metallic) * t.factor);
    let img = &backdrop.image;
    let (w, h) = (img.width as f32, img.height as f32);
    let spread = (params.ior - 1.0).max(0.0) * 0.025 * params.dispersion;
    let level =
        F8::splat(libm::log2f(w.max(h)) * (2.0 * params.ior - 2.0).clamp(0.0, 1.0)) * p.roughness;
    let footprint = level.exp2();
    let sampler = crate::texture::Sampler {
        wrap_u: crate::texture::Wrap::ClampToEdge,
        wrap_v: crate::texture::Wrap::ClampToEdge,
        filter: crate::texture::Filter::Trilinear,
    };
    let mut out = [F8::<L>::ZERO; 3];
    // One ray for all three channels, or one per channel with dispersion.
    let rays = if spread > 0.0 { 3 } else { 1 };
    for k in 0..rays {
        let ior = if rays == 1 {
            params.ior
        } else {
            params.ior + spread * (k as f32 - 1.0)
        };
        let dir = refract(-v, n, 1.0 / ior.max(1e-3));
        let travel = V3::new(
            dir.x * model_scale.x,
            dir.y * model_scale.y,
            dir.z * model_scale.z,
        )
        .scale(t.thickness);
        let exit = at + travel;
        let m = backdrop.view_proj;
        let (cx, cy, cw) = (
            clip_row(m, 0, exit),
            clip_row(m, 1, exit),
            clip_row(m, 3, exit),
        );
        let inv = F8::ONE / cw.max(F8::splat(1e-6));
        let half = F8::splat(0.5);
        let (u, vv) = (half + half * cx * inv, half - half * cy * inv);
        let texel = img.sample_grad_lanes(
            u,
            vv,
            footprint * (1.0 / w),
            F8::ZERO,
            F8::ZERO,
            footprint * (1.0 / h),
            mask,
            sampler,
        );
        let distance = travel.dot(travel).sqrt();
        for (c, o) in out.iter_mut().enumerate() {
            if rays == 3 && c != k {
                continue;
            }
            let absorb = if params.attenuation_distance.is_finite() {
                F8::splat(params.attenuation_color[c].max(1e-6))
                    .powf(distance * (1.0 / params.attenuation_distance))
            } else {
                F8::ONE
            };
            *o = texel[c] * absorb;
        }
    }
    V3::new(out[0], out[1], out[2]) * weight
}

/// Row `r` of `m` times the point `p` (a function, not a closure: lane code stays inline).
#[inline(always)]
fn clip_row<L: Level>(m: glam::Mat4, r: usize, p: V3<L>) -> F8<L> {
    F8::splat(m.col(0)[r]) * p.x
        + F8::splat(m.col(1)[r]) * p.y
        + F8::splat(m.col(2)[r]) * p.z
        + F8::splat(m.col(3)[r])
}

/// `refract(i, n, eta)` (GLSL's): the ray `i` bent through the surface of unit normal `n`
/// for the ratio of IORs `eta`; zero where it is totally reflected.
#[inline(always)]
fn refract<L: Level>(i: V3<L>, n: V3<L>, eta: f32) -> V3<L> {
    let ni = n.dot(i);
    let eta = F8::splat(eta);
    let k = F8::ONE - eta * eta * (F8::ONE - ni * ni);
    let r = i.scale(eta) - n.scale(eta * ni + k.max(F8::ZERO).sqrt());
    let ok = k.ge(F8::ZERO);
    V3::new(
        F8::select(ok, r.x, F8::ZERO),
        F8::select(ok, r.y, F8::ZERO),
        F8::select(ok, r.z, F8::ZERO),
    )
}
