//! Ray-traced shadows for Whitted's model (the textbook's §9.6.1), as a hybrid: the frame's
//! rasterizer finds what each pixel sees (a depth pass with the frame's own projection and
//! sub-pixel shift), a shadow ray from that point to each light asks the scene's hierarchy
//! whether anything is in the way, and the answers form one screen-space mask per light,
//! which the shaders read where they would read a shadow map ([`ShadowMap::screen`]). Exact
//! where the shadow map approximates: no resolution, no bias, no acne, no peter-panning.

use glam::{Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::frame::FrameData;
use super::passes::{self, Cx};
use super::pool::Pool;
use super::prepare::PreparedScene;
use super::settings::Settings;
use crate::raster::{Bins, Stats, Target};
use crate::scene::{Camera, LightKind};
use crate::shade::ShadowMap;
use realist_trace::Ray;

/// The depth pass's target and its depth, kept between frames.
#[derive(Debug, Default)]
pub(super) struct ScreenShadows {
    target: Option<Target>,
    depth: Vec<f32>,
}

impl ScreenShadows {
    /// Fills a screen mask for every source of `fd.lights` that casts shadows (in Whitted's
    /// model, every one that can), seen through `jvp` (the pass's jittered projection) at
    /// `w` x `h`. Returns false if stopped.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        scene: &PreparedScene,
        settings: &Settings,
        fd: &mut FrameData,
        camera: &Camera,
        jvp: Mat4,
        (w, h): (u32, u32),
        bins: &mut Bins,
        pool: &mut Pool,
        stats: &mut Stats,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        let target = self
            .target
            .get_or_insert_with(|| Target::new(w, h, Vec4::ZERO));
        target.set_samples(1, Vec4::ZERO);
        target.reshape(w, h, Vec4::ZERO);
        target.clear(Vec4::ZERO);
        let mut cx = Cx {
            scene,
            camera,
            eye: camera.eye,
            jitter: Mat4::IDENTITY,
            lod_scale: 1.0,
            target,
            bins,
            pool,
            stats,
            stop,
            vertex_nanos: 0,
            light: Some(jvp),
            sort: false,
            sections: &[],
        };
        if !passes::shadow_depth(&mut cx, fd, &[]) {
            return false;
        }
        let n = w as usize * h as usize;
        self.depth.clear();
        self.depth.resize(n, 0.0);
        target.write_depth(&mut self.depth);
        let rays = scene.rays(settings);
        let inv = jvp.inverse();
        let (_, radius) = scene.bounding_sphere();
        let depth = &self.depth;
        let mut used = 0;
        for i in 0..fd.lights.sources.len() {
            let src = &fd.lights.sources[i];
            if !src.casts {
                continue;
            }
            let (kind, position, axis) = (src.kind, src.position, src.axis);
            if used == fd.lights.shadows.len() {
                fd.lights.shadows.push(ShadowMap::default());
            }
            let map = &mut fd.lights.shadows[used];
            map.screen = Some((w, h));
            map.view_proj = jvp;
            map.depth.clear();
            map.depth.resize(n, 1.0);
            map.depth
                .par_chunks_mut(w as usize)
                .enumerate()
                .for_each(|(y, row)| {
                    for (x, vis) in row.iter_mut().enumerate() {
                        let z = depth[y * w as usize + x];
                        if z <= 0.0 {
                            continue;
                        }
                        let ndc = Vec2::new(
                            (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                            1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
                        );
                        let p = inv.project_point3(ndc.extend(z));
                        let near = inv.project_point3(ndc.extend(1.0));
                        let Some(from) = lifted(p, near, radius) else {
                            continue;
                        };
                        let ray = match kind {
                            LightKind::Directional => Ray::new(from, -axis, 0.0, f32::INFINITY),
                            _ => Ray::new(from, position - from, 0.0, 1.0),
                        };
                        if rays.occluded(&ray) {
                            *vis = 0.0;
                        }
                    }
                });
            fd.lights.sources[i].shadow = Some(used as u32);
            used += 1;
        }
        true
    }
}

/// The point `p` seen from `near` (its camera ray's start on the near plane) moved back
/// towards the camera by a little more than the depth buffer's rounding, so that its
/// shadow ray starts in front of the surface it lies on; `None` if not finite.
fn lifted(p: Vec3, near: Vec3, radius: f32) -> Option<Vec3> {
    let d = p - near;
    let len = d.length();
    let out = p - d / len.max(1e-30) * (2e-5 * (len + radius));
    out.is_finite().then_some(out)
}
