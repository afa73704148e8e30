//! The colour section: the CIE 1931 xy chromaticity diagram ([`crate::overlay::chroma`])
//! with where the frame's pixels (or a texture's texels) fall, and the fraction outside the
//! sRGB, Display P3 and Rec. 2020 gamuts. The diagram is drawn on a thread of its own and
//! shown when ready.

use std::sync::{Arc, Mutex};

use eframe::egui::{self, ColorImage, TextureHandle, TextureOptions};

use super::{Cx, Dock, Installed, Panel};
use crate::color::RgbSpace;
use crate::overlay::chroma::{self, ChromaOptions, PixelStyle};
use crate::texture::Texture;

/// Side of the diagram in pixels.
const SIZE: u32 = 420;

/// What the diagram analyses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Source {
    /// The frame on screen (A).
    #[default]
    Frame,
    /// The scene's texture with this index.
    Texture(usize),
}

/// What the diagram found.
struct Summary {
    /// (gamut name, fraction of non-dark pixels outside it).
    outside: Vec<(String, f64)>,
    pixels: u64,
    dark: u64,
    what: String,
}

/// A finished diagram.
struct Diagram {
    image: ColorImage,
    summary: Summary,
}

/// The colour section.
#[derive(Default)]
pub struct ColourPanel {
    pub source: Source,
    pub density: bool,
    texture: Option<TextureHandle>,
    shown: Option<Summary>,
    pending: Option<Arc<Mutex<Option<Diagram>>>>,
}

impl Panel for ColourPanel {
    fn dock(&self) -> Dock {
        Dock::Right
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Colour (CIE 1931)").show(ui, |ui| self.show(ui, cx));
    }

    fn installed(&mut self, what: &Installed<'_>) {
        if what.fresh {
            *self = Self::default();
        }
    }
}

/// Analyses `image` and draws the diagram (runs on a worker thread).
fn draw(image: &Texture, density: bool, what: String) -> Diagram {
    let gamuts = vec![
        RgbSpace::srgb(),
        RgbSpace::display_p3(),
        RgbSpace::rec2020(),
    ];
    let report = chroma::pixels::analyse(image, &gamuts);
    let opts = ChromaOptions {
        size: SIZE,
        gamuts,
        planckian: true,
        pixels: Some(report.clone()),
        pixel_style: if density {
            PixelStyle::Density
        } else {
            PixelStyle::Scatter
        },
        title: Some(format!("CIE 1931 xy: {what}")),
        ..ChromaOptions::default()
    };
    let pixmap = chroma::diagram_pixmap(&opts);
    let image = ColorImage::from_rgba_premultiplied(
        [pixmap.width() as usize, pixmap.height() as usize],
        pixmap.data(),
    );
    Diagram {
        image,
        summary: Summary {
            outside: report.outside.clone(),
            pixels: report.total,
            dark: report.dark,
            what,
        },
    }
}

/// The colour section.
impl ColourPanel {
    fn show(&mut self, ui: &mut egui::Ui, cx: &Cx<'_>) {
        let textures = cx.session.scene.scene().textures.clone();
        let st = self;
        ui.horizontal(|ui| {
            ui.selectable_value(&mut st.source, Source::Frame, "the frame");
            for i in 0..textures.len().min(8) {
                ui.selectable_value(&mut st.source, Source::Texture(i), format!("texture {i}"));
            }
        });
        ui.checkbox(&mut st.density, "density (log count) instead of dots");
        let busy = st.pending.is_some();
        if ui
            .add_enabled(!busy, egui::Button::new("draw the diagram"))
            .clicked()
        {
            let (image, what) = match st.source {
                Source::Frame => match cx.session.shown {
                    Some(s) => {
                        let texels =
                            s.a.pixels
                                .iter()
                                .map(|c| [c.r(), c.g(), c.b(), 255])
                                .collect();
                        let t = Texture::new(
                            "frame",
                            s.a.size[0] as u32,
                            s.a.size[1] as u32,
                            texels,
                            true,
                        );
                        (t.ok(), format!("frame, {}x{}", s.a.size[0], s.a.size[1]))
                    }
                    None => (None, String::new()),
                },
                Source::Texture(i) => (
                    textures.get(i).map(|t| (**t).clone()),
                    textures
                        .get(i)
                        .map_or(String::new(), |t| format!("texture '{}'", t.name)),
                ),
            };
            if let Some(image) = image {
                let slot = Arc::new(Mutex::new(None));
                let (out, density, ctx) = (Arc::clone(&slot), st.density, ui.ctx().clone());
                std::thread::spawn(move || {
                    let d = draw(&image, density, what);
                    if let Ok(mut s) = out.lock() {
                        *s = Some(d);
                    }
                    ctx.request_repaint();
                });
                st.pending = Some(slot);
            }
        }
        let done = st
            .pending
            .as_ref()
            .and_then(|p| p.lock().ok().and_then(|mut s| s.take()));
        if let Some(d) = done {
            st.pending = None;
            let tex = ui
                .ctx()
                .load_texture("cie-diagram", d.image, TextureOptions::LINEAR);
            st.texture = Some(tex);
            st.shown = Some(d.summary);
        }
        if busy {
            ui.label("drawing...");
        }
        if let Some(sm) = &st.shown {
            ui.label(format!(
                "{}: {} pixels, {} too dark to place",
                sm.what, sm.pixels, sm.dark
            ));
            for (name, f) in &sm.outside {
                ui.label(format!("outside {name}: {:.2}%", f * 100.0));
            }
        }
        if let Some(t) = &st.texture {
            let w = ui.available_width().min(SIZE as f32);
            ui.image((t.id(), egui::vec2(w, w)));
        }
    }
}
