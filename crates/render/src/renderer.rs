//! [`Renderer`]: renders frames of a [`PreparedScene`] again and again, as a viewer does,
//! keeping its target and every buffer between frames. After the first frame at a size
//! (and with the shading modes in use), rendering a frame allocates nothing
//! (`tests/alloc_free.rs` counts allocations to prove it).
//!
//! Supersampling renders `n x n` whole passes, each with the projection shifted by a
//! fraction of a pixel so the samples of a pixel lie on a regular grid, and averages them
//! in linear light: the same samples as rendering `n` times larger and box-filtering, with
//! one `n x n`-th of the memory, lines one pixel wide, and a natural point between passes
//! to stop or to show progress. Textures choose their mip level as for the larger image.

use std::time::Instant;

use glam::{Mat4, Vec3, Vec4};

use super::frame::{self, FrameData};
use super::passes::{self, Cx};
use super::pool::Pool;
use super::prepare::PreparedScene;
use super::settings::{Output, Settings, View};
use crate::raster::{Bins, Stats, Target, TileCost, TILE};
use crate::simd::KernelKind;

mod colours;
mod paths;
#[cfg(test)]
mod tests;

use colours::{accumulate, map_tone, write_mean};

/// Wall-clock milliseconds of a frame's stages (summed over supersampling passes).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct StageTimes {
    /// Lights, culling and material set-up.
    pub setup: f64,
    /// Vertex stage (transform and per-vertex lighting).
    pub vertex: f64,
    /// Clipping, culling, triangle set-up and binning.
    pub raster: f64,
    /// Tile fill and fragment shading.
    pub fill: f64,
    /// Summing supersampling passes.
    pub resolve: f64,
    /// The whole frame.
    pub total: f64,
}

/// What the last frame did.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct FrameReport {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel along each axis (1, 2, 4...).
    pub samples: u32,
    /// Multisampling: coverage and depth samples per pixel (1 or 4).
    pub msaa: u32,
    /// Counters, summed over the `samples * samples` passes.
    pub stats: Stats,
    pub times: StageTimes,
}

/// The frame was abandoned because the stop signal answered true.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("frame interrupted")]
pub struct Interrupted;

/// A reusable renderer: owns its target and scratch memory.
#[derive(Debug, Default)]
pub struct Renderer {
    target: Option<Target>,
    bins: Bins,
    pool: Pool,
    frame: FrameData,
    /// Sum of the passes of a supersampled frame, in the target's tile layout.
    accum: Vec<Vec4>,
    report: FrameReport,
    /// Clip -> world of the last frame (without jitter), for picking.
    inv_vp: Mat4,
    output: Output,
    /// The last frame completed (an interrupted frame leaves a partial target).
    complete: bool,
    shadows: super::shadows::ShadowTargets,
    screen_shadows: super::whitted::ScreenShadows,
    /// A path-traced pass's pixels (row-major), reused; after [`Renderer::render_paths`],
    /// the running sum of each pixel's first `paths` paths.
    path: Vec<Vec3>,
    /// Paths per pixel summed in `path` (0: none, or `path` holds a pass).
    paths: u32,
    /// The scene's emitters as the running sum's paths draw them (built when it starts).
    emitters: Option<crate::path::Emitters>,
}

