//! The lit shader as a pipeline of small stages, as Skia's raster pipeline and tiny-skia's
//! pipeline run: per draw, the renderer builds the list of stages that draw needs
//! ([`Program::build`]) and nothing else; the shader runs the list over each batch of 64
//! pixels the fill hands it, one stage at a time over all of them, with the working values
//! ([`Regs`]) in structure-of-arrays form in L1 between stages.
//!
//! | stage | when | what |
//! |---|---|---|
//! | `begin` | always | base colour (times the vertex colour), `K_s`, the unit normal |
//! | `sample` | one per slot the draw reads | the slot's texels (image or procedural) |
//! | `maps` | a draw with slots | base colour, gloss, normal map, bump, occlusion, emission, metal-roughness (and, for a clear coat over a mapped base, the coat's unmapped normal) |
//! | `debug` | a texture debug view | the view's colour (last stage) |
//! | `unlit` | `KHR_materials_unlit` | the base colour (last stage) |
//! | `ambient` | lit | facing, view vector, the ambient or image-based term, emission; the layers' values at the view (`brdf::Layers`: the coat's Fresnel, the sheen's albedo) |
//! | `light` | one per light that reaches the object | its share (shadow included), under the clear coat and sheen if any |
//! | `fog` | fog on | linear fog |
//! | `finish` | lit | alpha mode: the colour, and the lanes an alpha test keeps |
//!
//! Each stage is one function per kernel ([`per_kernel!`](crate::simd::per_kernel)), called
//! through a pointer once per batch: no function holds the whole shader, so none is large
//! and the compiler keeps each stage's values in registers. The arithmetic of every stage is
//! the lighting model written once over [`Num`](crate::simd::Num) ([`super::lighting`],
//! [`super::brdf`], [`super::maps`]), which the vertex stage, the pixel probe and the f64
//! references call in `f32` and `f64`.

use glam::Vec3;

use super::layer_maps::{self, LayerTexels, LAYER_VALUES};
use super::lighting::PbrParams;
use super::lighting::{ambient_at, contribution, emission_seen, view_vector, SurfaceAt};
use super::maps::perturb_lanes;
use super::shaders::{Backdrop, DrawParams, LitShader, SlotParams, TexView};
use super::texlab;
use crate::brdf::Pbr;
use crate::raster::{Batch, Colors, Fragments, GROUPS};
use crate::scene::{AlphaMode, Slot, TextureSource};
use crate::simd::{KernelKind, Lane, Level, F8, V3};

/// The slots a lit draw can sample, in the order of [`Regs::texel`]: base colour, gloss,
/// normal, occlusion, emissive, metallic-roughness.
pub const SLOTS: usize = 6;

/// The working values of one group of eight lanes, kept in memory (L1) between stages: each
/// stage loads the ones it reads and stores the ones it writes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Regs {
    // What every lit draw reads first, together (a few cache lines per group); the maps',
    // the layers' and the extensions' values after.
    /// Base (diffuse) colour and alpha.
    pub base: [Lane; 4],
    /// Specular colour (the gloss map multiplies it).
    pub ks: [Lane; 3],
    /// Unit shading normal: after the maps; turned to the side seen by `ambient`.
    pub n: [Lane; 3],
    /// Unit view vector (zero without a specular term).
    pub v: [Lane; 3],
    /// The colour so far (linear RGB).
    pub c: [Lane; 3],
    /// Emitted light.
    pub emitted: [Lane; 3],
    /// Ambient occlusion, where the draw has an occlusion map.
    pub occlusion: Lane,
    /// `E_ss` of a `pbr` surface for the punctual lights ([`crate::brdf::Pbr::ess`]).
    pub ess: Lane,
    /// The metallic-roughness texture's (roughness, metallic) factors, where the draw has one.
    pub rough: Lane,
    pub metal: Lane,
    /// The layers' values at the view ([`crate::brdf::Layers::view`]), where the draw has
    /// a clear coat or a sheen.
    pub coat_keep: Lane,
    pub sheen_ev: Lane,
    /// The coat's normal (the interpolated one, before the maps), where the draw has a
    /// clear coat over a normal- or bump-mapped base ([`coat_normal`]).
    pub nc: [Lane; 3],
    /// The thin film's Fresnel at the view over the dielectric and the metal
    /// ([`crate::brdf::Iridescence::view`]), where the draw has iridescence.
    pub film_dielectric: [Lane; 3],
    pub film_metal: [Lane; 3],
    /// The anisotropy's direction (world, unit) and strength
    /// ([`crate::brdf::Anisotropy::at`]), where the draw is anisotropic.
    pub aniso_t: [Lane; 3],
    pub aniso_strength: Lane,
    /// The texels of the draw's slots (base colour, gloss, normal, occlusion, emissive,
    /// metallic-roughness).
    pub texel: [[Lane; 4]; SLOTS],
    /// What the `KHR_materials_*` extensions' textures read ([`LayerTexels::values`]),
    /// where the draw has them.
    pub layer: [Lane; LAYER_VALUES],
}

