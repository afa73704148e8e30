//! The passes of one frame: solid instances grouped by the shader they need (flat, Gouraud,
//! Phong / Blinn / textured by varying type, debug views), wireframe with hidden lines
//! removed, the wireframe overlay, the meshes' points and lines, blended instances back to
//! front, or the overdraw count. Instances without triangles (only points or lines) are
//! left out of the triangle passes, whose per-triangle and per-pixel work is unchanged.
//!
//! Every group appends its instances' clip positions and float varyings to buffers kept in
//! the renderer's [`Pool`] and hands the rasterizer a [`DrawList`](crate::raster::DrawList)
//! that builds each draw from plain indices, so a frame allocates nothing once the buffers
//! have grown.

use glam::{Mat4, Vec3, Vec4};

use super::frame::{FrameData, FrameInst};
use super::pool::Pool;
use super::prepare::PreparedScene;
use super::vertex::{self, Lit};
use crate::raster::{self, Bins, Cull, DepthCopy, DrawState, LineStyle, Stats, Target};
use crate::scene::Camera;
use crate::shade::mode::Pass;
use crate::shade::{
    ColorShader, Constant, CountShader, Debug, DebugShader, DepthOnly, DrawParams, LitShader,
};

mod groups;
mod strokes;

use groups::{group, group_with, Geometry};
use strokes::{strokes, StrokeScratch};

/// Everything a pass reads and writes.
pub(super) struct Cx<'a> {
    pub scene: &'a PreparedScene,
    pub camera: &'a Camera,
    /// Camera position for lighting ([`Camera::shading_eye`]).
    pub eye: Vec3,
    /// Sub-pixel shift of this supersampling pass, applied after the projection.
    pub jitter: Mat4,
    /// UV-derivative scale for the textures' level of detail (1 / samples per axis).
    pub lod_scale: f32,
    pub target: &'a mut Target,
    pub bins: &'a mut Bins,
    pub pool: &'a mut Pool,
    pub stats: &'a mut Stats,
    pub stop: &'a (dyn Fn() -> bool + Sync),
    /// Nanoseconds spent in the vertex stage.
    pub vertex_nanos: u64,
    /// World -> clip of a shadow map being rendered (replaces each instance's `mvp`).
    pub light: Option<Mat4>,
    /// Draw each instance's triangles back to front (blended instances, whose triangles
    /// may overlap each other).
    pub sort: bool,
    /// The section planes in this pass's clip space (empty: nothing is cut; always empty
    /// for shadow maps).
    pub sections: &'a [Vec4],
}

/// Draws a whole frame; returns false if stopped.
pub(super) fn frame(cx: &mut Cx, fd: &mut FrameData, overdraw: bool, overlay: bool) -> bool {
    if overdraw {
        let (scene, all) = (cx.scene, &|_: usize, _: &FrameInst| true);
        let vertex = |fi: &FrameInst, out: &mut Vec<f32>| vertex::unit(scene, fi, out);
        return group(cx, fd, all, Geometry::Indexed, vertex, &CountShader);
    }
    let fdr = &*fd;
    // The transmissive surfaces wait for the opaque ones they see through.
    if !solid(cx, fdr, &|_, fi| {
        !fi.blend && fi.mode.mode().pass != Pass::Edges && fi.tris && !transmissive(fdr, fi)
    }) {
        return false;
    }
    if !caps(cx, fdr) {
        return false;
    }
    let wire = |_: usize, fi: &FrameInst| !fi.blend && fi.mode.mode().pass == Pass::Edges;
    let mut depth = std::mem::take(&mut fd.depth);
    let mut done = wireframe(cx, fd, &wire, false, &mut depth);
    fd.depth = depth;
    if done {
        done = strokes(cx, fd);
    }
    if done && fd.insts.iter().any(|fi| transmissive(fd, fi)) {
        fd.backdrop = backdrop(cx, fd);
        let fdr = &*fd;
        done = solid(cx, fdr, &|_, fi| transmissive(fdr, fi));
    }
    // The wireframe over the shaded surfaces, the transmissive ones included.
    if done && overlay {
        let shaded = |_: usize, fi: &FrameInst| !fi.blend && fi.mode.mode().pass != Pass::Edges;
        let mut depth = std::mem::take(&mut fd.depth);
        done = wireframe(cx, fd, &shaded, true, &mut depth);
        fd.depth = depth;
    }
    let fdr = &*fd;
    cx.sort = true;
    for &k in &fdr.order {
        if !done {
            break;
        }
        done = solid(cx, fdr, &|j, _| j == k as usize);
    }
    cx.sort = false;
    done
}

