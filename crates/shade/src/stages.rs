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

use super::layer_maps::LAYER_VALUES;
use super::shaders::{DrawParams, LitShader, SlotParams, TexView};
use super::texlab;
use crate::raster::{Batch, Colors, GROUPS};
use crate::scene::{AlphaMode, Slot};
use crate::simd::{KernelKind, Lane, Level, F8, V3};

mod shading;
mod texturing;
mod transmission;

use shading::{ambient_stage, light};
use texturing::{anisotropy, layer_sample, maps, sample};
use transmission::transmit;

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

/// The world position of group `g` (varyings 0..3).
#[inline(always)]
fn position<L: Level>(b: &Batch, g: usize) -> V3<L> {
    let v = &b.var[g];
    V3::new(v[0].get(), v[1].get(), v[2].get())
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