/// What every stage of a batch reads: the shader (lights, eye, fog, level-of-detail scale)
/// and the batch's draw.
pub struct Cx<'a> {
    pub s: &'a LitShader<'a>,
    pub d: &'a DrawParams,
}

/// A stage: one kernel's copy of it, run over the first `b.len` groups of the batch with
/// its registers, with its argument (a slot or a light).
pub type StageFn = fn(&mut Batch, &mut [Regs], &Cx<'_>, u32);

/// One step of a program.
#[derive(Clone, Copy, Debug)]
pub struct Step {
    pub run: StageFn,
    pub arg: u32,
}

/// The stages one draw runs, in order.
#[derive(Clone, Debug, Default)]
pub struct Program {
    pub steps: Vec<Step>,
}

impl Program {
    /// The stages of draw `d` (its lights: `active`, indices into the frame's sources; fog:
    /// whether the frame has fog) for `kernel`, replacing what the program held (its memory
    /// is kept: a renderer rebuilds its programs every frame without allocating).
    pub fn build(&mut self, d: &DrawParams, active: &[u32], fog: bool, kernel: KernelKind) {
        let steps = &mut self.steps;
        steps.clear();
        let mut push = |run: StageFn, arg: u32| steps.push(Step { run, arg });
        push(begin::pick(kernel), 0);
        if d.mapped {
            for (k, slot) in slots(d).iter().enumerate() {
                if slot.is_some() {
                    push(sample::pick(kernel), k as u32);
                }
            }
            push(maps::pick(kernel), 0);
            for (k, slot) in d.layer_maps.iter().enumerate() {
                if slot.is_some() {
                    push(layer_sample::pick(kernel), k as u32);
                }
            }
        }
        if anisotropic(d) && d.view == TexView::Lit && !d.unlit {
            push(anisotropy::pick(kernel), 0);
        }
        if d.view != TexView::Lit {
            push(debug::pick(kernel), 0);
            return;
        }
        if d.unlit {
            push(unlit::pick(kernel), 0);
            return;
        }
        push(ambient_stage::pick(kernel), 0);
        for &i in active {
            push(light::pick(kernel), i);
        }
        if d.transmits() {
            push(transmit::pick(kernel), 0);
        }
        if fog {
            push(fog_stage::pick(kernel), 0);
        }
        push(finish::pick(kernel), 0);
    }

    /// Runs the program over the first `b.len` groups of `b`.
    #[inline]
    pub fn run(&self, b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>) {
        let regs = &mut regs[..b.len.min(GROUPS)];
        for s in &self.steps {
            (s.run)(b, regs, cx, s.arg);
        }
    }
}

/// The slots of draw `d` in the order of [`Regs::texel`].
#[inline(always)]
fn slots(d: &DrawParams) -> [&Option<SlotParams>; SLOTS] {
    [
        &d.base_map,
        &d.gloss,
        &d.normal_map,
        &d.occlusion,
        &d.emissive_map,
        &d.metal_rough,
    ]
}

/// The first varying with derivatives of draw `d` (`usize::MAX` without).
#[inline(always)]
fn first_derivative(d: &DrawParams) -> usize {
    d.layout
        .derivatives()
        .map_or(usize::MAX, |(first, _)| first)
}

/// Four stored lanes as values.
#[inline(always)]
fn get4<L: Level>(v: &[Lane; 4]) -> [F8<L>; 4] {
    [v[0].get(), v[1].get(), v[2].get(), v[3].get()]
}

/// Four values stored.
#[inline(always)]
fn set4<L: Level>(v: &mut [Lane; 4], x: [F8<L>; 4]) {
    for (d, s) in v.iter_mut().zip(x) {
        d.set(s);
    }
}

crate::simd::per_kernel! {
    /// Base colour (times the vertex colour), `K_s`, the emission and the unit normal.
    fn begin<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        let d = cx.d;
        for (g, r) in regs.iter_mut().enumerate() {
            let v = &b.var[g];
            let mut c = d.base.to_array().map(F8::<L>::splat);
            if let Some(k) = d.layout.color_at() {
                for (j, c) in c.iter_mut().enumerate() {
                    *c *= v[k + j].get();
                }
            }
            set4(&mut r.base, c);
            V3::<L>::splat(d.surface.specular).set(&mut r.ks);
            V3::<L>::new(v[3].get(), v[4].get(), v[5].get())
                .normalize_or_zero()
                .set(&mut r.n);
            V3::<L>::splat(d.emissive).set(&mut r.emitted);
        }
    }
}

