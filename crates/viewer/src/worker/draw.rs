//! Rendering one level of a job: side A, side B beside it, and the ΔE00 heat map between
//! them.

use std::time::Instant;

use eframe::egui::Color32;

use super::schedule::record;
use super::{Frame, Heat, Image, Job, Level, Worker};
use crate::quality::metrics::{delta_e_map, heat_color, mean_p95};
use crate::quality::LinearImage;
use crate::render::{PreparedScene, Renderer, Settings, View};

impl Worker {
    /// Renders one level of a job (A, B and the heat map); `from`: for a [`Level::Paths`],
    /// the paths per pixel already summed by the job's earlier levels.
    pub(super) fn render_level(
        &mut self,
        job: &Job,
        n: u64,
        (level, from): (Level, u32),
        stale: &(dyn Fn() -> bool + Sync),
    ) -> Result<Frame, crate::render::Interrupted> {
        let start = Instant::now();
        let mut view = job.view.clone();
        let d = level.divisor();
        view.width = (view.width / d).max(1);
        view.height = (view.height / d).max(1);
        let samples = level.samples();
        let scene = match (level, &job.proxy) {
            (Level::Simplified(_), Some(p)) => p,
            _ => &job.scene,
        };
        let paths = match level {
            Level::Paths(to) => Some(from..to),
            _ => None,
        };
        let a = render_image(&mut self.a, scene, &job.a, &view, (samples, paths), stale)?;
        let b = match &job.b {
            Some(s) => {
                let how = (level, from, job.max_samples);
                Some(self.render_b(scene, s, &view, how, stale)?)
            }
            None => None,
        };
        if !matches!(level, Level::Supersampled(_) | Level::Paths(2..)) {
            let ms = start.elapsed().as_secs_f64() * 1e3;
            record(self.times_of(level), level.divisor() as usize, ms);
        }
        let heat = match (&b, job.heat, level) {
            (Some(_), true, Level::Full | Level::Supersampled(_) | Level::Paths(_)) => {
                Some(heat(&self.a, &self.b))
            }
            _ => None,
        };
        let mut depth = vec![0.0; (view.width * view.height) as usize];
        if let Some(t) = self.a.target() {
            t.write_depth(&mut depth);
        }
        Ok(Frame {
            job: n,
            level,
            view,
            a,
            b,
            heat,
            depth,
            last: false,
        })
    }
}

impl Worker {
    /// Renders side B at `level` (`from`: as in [`Worker::render_level`]). Beside a
    /// path-traced A that accumulates, a B not path traced is drawn twice only: with one
    /// sample beside A's first path, then supersampled as far as `max_samples` allows beside
    /// the second batch; A's later batches show that image again (a path-traced B
    /// accumulates as A does).
    fn render_b(
        &mut self,
        scene: &PreparedScene,
        settings: &Settings,
        view: &View,
        (level, from, max_samples): (Level, u32, u32),
        stale: &(dyn Fn() -> bool + Sync),
    ) -> Result<Image, crate::render::Interrupted> {
        let paths = match level {
            Level::Paths(to) => Some(from..to),
            _ => None,
        };
        let fixed = paths.is_some() && !path_traced(settings);
        if let (true, 2.., Some(image)) = (fixed, from, &self.b_image) {
            return Ok(image.clone());
        }
        let samples = match (fixed, from) {
            (true, 1) => max_samples.clamp(1, 4),
            _ => level.samples(),
        };
        let image = render_image(&mut self.b, scene, settings, view, (samples, paths), stale)?;
        self.b_image = fixed.then(|| image.clone());
        Ok(image)
    }
}

/// Renders one side: `samples` per axis, or for a path-traced side given `paths`, those
/// paths added to its running sum (a side not path traced is drawn with `samples`).
fn render_image(
    r: &mut Renderer,
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    (samples, paths): (u32, Option<std::ops::Range<u32>>),
    stale: &(dyn Fn() -> bool + Sync),
) -> Result<Image, crate::render::Interrupted> {
    let report = match paths {
        Some(range) if path_traced(settings) => {
            r.render_paths(scene, settings, view, range, stale)?.clone()
        }
        _ => {
            let mut s = settings.clone();
            s.samples = samples;
            r.render_until(scene, &s, view, stale)?.clone()
        }
    };
    let mut pixels = vec![Color32::BLACK; (view.width * view.height) as usize];
    r.write_pixels(&mut pixels, |[cr, cg, cb, ca]| {
        Color32::from_rgba_premultiplied(cr, cg, cb, ca)
    });
    let tiles_x = r.target().map_or(1, |t| t.tiles_x);
    Ok(Image {
        pixels,
        report,
        tile_costs: r.tile_costs().to_vec(),
        tiles_x,
    })
}

/// Whether `settings` shade by path tracing (what [`Renderer::render_paths`] adds up).
pub(super) fn path_traced(settings: &Settings) -> bool {
    settings.rays() == crate::shade::mode::Rays::Path
        && settings.output == crate::render::Output::Shaded
}

/// The ΔE00 map between the two renderers' frames.
fn heat(a: &Renderer, b: &Renderer) -> Heat {
    let (Some(ta), Some(tb)) = (a.target(), b.target()) else {
        return Heat {
            pixels: Vec::new(),
            mean: 0.0,
            p95: 0.0,
        };
    };
    let (fa, fb) = (ta.resolve(), tb.resolve());
    let (ia, ib) = (
        LinearImage::from_framebuffer(&fa),
        LinearImage::from_framebuffer(&fb),
    );
    let de = delta_e_map(&ia, &ib);
    // The statistics are over the pixels either side drew something in: the background
    // (ΔE 0 wherever both clear to it) would dilute the mean and zero the percentile.
    let drawn: Vec<f64> = de
        .iter()
        .zip(fa.depth.iter().zip(&fb.depth))
        .filter(|(_, (a, b))| **a > 0.0 || **b > 0.0)
        .map(|(d, _)| *d)
        .collect();
    let (mean, p95) = mean_p95(&drawn);
    let pixels = de
        .iter()
        .map(|&d| {
            let [r, g, b] = heat_color(d);
            Color32::from_rgb(r, g, b)
        })
        .collect();
    Heat { pixels, mean, p95 }
}