/// Whether `fi` is drawn in the transmissive pass (`DrawParams::transmits`), after the
/// opaque surfaces it sees through.
fn transmissive(fd: &FrameData, fi: &FrameInst) -> bool {
    !fi.blend && fi.tris && fd.params[fi.param as usize].transmits()
}

/// What the frame's transmissive surfaces see through: the target's colour so far (the
/// opaque surfaces, the background) in linear light, its mip chain built at once, with
/// this pass's world -> clip.
fn backdrop(cx: &mut Cx, fd: &FrameData) -> Option<crate::shade::Backdrop> {
    let fb = cx.target.resolve();
    let texels = fb.color.iter().map(|c| c.to_array()).collect();
    let image = crate::texture::Texture::from_texels(
        "backdrop",
        fb.width,
        fb.height,
        crate::texture::Texels::Float(texels),
    )
    .ok()?;
    image.prepare_mips();
    Some(crate::shade::Backdrop {
        image: std::sync::Arc::new(image),
        view_proj: cx.jitter * fd.view_proj,
    })
}

/// Depth only, at the pixel centres (no jitter), of the opaque surfaces: after a
/// supersampled frame, so its depth buffer (picking, probing) is the pixel centres' and not
/// the last pass's shifted samples. Returns false if stopped.
pub(super) fn centre_depth(cx: &mut Cx, fd: &FrameData) -> bool {
    cx.target.clear_depth();
    let scene = cx.scene;
    let saved = *cx.stats;
    let opaque = |_: usize, fi: &FrameInst| !fi.blend && fi.mode.mode().pass != Pass::Edges;
    let (done, g) = group_with(
        cx,
        &fd.insts,
        &opaque,
        Geometry::Indexed,
        &mut |fi, out| vertex::unit(scene, fi, out),
        &DepthOnly,
        |s| DrawState {
            color_write: false,
            ..s
        },
    );
    // Not part of the frame's counters: the passes already counted this geometry.
    *cx.stats = saved;
    cx.pool.put(g);
    done
}

/// The depth of every shadow caster seen from a light (`cx.light`): the frame's opaque,
/// non-wireframe instances and `culled` (casters outside the view frustum), both faces, into
/// a depth-only target. Not counted in the frame's counters. Returns false if stopped.
pub(super) fn shadow_depth(cx: &mut Cx, fd: &FrameData, culled: &[FrameInst]) -> bool {
    let scene = cx.scene;
    let saved = *cx.stats;
    let caster = |_: usize, fi: &FrameInst| !fi.blend && fi.mode.mode().pass != Pass::Edges;
    let state = |s: DrawState| DrawState {
        color_write: false,
        cull: Cull::None,
        depth_test: raster::DepthTest::Greater,
        depth_write: true,
        blend: raster::Blend::Replace,
        ..s
    };
    let mut done = true;
    for insts in [&fd.insts[..], culled] {
        if !done {
            break;
        }
        let (d, g) = group_with(
            cx,
            insts,
            &caster,
            Geometry::Indexed,
            &mut |fi, out| vertex::unit(scene, fi, out),
            &DepthOnly,
            state,
        );
        cx.pool.put(g);
        done = d;
    }
    *cx.stats = saved;
    done
}

/// What the lit vertex functions share, for the pass `cx` and the frame `fd`.
pub(super) fn lit_of<'a>(cx: &Cx<'a>, fd: &'a FrameData) -> Lit<'a> {
    Lit {
        scene: cx.scene,
        params: &fd.params,
        lights: &fd.lights,
        active: &fd.active,
        eye: cx.eye,
        forward: cx.camera.forward(),
        fog: fd.fog,
        kernel: cx.bins.kernel,
    }
}

