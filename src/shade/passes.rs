//! The passes of a frame: solid instances grouped by the shader they need (flat, Gouraud,
//! Phong / Blinn / textured by varying type, debug views), and wireframe with hidden lines
//! removed.

use glam::{Vec2, Vec3, Vec4};

use super::lighting::LightSet;
use super::render::Inst;
use super::shaders::{
    ColorShader, Debug, DebugShader, DepthOnly, DrawParams, LitShader, LitVarying,
};
use super::vertex;
use super::Shading;
use crate::raster::{self, Cull, Draw, DrawState, LineStyle, Stats, Target};
use crate::scene::Camera;

/// Frame-wide data the passes share.
pub(super) struct Ctx<'a> {
    pub params: &'a [DrawParams],
    pub lights: &'a LightSet,
    pub eye: Vec3,
    pub camera: &'a Camera,
}

/// Draws solid instances grouped by the shader they need.
pub(super) fn draw_group(target: &mut Target, insts: &[&Inst], ctx: &Ctx, stats: &mut Stats) {
    let pick = |f: &dyn Fn(&Inst) -> bool| -> Vec<&Inst> {
        insts.iter().copied().filter(|i| f(i)).collect()
    };
    let flat = pick(&|i| i.mode == Shading::Flat);
    if !flat.is_empty() {
        let data: Vec<_> = flat
            .iter()
            .map(|i| vertex::flat(i, ctx.params, ctx.lights, ctx.eye))
            .collect();
        let draws: Vec<_> = flat
            .iter()
            .zip(&data)
            .map(|(i, (c, v, t))| draw_of(i, c, v, t))
            .collect();
        let shader = ColorShader::<Vec4> {
            draws: ctx.params,
            _v: std::marker::PhantomData,
        };
        raster::draw(target, &draws, &shader, stats);
    }
    let gouraud = pick(&|i| i.mode == Shading::Gouraud);
    if !gouraud.is_empty() {
        let data: Vec<_> = gouraud
            .iter()
            .map(|i| vertex::gouraud(i, ctx.params, ctx.lights, ctx.eye))
            .collect();
        let draws: Vec<_> = gouraud
            .iter()
            .zip(&data)
            .map(|(i, (c, v))| draw_of(i, c, v, &i.tri.triangles))
            .collect();
        let shader = ColorShader::<(Vec4, Vec4)> {
            draws: ctx.params,
            _v: std::marker::PhantomData,
        };
        raster::draw(target, &draws, &shader, stats);
    }
    for (mode, blinn) in [
        (Shading::Phong, false),
        (Shading::Blinn, true),
        (Shading::Textured, true),
    ] {
        let of_mode = pick(&|i| i.mode == mode);
        for tex in [false, true] {
            for col in [false, true] {
                let group: Vec<&Inst> = of_mode
                    .iter()
                    .copied()
                    .filter(|i| i.textured == tex && i.tri.colors.is_some() == col)
                    .collect();
                match (tex, col, blinn) {
                    (false, false, false) => {
                        lit::<(Vec3, Vec3, ()), false>(target, &group, ctx, stats)
                    }
                    (false, false, true) => {
                        lit::<(Vec3, Vec3, ()), true>(target, &group, ctx, stats)
                    }
                    (false, true, false) => {
                        lit::<(Vec3, Vec3, Vec4), false>(target, &group, ctx, stats)
                    }
                    (false, true, true) => {
                        lit::<(Vec3, Vec3, Vec4), true>(target, &group, ctx, stats)
                    }
                    (true, false, _) => lit::<(Vec3, Vec3, Vec2), true>(target, &group, ctx, stats),
                    (true, true, _) => {
                        lit::<(Vec3, Vec3, (Vec2, Vec4)), true>(target, &group, ctx, stats)
                    }
                }
            }
        }
    }
    for (mode, debug) in [
        (Shading::Normals, Debug::Normals),
        (Shading::Depth, Debug::Depth),
        (Shading::Uv, Debug::Uv),
    ] {
        let group = pick(&|i| i.mode == mode);
        if group.is_empty() {
            continue;
        }
        let data: Vec<_> = group.iter().map(|i| vertex::debug(i, debug)).collect();
        let draws: Vec<_> = group
            .iter()
            .zip(&data)
            .map(|(i, (c, v))| draw_of(i, c, v, &i.tri.triangles))
            .collect();
        let shader = DebugShader {
            mode: debug,
            near: ctx.camera.near,
            far: ctx.camera.far,
        };
        raster::draw(target, &draws, &shader, stats);
    }
}

