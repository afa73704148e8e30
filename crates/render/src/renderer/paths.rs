//! Progressive path tracing into the renderer: a running sum of paths per pixel kept
//! between calls, its mean tone mapped into the target.

use std::time::Instant;

use glam::Vec3;

use super::colours::{map_tone, write_mean};
use super::{FrameReport, Interrupted, Renderer, StageTimes};
use crate::prepare::PreparedScene;
use crate::raster::{Stats, Target};
use crate::settings::{Output, Settings, View};

impl Renderer {
    /// Progressive path tracing (`--shading path`): adds paths `samples` of every pixel
    /// to a running sum kept in the renderer, and makes the target its mean, tone mapped
    /// as [`Renderer::render_until`] does (so [`Renderer::write_pixels`] shows it). Samples
    /// from 0 start a new sum; later ranges continue it (the same scene, settings and view
    /// are the caller's business). After `0..n` in any number of calls the target holds,
    /// bit for bit, the mean of [`path::path_image`](crate::path::path_image) with `n`
    /// paths and seed 0: one path per pixel is [`Renderer::render_until`]'s path frame with
    /// one sample, and the mean of `n` paths is tone mapped once (a supersampled path frame
    /// tone maps each of its passes before averaging them). No depth is written.
    ///
    /// # Errors
    /// [`Interrupted`] if stopped; the sum is then lost (the next call starts from 0).
    ///
    /// A range that starts neither at 0 nor where the sum ends ([`Renderer::paths`]), or a
    /// view whose size changed since the sum began, starts a new sum: paths `0..end` are
    /// traced.
    pub fn render_paths(
        &mut self,
        scene: &PreparedScene,
        settings: &Settings,
        view: &View,
        samples: std::ops::Range<u32>,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<&FrameReport, Interrupted> {
        let t0 = Instant::now();
        let (w, h) = (view.width.max(1), view.height.max(1));
        let pixels = w as usize * h as usize;
        let continues = samples.start == self.paths && self.path.len() == pixels;
        let samples = if continues { samples } else { 0..samples.end };
        if samples.start == 0 {
            self.emitters = None;
            self.path.clear();
            self.path.resize(pixels, Vec3::ZERO);
        }
        self.paths = 0;
        self.complete = false;
        let bg = settings.background;
        let target = self.target.get_or_insert_with(|| Target::new(w, h, bg));
        target.set_samples(1, bg);
        target.reshape(w, h, bg);
        self.output = Output::Shaded;
        let view_m = view.camera.view();
        let vp = view.camera.projection(view.aspect()) * view_m;
        self.inv_vp = vp.inverse();
        let done = crate::path::path_into::<f32>(
            scene,
            settings,
            vp,
            view_m.inverse(),
            (w, h),
            (samples.clone(), 0, true),
            crate::path::Store::Sum,
            &mut self.path,
            &mut self.emitters,
            stop,
        );
        if !done {
            return Err(Interrupted);
        }
        self.paths = samples.end;
        let t_fill = t0.elapsed();
        write_mean(target, &self.path, self.paths);
        let (scale, tone) = (settings.exposure_scale(), settings.tone_for(scene.scene()));
        if tone != crate::ToneMap::Clamp || scale != 1.0 {
            map_tone(target, tone, scale, bg);
        }
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        self.report = FrameReport {
            width: w,
            height: h,
            samples: 1,
            msaa: 1,
            stats: Stats::default(),
            times: StageTimes {
                fill: ms(t_fill),
                resolve: ms(t0.elapsed() - t_fill),
                total: ms(t0.elapsed()),
                ..StageTimes::default()
            },
        };
        self.complete = true;
        Ok(&self.report)
    }
}
