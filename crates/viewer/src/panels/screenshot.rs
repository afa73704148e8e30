//! Screenshots: F12 saves the frame on screen at the window's size; the screenshot window
//! renders the current view offscreen at a chosen size (e.g. 3840x2160) and anti-aliasing,
//! on a thread of its own, and saves it as PNG.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use eframe::egui;

use super::{Cx, Dock, Panel};
use crate::keys::Action;
use crate::render::{PreparedScene, Renderer, Settings, View};

/// Largest side of an offscreen screenshot: 8192 x 8192 needs about 1.3 GB of tiles, and
/// as much again to average supersampling passes.
const MAX_SIDE: u32 = 8192;

/// Where an offscreen render leaves its file (or error); `None` while it runs.
type Outcome = Arc<Mutex<Option<Result<PathBuf, String>>>>;

/// The screenshot window, and F12.
pub struct ScreenshotPanel {
    pub open: bool,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub folder: String,
    /// The outcome of the running (or last) offscreen render.
    result: Option<Outcome>,
}

impl Panel for ScreenshotPanel {
    fn dock(&self) -> Dock {
        Dock::Window
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        self.window(ui.ctx(), cx);
    }

    fn file_menu(&mut self, ui: &mut egui::Ui, _cx: &mut Cx<'_>) {
        if ui.button("Screenshot...  (F12 saves at once)").clicked() {
            self.open = true;
            ui.close();
        }
    }

    fn act(&mut self, action: Action, cx: &mut Cx<'_>) {
        if action == Action::Screenshot {
            self.quick(cx);
        }
    }
}

impl Default for ScreenshotPanel {
    fn default() -> Self {
        Self {
            open: false,
            width: 3840,
            height: 2160,
            samples: 2,
            folder: ".".into(),
            result: None,
        }
    }
}

/// A file name that does not exist yet in `folder`.
fn file_name(folder: &str, scene: &str, w: u32, h: u32) -> PathBuf {
    let stem: String = scene
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let mut k = 0;
    loop {
        let suffix = if k == 0 {
            String::new()
        } else {
            format!("-{k}")
        };
        let at = stamp(secs);
        let p = PathBuf::from(folder).join(format!("realist-{stem}-{w}x{h}-{at}{suffix}.png"));
        if !p.exists() {
            return p;
        }
        k += 1;
    }
}

/// `secs` after the Unix epoch as a UTC date and time for a file name:
/// `2026-11-28_15-34-55` (the proleptic Gregorian calendar, as `date -u` shows it).
fn stamp(secs: u64) -> String {
    let (days, rest) = (secs / 86_400, secs % 86_400);
    // Days to a civil date (H. Hinnant's algorithm), from 0000-03-01.
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}_{:02}-{:02}-{:02}",
        rest / 3600,
        rest / 60 % 60,
        rest % 60
    )
}

fn save_png(path: &std::path::Path, w: u32, h: u32, rgba: Vec<u8>) -> Result<(), String> {
    crate::color::png::Png::rgba(w, h, &rgba)
        .with_text("Source", "realist viewer screenshot")
        .write(path)
}

/// Renders `view` offscreen and saves it.
fn offscreen(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    path: &std::path::Path,
) -> Result<(), String> {
    let mut r = Renderer::new();
    r.render(scene, settings, view);
    let mut px = vec![[0u8; 4]; (view.width * view.height) as usize];
    r.write_rgba8(&mut px);
    save_png(path, view.width, view.height, px.into_flattened())
}