fn draw_of<'a, V>(i: &Inst, clip: &'a [Vec4], var: &'a [V], tris: &'a [[u32; 3]]) -> Draw<'a, V> {
    Draw {
        id: i.id,
        clip,
        varyings: var,
        triangles: tris,
        state: i.state,
    }
}

fn lit<V: LitVarying, const BLINN: bool>(
    target: &mut Target,
    group: &[&Inst],
    ctx: &Ctx,
    stats: &mut Stats,
) {
    if group.is_empty() {
        return;
    }
    let data: Vec<(Vec<Vec4>, Vec<V>)> = group.iter().map(|i| vertex::lit::<V>(i)).collect();
    let draws: Vec<_> = group
        .iter()
        .zip(&data)
        .map(|(i, (c, v))| draw_of(i, c, v, &i.tri.triangles))
        .collect();
    let shader = LitShader::<V, BLINN> {
        draws: ctx.params,
        lights: ctx.lights,
        eye: ctx.eye,
        _v: std::marker::PhantomData,
    };
    raster::draw(target, &draws, &shader, stats);
}

/// Slope-scaled offset of the hidden-line depth pass, in pixels of depth slope: a line pixel
/// is at most half a pixel from its edge, so 1.5 covers it with margin on edges where two
/// steep facets meet.
const WIRE_DEPTH_OFFSET: f32 = 1.5;
/// Relative depth tolerance of wireframe lines against the hidden-line depth (0.01% of the
/// distance), for rounding along nearly edge-on facets.
const WIRE_DEPTH_TOLERANCE: f32 = 1e-4;

/// Wireframe with hidden lines removed: the instances' surfaces go into a scratch copy of the
/// depth buffer only, then their edges are drawn testing against it.
pub(super) fn draw_wireframe(target: &mut Target, insts: &[&Inst], ctx: &Ctx, stats: &mut Stats) {
    if insts.is_empty() {
        return;
    }
    let saved = target.save_depth();
    let clips: Vec<Vec<Vec4>> = insts
        .iter()
        .map(|i| raster::transform_positions(i.mvp, &i.tri.positions))
        .collect();
    let units: Vec<Vec<()>> = insts
        .iter()
        .map(|i| vec![(); i.tri.positions.len()])
        .collect();
    let state = |i: &Inst| DrawState {
        color_write: false,
        cull: Cull::None,
        depth_offset: WIRE_DEPTH_OFFSET,
        ..i.state
    };
    let draws: Vec<Draw<()>> = insts
        .iter()
        .zip(clips.iter().zip(&units))
        .map(|(i, (c, u))| Draw {
            state: state(i),
            ..draw_of(i, c, u, &i.tri.triangles)
        })
        .collect();
    let mut depth_stats = Stats::default();
    raster::draw(target, &draws, &DepthOnly, &mut depth_stats);
    let scratch = target.restore_depth(saved);
    for (i, clip) in insts.iter().zip(&clips) {
        let base = ctx.params[i.id as usize].base;
        let color = (base.truncate() * 0.85 + Vec3::splat(0.15)).extend(1.0);
        let style = LineStyle {
            color,
            depth_test: true,
            depth_tolerance: WIRE_DEPTH_TOLERANCE,
            depth_write: true,
        };
        stats.triangles_in += i.tri.triangles.len() as u64;
        raster::draw_lines(target, Some(&scratch), clip, &i.tri.edges, &style, stats);
    }
}