/// Solid instances grouped by the shader they need.
fn solid(cx: &mut Cx, fd: &FrameData, pick: &dyn Fn(usize, &FrameInst) -> bool) -> bool {
    let scene = cx.scene;
    let lit = lit_of(cx, fd);
    let params: &[DrawParams] = &fd.params;
    let of =
        |pass: Pass| move |k: usize, fi: &FrameInst| fi.mode.mode().pass == pass && pick(k, fi);

    let flat_pick = of(Pass::Facets);
    if fd.insts.iter().enumerate().any(|(k, fi)| flat_pick(k, fi)) {
        let mut facets = cx.pool.take::<FacetScratch>();
        let shader = ColorShader {
            draws: params,
            kernel: cx.bins.kernel,
        };
        let vertex = |fi: &FrameInst, out: &mut Vec<f32>| lit.flat(fi, &mut facets.0, out);
        let done = group(cx, fd, &flat_pick, Geometry::Flat, vertex, &shader);
        cx.pool.put(facets);
        if !done {
            return false;
        }
    }
    let shader = ColorShader {
        draws: params,
        kernel: cx.bins.kernel,
    };
    // Double-sided materials (no culling) get both sides' colours (`Lit::gouraud`).
    let (done, g) = group_with(
        cx,
        &fd.insts,
        &of(Pass::Vertices),
        Geometry::Indexed,
        &mut |fi, out| lit.gouraud(fi, out),
        &shader,
        |s| DrawState {
            facing_varyings: s.cull == Cull::None,
            ..s
        },
    );
    cx.pool.put(g);
    if !done {
        return false;
    }
    // The per-pixel modes in one group: each draw carries its own varying layout and
    // highlight (`DrawParams::layout`, `blinn`).
    let per_pixel = |k: usize, fi: &FrameInst| fi.mode.per_pixel() && pick(k, fi);
    if !lit_group(cx, fd, &per_pixel) {
        return false;
    }
    for debug in [Debug::Normals, Debug::Depth, Debug::Uv] {
        let shader = DebugShader {
            mode: debug,
            near: cx.camera.near,
            far: cx.camera.far,
            kernel: cx.bins.kernel,
        };
        let vertex = |fi: &FrameInst, out: &mut Vec<f32>| vertex::debug(scene, fi, debug, out);
        if !group(
            cx,
            fd,
            &of(Pass::Debug(debug)),
            Geometry::Indexed,
            vertex,
            &shader,
        ) {
            return false;
        }
    }
    true
}

/// The caps of the section planes: the back faces of the cut opaque instances, drawn in
/// the cap colour where they are at least as near as what is drawn (so they replace the
/// lit back faces of double-sided materials too). Seen only through a cut, or on an open
/// surface seen from behind. Returns false if stopped.
fn caps(cx: &mut Cx, fd: &FrameData) -> bool {
    let Some(color) = fd.cap.filter(|_| !cx.sections.is_empty()) else {
        return true;
    };
    let scene = cx.scene;
    let cut = |_: usize, fi: &FrameInst| {
        !fi.blend
            && fi.tris
            && fi.mode.mode().pass != Pass::Edges
            && !scene.instances[fi.inst as usize].ground
    };
    let (done, g) = group_with(
        cx,
        &fd.insts,
        &cut,
        Geometry::Indexed,
        &mut |fi, out| vertex::unit(scene, fi, out),
        &Constant(color),
        |s| DrawState {
            cull: Cull::Front,
            depth_test: raster::DepthTest::GreaterEqual,
            depth_write: true,
            blend: raster::Blend::Replace,
            color_write: true,
            depth_offset: 0.0,
            facing_varyings: false,
            ..s
        },
    );
    cx.pool.put(g);
    done
}

/// Flat shading's per-facet colours, kept in the pool between frames.
#[derive(Default)]
struct FacetScratch(Vec<Vec4>);