impl ScreenshotPanel {
    /// F12: the frame on screen, as it is, at the window's size (drawn again at that size
    /// when the frame on screen is a reduced one, drawn while moving).
    fn quick(&self, cx: &mut Cx<'_>) {
        let Some(s) = cx.session.shown else {
            cx.notice("no frame to save yet");
            return;
        };
        if let crate::worker::Level::Reduced(_) | crate::worker::Level::Simplified(_) = s.level {
            // A frame drawn small or simplified while moving: the view drawn again at the
            // window's size, in full.
            let [w, h] = cx.viewport.size_px;
            let view = View {
                width: w.max(1),
                height: h.max(1),
                ..s.view.clone()
            };
            let path = file_name(&self.folder, &cx.session.name(), view.width, view.height);
            let saved = offscreen(cx.session.scene, cx.settings, &view, &path);
            cx.notice(match saved {
                Ok(()) => format!("saved {} (full resolution)", path.display()),
                Err(e) => e,
            });
            return;
        }
        let [w, h] = s.a.size;
        let path = file_name(&self.folder, &cx.session.name(), w as u32, h as u32);
        let rgba =
            s.a.pixels
                .iter()
                .flat_map(|c| [c.r(), c.g(), c.b(), 255])
                .collect();
        cx.notice(match save_png(&path, w as u32, h as u32, rgba) {
            Ok(()) => format!("saved {} ({})", path.display(), s.level.label()),
            Err(e) => e,
        });
    }

    /// The screenshot window.
    fn window(&mut self, ctx: &egui::Context, cx: &Cx<'_>) {
        if !self.open {
            return;
        }
        let mut open = true;
        let mut start = false;
        egui::Window::new("Screenshot")
            .open(&mut open)
            .show(ctx, |ui| {
                let st = &mut *self;
                ui.horizontal(|ui| {
                    ui.add(
                        egui::DragValue::new(&mut st.width)
                            .range(16..=MAX_SIDE)
                            .suffix(" px"),
                    );
                    ui.label("x");
                    ui.add(
                        egui::DragValue::new(&mut st.height)
                            .range(16..=MAX_SIDE)
                            .suffix(" px"),
                    );
                });
                ui.horizontal(|ui| {
                    for (w, h) in [(1920, 1080), (2560, 1440), (3840, 2160)] {
                        if ui.button(format!("{w}x{h}")).clicked() {
                            (st.width, st.height) = (w, h);
                        }
                    }
                    if ui.button("window").clicked() {
                        [st.width, st.height] = cx.viewport.size_px;
                    }
                });
                ui.horizontal(|ui| {
                    ui.label("anti-aliasing");
                    for n in [1, 2, 4] {
                        ui.selectable_value(
                            &mut st.samples,
                            n,
                            if n == 1 {
                                "off".into()
                            } else {
                                format!("{n}x{n}")
                            },
                        );
                    }
                });
                ui.horizontal(|ui| {
                    ui.label("folder");
                    ui.text_edit_singleline(&mut st.folder)
                        .accessible_name("screenshot folder");
                });
                let running = st
                    .result
                    .as_ref()
                    .is_some_and(|r| r.lock().is_ok_and(|g| g.is_none()));
                if running {
                    ui.label("rendering...");
                } else if ui.button("render and save").clicked() {
                    start = true;
                }
                if let Some(Some(r)) = st
                    .result
                    .as_ref()
                    .and_then(|r| r.lock().ok().map(|g| g.clone()))
                {
                    match r {
                        Ok(p) => ui.label(format!("saved {}", p.display())),
                        Err(e) => ui.colored_label(egui::Color32::from_rgb(255, 110, 90), e),
                    };
                }
            });
        self.open &= open;
        if start {
            let st = &*self;
            let (w, h) = (st.width.clamp(16, MAX_SIDE), st.height.clamp(16, MAX_SIDE));
            let view = View {
                camera: cx.nav.camera(w as f32 / h as f32),
                width: w,
                height: h,
            };
            let settings = Settings {
                samples: st.samples,
                ..cx.settings.clone()
            };
            let path = file_name(&st.folder, &cx.session.name(), w, h);
            let (scene, slot, ctx) = (
                Arc::clone(cx.session.scene),
                Arc::new(Mutex::new(None)),
                ctx.clone(),
            );
            let out = Arc::clone(&slot);
            std::thread::spawn(move || {
                let r = offscreen(&scene, &settings, &view, &path).map(|()| path);
                if let Ok(mut g) = out.lock() {
                    *g = Some(r);
                }
                ctx.request_repaint();
            });
            self.result = Some(slot);
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn stamps_are_utc_dates_and_times() {
        assert_eq!(super::stamp(0), "1970-01-01_00-00-00");
        assert_eq!(super::stamp(951_782_400), "2000-02-29_00-00-00");
        assert_eq!(super::stamp(1_795_880_095), "2026-11-28_15-34-55");
    }
}