impl Renderer {
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Renders a frame on the current rayon pool (call it from inside `pool.install` to keep
    /// work off other pools; the image does not depend on the thread count).
    pub fn render(
        &mut self,
        scene: &PreparedScene,
        settings: &Settings,
        view: &View,
    ) -> &FrameReport {
        match self.render_until(scene, settings, view, &|| false) {
            Ok(_) | Err(Interrupted) => &self.report,
        }
    }

    /// [`Renderer::render`] that asks `stop` before each tile and between passes, and
    /// abandons the frame once it answers true (e.g. when a newer view is waiting).
    ///
    /// # Errors
    /// [`Interrupted`] if stopped; the target then holds a partial frame.
    pub fn render_until(
        &mut self,
        scene: &PreparedScene,
        settings: &Settings,
        view: &View,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<&FrameReport, Interrupted> {
        if settings.rays() == crate::shade::mode::Rays::Radiosity
            && settings.output == Output::Shaded
        {
            // The solution (made once, kept) drawn as it is: unlit patches whose corners
            // carry their radiance, interpolated (Gouraud).
            let solved = scene.radiosity(settings);
            let shown = Settings {
                shading: Some(crate::shade::Shading::Pbr),
                ground: None,
                hidden: super::settings::Hidden::default(),
                ..settings.clone()
            };
            return self.render_until(&solved.scene, &shown, view, stop);
        }
        let t0 = Instant::now();
        self.complete = false;
        self.paths = 0;
        // The emitters are built again for this frame's scene and settings.
        self.emitters = None;
        let (w, h) = (view.width.max(1), view.height.max(1));
        let n = settings.samples.clamp(1, 8);
        // The overdraw view counts from zero.
        let bg = match settings.output {
            Output::Shaded => settings.background,
            Output::Overdraw => Vec4::ZERO,
        };
        let target = self.target.get_or_insert_with(|| Target::new(w, h, bg));
        target.set_samples(settings.msaa, bg);
        target.reshape(w, h, bg);
        self.bins.reset_costs();
        self.bins.kernel = settings.kernel.unwrap_or_else(KernelKind::best);
        self.output = settings.output;
        let camera = &view.camera;
        let view_m = camera.view();
        let vp = camera.projection(view.aspect()) * view_m;
        self.inv_vp = vp.inverse();
        let eye = camera.shading_eye();
        let mut stats = Stats::default();
        frame::set_up(
            &mut self.frame,
            scene,
            settings,
            view_m,
            vp,
            eye,
            self.bins.kernel,
            &mut stats,
        );
        let traced = settings.rays() == crate::shade::mode::Rays::Whitted
            && settings.output == Output::Shaded;
        let traced_shadows = traced && self.frame.lights.sources.iter().any(|s| s.casts);
        if !traced_shadows
            && self.frame.lights.sources.iter().any(|s| s.casts)
            && settings.output == Output::Shaded
        {
            let done = self.shadows.render(
                scene,
                &mut self.frame,
                &settings.shadow,
                &mut self.bins,
                &mut self.pool,
                &mut stats,
                stop,
            );
            if !done {
                return Err(Interrupted);
            }
        }
        let t_setup = t0.elapsed();
        let passes = n * n;
        if passes > 1 {
            self.accum.clear();
            self.accum
                .resize(target.tiles.len() * (TILE * TILE) as usize, Vec4::ZERO);
        }
        let mut vertex_nanos = 0;
        let mut resolve = std::time::Duration::ZERO;
        let scale = settings.exposure_scale();
        let tone = settings.tone_for(scene.scene());
        let map =
            (tone != super::ToneMap::Clamp || scale != 1.0) && settings.output == Output::Shaded;
        // After the passes of a supersampled frame, one more: depth at the pixel centres.
        let centre_depth = passes > 1 && settings.output == Output::Shaded;
        for k in 0..passes + u32::from(centre_depth) {
            if stop() {
                return Err(Interrupted);
            }
            if k > 0 && k < passes {
                target.clear(bg);
            }
            // Sample k of the n x n grid: offsets (i + 0.5) / n - 0.5 pixel, y down.
            let (dx, dy) = if k < passes {
                (
                    ((k % n) as f32 + 0.5) / n as f32 - 0.5,
                    ((k / n) as f32 + 0.5) / n as f32 - 0.5,
                )
            } else {
                (0.0, 0.0)
            };
            let jitter =
                Mat4::from_translation(Vec3::new(2.0 * dx / w as f32, -2.0 * dy / h as f32, 0.0));
            // The environment as the background: each pixel gets what its camera ray sees
            // (the ray through the sample this pass shades).
            if let (true, Some(blur), Some(env)) = (
                k < passes && settings.output == Output::Shaded,
                settings.env_background,
                &self.frame.lights.env,
            ) {
                let inv = self.inv_vp;
                let (wf, hf) = (w as f32, h as f32);
                target.clear_with(|x, y| {
                    let nx = (x as f32 + 0.5 - dx) / wf * 2.0 - 1.0;
                    let ny = 1.0 - (y as f32 + 0.5 - dy) / hf * 2.0;
                    // Reversed Z: the near plane is at 1.
                    let near = inv.project_point3(Vec3::new(nx, ny, 1.0));
                    let mid = inv.project_point3(Vec3::new(nx, ny, 0.5));
                    env.background((mid - near).normalize_or_zero(), blur)
                        .extend(1.0)
                });
            }
            if traced_shadows && k < passes {
                let done = self.screen_shadows.render(
                    scene,
                    settings,
                    &mut self.frame,
                    camera,
                    jitter * vp,
                    (w, h),
                    &mut self.bins,
                    &mut self.pool,
                    &mut stats,
                    stop,
                );
                if !done {
                    return Err(Interrupted);
                }
            }
            let mut planes = [Vec4::ZERO; crate::Sections::MAX];
            let sections = settings.sections.to_clip(jitter * vp, &mut planes);
            let mut cx = Cx {
                scene,
                camera,
                eye,
                jitter,
                lod_scale: 1.0 / n as f32,
                target,
                bins: &mut self.bins,
                pool: &mut self.pool,
                stats: &mut stats,
                stop,
                vertex_nanos: 0,
                light: None,
                sort: false,
                sections: &planes[..sections],
            };
            let path = settings.rays() == crate::shade::mode::Rays::Path
                && settings.output == Output::Shaded;
            let done = if path {
                // Nothing rasterized: one path per pixel for this pass (sample `k`), and no
                // depth (the centre-depth pass finds none).
                k >= passes || {
                    self.path.clear();
                    self.path.resize(w as usize * h as usize, Vec3::ZERO);
                    let done = super::path::path_into::<f32>(
                        scene,
                        settings,
                        vp,
                        view_m.inverse(),
                        (w, h),
                        (k..k + 1, 0, true),
                        super::path::Store::Mean,
                        &mut self.path,
                        &mut self.emitters,
                        stop,
                    );
                    write_mean(cx.target, &self.path, 1);
                    done
                }
            } else if k < passes {
                let overdraw = settings.output == Output::Overdraw;
                passes::frame(
                    &mut cx,
                    &mut self.frame,
                    overdraw,
                    settings.wireframe_overlay,
                )
            } else {
                passes::centre_depth(&mut cx, &self.frame)
            };
            vertex_nanos += cx.vertex_nanos;
            if !done {
                return Err(Interrupted);
            }
            if traced && k < passes {
                let cam_to_world = view_m.inverse();
                if !super::whitted::mirrors(
                    scene,
                    settings,
                    target,
                    jitter * vp,
                    cam_to_world,
                    stop,
                ) {
                    return Err(Interrupted);
                }
            }
            if map && k < passes {
                // Each pass tone mapped before the passes are averaged (as the samples of a
                // multisampled pixel are).
                let t = Instant::now();
                map_tone(target, tone, scale, bg);
                resolve += t.elapsed();
            }
            if passes > 1 && k < passes {
                let t = Instant::now();
                let last = k + 1 == passes;
                accumulate(target, &mut self.accum, last.then_some(1.0 / passes as f32));
                resolve += t.elapsed();
            }
        }
        let ms = |nanos: u64| nanos as f64 * 1e-6;
        self.report = FrameReport {
            width: w,
            height: h,
            samples: n,
            msaa: target.samples(),
            stats,
            times: StageTimes {
                setup: t_setup.as_secs_f64() * 1e3,
                vertex: ms(vertex_nanos),
                raster: ms(self.bins.setup_nanos),
                fill: ms(self.bins.fill_nanos),
                resolve: resolve.as_secs_f64() * 1e3,
                total: t0.elapsed().as_secs_f64() * 1e3,
            },
        };
        self.complete = true;
        Ok(&self.report)
    }

    /// Paths per pixel in the running sum of [`Renderer::render_paths`] (0 after any
    /// other frame or an interrupted one).
    #[must_use]
    pub fn paths(&self) -> u32 {
        self.paths
    }

    /// The last frame's report.
    #[must_use]
    pub fn report(&self) -> &FrameReport {
        &self.report
    }

    /// The target of the last frame (linear light; for a supersampled frame, the average of
    /// its passes, and the depth of the pixel centres). `None` before the first frame.
    #[must_use]
    pub fn target(&self) -> Option<&Target> {
        self.target.as_ref()
    }

    /// Takes the target out (the next frame allocates a new one).
    pub fn take_target(&mut self) -> Option<Target> {
        self.target.take()
    }

    /// Per-tile cost of the last frame, in the order of [`Target::tiles`].
    #[must_use]
    pub fn tile_costs(&self) -> &[TileCost] {
        self.bins.costs()
    }

    /// Whether the last frame completed.
    #[must_use]
    pub fn complete(&self) -> bool {
        self.complete
    }

    /// Writes the last frame as 8-bit sRGB (alpha 255) into `out`, row-major, `width *
    /// height` pixels, e.g. the pixels of an egui `ColorImage` (no intermediate copy). The
    /// overdraw view is mapped through [`overdraw_color`](super::overdraw_color).
    ///
    /// # Panics
    /// If there is no frame yet or `out` has the wrong size.
    pub fn write_rgba8(&self, out: &mut [[u8; 4]]) {
        self.write_pixels(out, |p| p);
    }

    /// [`Renderer::write_rgba8`] into any pixel type: `make` turns sRGB bytes (alpha 255)
    /// into a pixel, e.g. `|[r, g, b, a]| Color32::from_rgba_premultiplied(r, g, b, a)`.
    ///
    /// # Panics
    /// If there is no frame yet or `out` has the wrong size.
    pub fn write_pixels<P: Send>(&self, out: &mut [P], make: impl Fn([u8; 4]) -> P + Sync) {
        let target = self.target.as_ref().expect("a frame was rendered");
        match self.output {
            Output::Shaded => target.write_pixels(out, |c| c, make),
            Output::Overdraw => target.write_pixels(out, |c| super::overdraw_color(c.x), make),
        }
    }

    /// The world-space point seen at pixel (x, y) of the last frame, from its depth buffer,
    /// or `None` where nothing was drawn.
    #[must_use]
    pub fn pick(&self, x: u32, y: u32) -> Option<Vec3> {
        let target = self.target.as_ref()?;
        let (_, depth) = target.pixel(x, y)?;
        if self.output == Output::Overdraw {
            return None;
        }
        let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
        unproject_with(self.inv_vp, target.width, target.height, fx, fy, depth)
    }
}

/// The world point at pixel position (x, y) of `view` (pixels, y down; pixel centres at
/// +0.5) whose depth-buffer value is `depth` (reversed-Z z/w), or `None` for depth 0
/// (nothing drawn) or a non-finite result.
#[must_use]
pub fn unproject(view: &View, x: f32, y: f32, depth: f32) -> Option<Vec3> {
    let vp = view.camera.projection(view.aspect()) * view.camera.view();
    unproject_with(
        vp.inverse(),
        view.width.max(1),
        view.height.max(1),
        x,
        y,
        depth,
    )
}

fn unproject_with(inv_vp: Mat4, w: u32, h: u32, x: f32, y: f32, depth: f32) -> Option<Vec3> {
    if !(depth > 0.0 && depth.is_finite()) {
        return None;
    }
    let ndc = glam::Vec2::new(x / w as f32 * 2.0 - 1.0, 1.0 - y / h as f32 * 2.0);
    let p = inv_vp * ndc.extend(depth).extend(1.0);
    let p = p.truncate() / p.w;
    p.is_finite().then_some(p)
}