fn lit_group(cx: &mut Cx, fd: &FrameData, pick: &dyn Fn(usize, &FrameInst) -> bool) -> bool {
    let shader = LitShader {
        draws: &fd.params,
        programs: &fd.programs,
        lights: &fd.lights,
        active: &fd.active,
        eye: cx.eye,
        forward: cx.camera.forward(),
        fog: fd.fog,
        lod_scale: cx.lod_scale,
        backdrop: fd.backdrop.as_ref(),
    };
    let scene = cx.scene;
    group(
        cx,
        fd,
        pick,
        Geometry::Indexed,
        |fi, out| vertex::lit(scene, fi, &fd.params, out),
        &shader,
    )
}

/// Slope-scaled offset of the hidden-line depth pass, in pixels of depth slope: a line pixel
/// is at most half a pixel from its edge, so 1.5 covers it with margin on edges where two
/// steep facets meet.
const WIRE_DEPTH_OFFSET: f32 = 1.5;
/// Relative depth tolerance of wireframe lines against the hidden-line depth (0.01% of the
/// distance), for rounding along nearly edge-on facets.
const WIRE_DEPTH_TOLERANCE: f32 = 1e-4;
/// Line colour of the wireframe overlay drawn over shaded surfaces (linear RGB).
const OVERLAY_LINE: Vec3 = Vec3::splat(0.004);

fn wire_depth_state(s: DrawState) -> DrawState {
    DrawState {
        color_write: false,
        cull: Cull::None,
        depth_offset: WIRE_DEPTH_OFFSET,
        ..s
    }
}

/// Wireframe with hidden lines removed: the instances' surfaces go into a scratch copy of the
/// depth buffer only, then their edges are drawn testing against it. As an `overlay` the
/// lines are dark (drawn over the shaded surfaces); otherwise they take the material colour.
fn wireframe(
    cx: &mut Cx,
    fd: &FrameData,
    pick: &dyn Fn(usize, &FrameInst) -> bool,
    overlay: bool,
    depth: &mut DepthCopy,
) -> bool {
    if !fd.insts.iter().enumerate().any(|(k, fi)| pick(k, fi)) {
        return true;
    }
    cx.target.save_depth(depth);
    if overlay {
        // The overlay's hidden-line depth holds only the shaded surfaces, pushed back by the
        // slope-scaled offset (their exact depth would hide half of each edge's pixels).
        cx.target.clear_depth();
    }
    let scene = cx.scene;
    // The hidden-line pass is not part of the frame's counters.
    let saved = *cx.stats;
    let (done, g) = group_with(
        cx,
        &fd.insts,
        pick,
        Geometry::Indexed,
        &mut |fi, out| vertex::unit(scene, fi, out),
        &DepthOnly,
        wire_depth_state,
    );
    cx.pool.put(g);
    *cx.stats = saved;
    cx.target.restore_depth(depth);
    let mut cut_scratch = cx.pool.take::<StrokeScratch>();
    if done {
        let picked = fd.insts.iter().enumerate().filter(|(k, fi)| pick(*k, fi));
        for (_, fi) in picked {
            let tri = &scene.meshes[fi.mesh as usize].tri;
            let color = if overlay {
                OVERLAY_LINE
            } else {
                let base = fd.params[fi.param as usize].base;
                base.truncate() * 0.85 + Vec3::splat(0.15)
            };
            let style = LineStyle {
                color: color.extend(1.0),
                depth_test: true,
                depth_tolerance: WIRE_DEPTH_TOLERANCE,
                depth_write: true,
            };
            if !overlay {
                cx.stats.triangles_in += tri.triangles.len() as u64;
            }
            // The same clip positions as the depth pass's (same matrix, same positions).
            let StrokeScratch { clip, cut, .. } = &mut *cut_scratch;
            clip.clear();
            raster::transform_positions_into(cx.jitter * fi.mvp, &tri.positions, clip);
            let edges = scene.wire(fi.mesh as usize);
            if cx.sections.is_empty() || scene.instances[fi.inst as usize].ground {
                raster::draw_lines(cx.target, Some(depth), clip, edges, &style, cx.stats);
            } else {
                cut.cut(cx.sections, clip, None, edges, &[]);
                raster::draw_lines(cx.target, Some(depth), clip, &cut.lines, &style, cx.stats);
            }
        }
    }
    cx.pool.put(cut_scratch);
    done
}