crate::simd::per_kernel! {
    /// The texels of slot `arg` (filtered by its sampler; a procedural texture evaluated
    /// lane by lane, outside the kernel: `texlab`).
    fn sample<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, arg: u32) {
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
    fn maps<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
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
    fn layer_sample<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, arg: u32) {
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
    fn anisotropy<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
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

/// Whether draw `d` is anisotropic (a `pbr` material with `KHR_materials_anisotropy`, on a
/// mesh with tangents).
#[inline(always)]
fn anisotropic(d: &DrawParams) -> bool {
    d.surface.pbr.is_some_and(|p| p.anisotropy > 0.0) && d.layout.tangent_at().is_some()
}

crate::simd::per_kernel! {
    /// A texture debug view (the last stage).
    fn debug<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        for (g, r) in regs.iter_mut().enumerate() {
            let n = V3::<L>::get(&r.n);
            let n = if b.front { n } else { -n };
            b.out[g] = texlab::debug_lanes(cx.d, &b.group(g), cx.s.lod_scale, n);
        }
    }
}

crate::simd::per_kernel! {
    /// `KHR_materials_unlit`: the base colour (the last stage).
    fn unlit<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        for (g, r) in regs.iter_mut().enumerate() {
            let [red, green, blue, a] = get4::<L>(&r.base);
            let (a, keep) = alpha_lanes(cx.d.alpha, a, b.mask[g]);
            b.out[g] = Colors::of(red, green, blue, a);
            b.mask[g] = keep;
        }
    }
}

/// Whether draw `d`'s clear coat has a normal of its own: the base's is normal- or
/// bump-mapped, which the coat does not follow, or the coat has a normal map.
#[inline(always)]
fn coat_normal(d: &DrawParams) -> bool {
    d.surface.pbr.is_some_and(|p| p.clearcoat > 0.0)
        && (d.normal_map.is_some()
            || d.bump.is_some()
            || d.layer_map(Slot::ClearcoatNormal).is_some())
}

/// The surface of draw `d` at the lanes of `r` (after the maps); `PBR` false for a draw
/// of the Phong modes (its surface has no `pbr` part: said statically, the compiler leaves
/// the BRDF's code out of the caller).
#[inline(always)]
fn surface<L: Level, const PBR: bool>(d: &DrawParams, r: &Regs, mask: u8) -> SurfaceAt<F8<L>> {
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

/// The world position of group `g` (varyings 0..3).
#[inline(always)]
fn position<L: Level>(b: &Batch, g: usize) -> V3<L> {
    let v = &b.var[g];
    V3::new(v[0].get(), v[1].get(), v[2].get())
}

crate::simd::per_kernel! {
    /// The normal turned to the side seen, the view vector, and the ambient term (Phong's,
    /// or `pbr`'s image-based light) plus the emission.
    fn ambient_stage<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
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
    fn light<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, arg: u32) {
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

crate::simd::per_kernel! {
    /// The light through a transmissive base (`KHR_materials_transmission`): the frame's
    /// opaque surfaces seen along the refracted ray ([`transmitted`]).
    fn transmit<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
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
    let level = F8::splat(w.max(h).log2() * (2.0 * params.ior - 2.0).clamp(0.0, 1.0)) * p.roughness;
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

crate::simd::per_kernel! {
    /// Linear fog.
    fn fog_stage<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        let Some(fog) = &cx.s.fog else {
            return;
        };
        let (eye, forward) = (V3::<L>::splat(cx.s.eye), V3::<L>::splat(cx.s.forward));
        for (g, r) in regs.iter_mut().enumerate() {
            let c = fog.apply::<F8<L>>(V3::get(&r.c), position(b, g), eye, forward);
            c.set(&mut r.c);
        }
    }
}

crate::simd::per_kernel! {
    /// The colour and the alpha mode: the lanes an alpha test keeps.
    fn finish<L>(b: &mut Batch, regs: &mut [Regs], cx: &Cx<'_>, _arg: u32) {
        for (g, r) in regs.iter_mut().enumerate() {
            let (a, keep) = alpha_lanes(cx.d.alpha, r.base[3].get::<L>(), b.mask[g]);
            b.out[g] = Colors {
                r: r.c[0],
                g: r.c[1],
                b: r.c[2],
                a: a.into(),
            };
            b.mask[g] = keep;
        }
    }
}

/// Applies alpha mode `mode` to lanes `mask` with alpha `a`: the alpha to store and the
/// lanes kept (`Mask` discards those below the cutoff).
#[inline(always)]
pub(crate) fn alpha_lanes<L: Level>(mode: AlphaMode, a: F8<L>, mask: u32) -> (F8<L>, u32) {
    match mode {
        AlphaMode::Opaque => (F8::ONE, mask),
        AlphaMode::Mask(cutoff) => (F8::ONE, mask & a.ge(F8::splat(cutoff)).bits()),
        AlphaMode::Blend => (a, mask),
    }
}
