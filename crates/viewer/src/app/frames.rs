//! Frames: a job submitted when the view, the scene or the settings change, and the finished frame uploaded to the screen.

use super::*;
use crate::panels::Side;
use crate::worker::{PROXY_ABOVE, PROXY_TRIANGLES};

impl ViewerApp {
    /// Uploads the newest finished frame.
    pub(super) fn take_frames(&mut self, ctx: &egui::Context) {
        let Some(frame) = self.host.take_frame() else {
            return;
        };
        let Frame {
            job,
            level,
            view,
            a,
            b,
            heat,
            depth,
            last,
        } = frame;
        let size = [view.width as usize, view.height as usize];
        let opts = if matches!(level, Level::Reduced(_) | Level::Simplified(2..)) {
            TextureOptions::LINEAR
        } else {
            TextureOptions::NEAREST
        };
        let img_a = Arc::new(ColorImage::new(size, a.pixels));
        let upload = |old: Option<TextureHandle>, name: &str, img: Arc<ColorImage>| {
            match old {
                // In place when the size is unchanged (glTexSubImage2D), else reallocated.
                Some(mut t) if t.size() == size => {
                    t.set_partial([0, 0], img, opts);
                    t
                }
                Some(mut t) => {
                    t.set(img, opts);
                    t
                }
                None => ctx.load_texture(name, img, opts),
            }
        };
        let old = self.shown.take();
        let (old_a, old_b, old_h, prev) = match old {
            Some(s) => (Some(s.tex_a), s.tex_b, s.tex_heat, Some(s.arrived)),
            None => (None, None, None, None),
        };
        let tex_a = upload(old_a, "frame-a", Arc::clone(&img_a));
        let (tex_b, report_b) = match b {
            Some(b) => (
                Some(upload(
                    old_b,
                    "frame-b",
                    Arc::new(ColorImage::new(size, b.pixels)),
                )),
                Some(b.report),
            ),
            None => (None, None),
        };
        let (tex_heat, heat) = match heat {
            Some(h) if h.pixels.len() == size[0] * size[1] => (
                Some(upload(
                    old_h,
                    "frame-heat",
                    Arc::new(ColorImage::new(size, h.pixels)),
                )),
                Some((h.mean, h.p95)),
            ),
            _ => (None, None),
        };
        let now = Instant::now();
        let line = format!(
            r#"{{"event":"frame","t_ms":{:.3},"job":{job},"level":"{}","width":{},"height":{},"render_ms":{:.3},"first":{}}}"#,
            crate::since_launch_ms(),
            level.label(),
            view.width,
            view.height,
            a.report.times.total,
            prev.is_none()
        );
        self.trace_line(&line);
        self.shown = Some(Shown {
            job,
            level,
            view,
            last,
            a: img_a,
            tex_a,
            tex_b,
            tex_heat,
            report_a: a.report,
            report_b,
            tile_costs: a.tile_costs,
            tiles_x: a.tiles_x,
            depth,
            heat,
            arrived: now,
            interval: prev.map(|p| now.duration_since(p).as_secs_f64() * 1e3),
        });
        self.reprobe();
    }

    /// The view of the viewport as it is now.
    #[must_use]
    pub fn current_view(&self) -> View {
        crate::viewport::view_of(&self.nav, &self.viewport)
    }

    /// Submits a job if the view, the scene or the settings changed since the last one.
    pub(super) fn submit_if_changed(&mut self) {
        if self.viewport.size_px[0] == 0 {
            return;
        }
        let view = self.current_view();
        let b = self.split.enabled.then_some(&self.split.b);
        let heat = self.split.enabled && self.split.heat;
        let same = self.last_job.as_ref().is_some_and(|j| {
            Arc::ptr_eq(&j.scene, &self.scene)
                && j.view == view
                && crate::same::same(&j.a, &self.settings)
                && match (j.b.as_deref(), b) {
                    (Some(x), Some(y)) => crate::same::same(x, y),
                    (x, y) => x.is_none() && y.is_none(),
                }
                && j.heat == heat
                && j.max_samples == self.max_samples
        });
        if same {
            return;
        }
        let proxy = self.proxy.for_scene(&self.scene, &self.repaint);
        let job = Job {
            scene: Arc::clone(&self.scene),
            a: Arc::new(self.settings.clone()),
            b: b.map(|s| Arc::new(s.clone())),
            heat,
            view,
            interactive: self.interacting,
            max_samples: self.max_samples,
            proxy,
        };
        self.last_job = Some(job.clone());
        self.host.submit(job);
        if self.synchronous {
            // The frame is ready now; show it in this pass's successor.
            (self.repaint)();
        }
    }

    /// The frame on screen is the final one for the current view and settings.
    #[must_use]
    pub fn settled(&self) -> bool {
        self.shown
            .as_ref()
            .is_some_and(|s| s.last && s.job == self.host.submitted())
            && !self.host.busy()
    }

    /// Reads the probed pixel again from a final frame drawn with other settings than the
    /// probe's (a changed mode or material must not leave the old reading on screen).
    fn reprobe(&mut self) {
        let (Some(pv), Some(shown)) = (&self.shared.probe, &self.shown) else {
            return;
        };
        let settings = match pv.side {
            Side::A => &self.settings,
            Side::B => &self.split.b,
        };
        let size = [shown.view.width, shown.view.height];
        if !shown.last
            || shown.job != self.host.submitted()
            || size != pv.frame_size
            || crate::same::same(&pv.settings, settings)
        {
            return;
        }
        let pv =
            crate::viewport::read_probe(shown, &self.scene, settings, pv.pixel, pv.side, pv.at);
        self.shared.probe = Some(pv);
    }
}

/// The simplified copy of a scene too large to redraw while the camera moves
/// ([`PreparedScene::simplified`]), made once per scene on a thread of its own.
#[derive(Default)]
pub struct Proxy {
    /// The scene it is (being) made for.
    base: Option<Arc<PreparedScene>>,
    ready: Option<Arc<PreparedScene>>,
    making: Option<std::sync::mpsc::Receiver<Option<PreparedScene>>>,
}

impl Proxy {
    /// The simplified copy of `scene` once it is made; starts making it the first time a
    /// still scene of more than [`PROXY_ABOVE`] triangles is asked for (`repaint` wakes the
    /// UI when it is done).
    pub fn for_scene(
        &mut self,
        scene: &Arc<PreparedScene>,
        repaint: &Arc<dyn Fn() + Send + Sync>,
    ) -> Option<Arc<PreparedScene>> {
        if !self.base.as_ref().is_some_and(|b| Arc::ptr_eq(b, scene)) {
            self.base = Some(Arc::clone(scene));
            self.ready = None;
            self.making = None;
            if scene.triangle_count() > PROXY_ABOVE && scene.scene().animations.is_empty() {
                let (tx, rx) = std::sync::mpsc::channel();
                let (s, repaint) = (Arc::clone(scene), Arc::clone(repaint));
                let spawned = std::thread::Builder::new()
                    .name("realist-proxy".into())
                    .spawn(move || {
                        let _ = tx.send(s.simplified(PROXY_TRIANGLES));
                        repaint();
                    });
                // Without a thread, moving frames keep to the reduced resolutions.
                self.making = spawned.ok().map(|_| rx);
            }
        }
        if let Some(Ok(p)) = self
            .making
            .as_ref()
            .map(std::sync::mpsc::Receiver::try_recv)
        {
            self.ready = p.map(Arc::new);
            self.making = None;
        }
        self.ready.clone()
    }
}
