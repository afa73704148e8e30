//! Shadow maps for the frame's lights that cast shadows: each is rendered by the same
//! rasterizer as the frame (depth only, both faces, one sample per texel) from the light —
//! a parallel projection over the scene's bounding sphere for a directional light (every
//! shadow a caster throws lies inside the caster's extent across the light, so the map
//! covers all of them), a perspective one over the cone or pyramid for a spot — and its
//! depth converted to distance along the light's axis for the shaders'
//! [`ShadowMap::lookup`]. Maps and targets are kept between frames; a frame whose lights
//! cast no shadows does none of this.

use glam::{Mat4, Vec4};

use super::frame::FrameData;
use super::passes::{self, Cx};
use super::pool::Pool;
use super::prepare::PreparedScene;
use crate::raster::{Bins, Stats, Target};
use crate::shade::{ShadowMap, ShadowSettings, MAX_SHADOW_SIZE};

/// The shadow maps' render targets, kept between frames.
#[derive(Debug, Default)]
pub(super) struct ShadowTargets {
    targets: Vec<Target>,
}

impl ShadowTargets {
    /// Renders a shadow map for every source of `fd.lights` that casts shadows, pointing the
    /// source at it. Returns false if stopped.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        scene: &PreparedScene,
        fd: &mut FrameData,
        settings: &ShadowSettings,
        bins: &mut Bins,
        pool: &mut Pool,
        stats: &mut Stats,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        let size = settings.size.clamp(16, MAX_SHADOW_SIZE);
        let (center, radius) = scene.bounding_sphere();
        let mut used = 0;
        for i in 0..fd.lights.sources.len() {
            let src = &fd.lights.sources[i];
            if !src.casts {
                continue;
            }
            let eye = (src.kind != crate::scene::LightKind::Directional).then_some(src.position);
            let (cam, texel) = ShadowMap::camera(eye, src.axis, src.spread, center, radius, size);
            let vp: Mat4 = cam.projection(1.0) * cam.view();
            if used == self.targets.len() {
                self.targets.push(Target::new(size, size, Vec4::ZERO));
            }
            let target = &mut self.targets[used];
            target.set_samples(1, Vec4::ZERO);
            target.reshape(size, size, Vec4::ZERO);
            target.clear(Vec4::ZERO);
            let mut cx = Cx {
                scene,
                camera: &cam,
                eye: cam.eye,
                jitter: Mat4::IDENTITY,
                lod_scale: 1.0,
                target,
                bins,
                pool,
                stats,
                stop,
                vertex_nanos: 0,
                light: Some(vp),
                sort: false,
                sections: &[],
            };
            let casters = std::mem::take(&mut fd.casters);
            let done = passes::shadow_depth(&mut cx, fd, &casters);
            fd.casters = casters;
            if !done {
                return false;
            }
            if used == fd.lights.shadows.len() {
                fd.lights.shadows.push(ShadowMap::default());
            }
            let map = &mut fd.lights.shadows[used];
            map.depth.clear();
            map.depth.resize((size * size) as usize, 0.0);
            self.targets[used].write_depth(&mut map.depth);
            ShadowMap::depth_from_raster(&cam, &mut map.depth);
            map.view_proj = vp;
            map.origin = cam.eye;
            map.axis = src.axis;
            map.ortho = eye.is_none();
            map.size = size;
            map.texel = texel;
            map.settings = *settings;
            map.screen = None;
            fd.lights.sources[i].shadow = Some(used as u32);
            stats.shadow_maps += 1;
            used += 1;
        }
        true
    }
}
