//! The texture lab's rows under a slot: its sampler's wrap modes, its image file with the error of the last one that failed, and the model's UV map.

use super::*;

/// names them.
pub(super) const WRAPS: [(Wrap, &str); 3] = [
    (Wrap::Repeat, "repeat"),
    (Wrap::MirroredRepeat, "mirrored repeat"),
    (Wrap::ClampToEdge, "clamp to edge"),
];

/// The wrap menu of an image in a slot: the material's own sampler (`None`) or one wrap
/// mode on both axes. True when it changed.
pub(super) fn wrap_row(
    ui: &mut egui::Ui,
    id: &str,
    slot: Slot,
    sampler: &mut Option<Sampler>,
) -> bool {
    let name = |w: Wrap| WRAPS.iter().find(|(x, _)| *x == w).map_or("?", |(_, n)| *n);
    let shown = match sampler {
        None => "the texture's".to_owned(),
        Some(s) if s.wrap_u == s.wrap_v => name(s.wrap_u).to_owned(),
        Some(s) => format!("{} x {}", name(s.wrap_u), name(s.wrap_v)),
    };
    let mut changed = false;
    ui.horizontal(|ui| {
        let label = ui.label("wrap");
        egui::ComboBox::from_id_salt((id, "wrap", slot.key()))
            .selected_text(shown)
            .show_ui(ui, |ui| {
                if ui
                    .selectable_label(sampler.is_none(), "the texture's")
                    .clicked()
                {
                    *sampler = None;
                    changed = true;
                }
                for (w, n) in WRAPS {
                    let on = sampler.is_some_and(|s| s.wrap_u == w && s.wrap_v == w);
                    if ui.selectable_label(on, n).clicked() && !on {
                        let filter = sampler.map_or(Filter::default(), |s| s.filter);
                        *sampler = Some(Sampler {
                            wrap_u: w,
                            wrap_v: w,
                            filter,
                        });
                        changed = true;
                    }
                }
            })
            .response
            .labelled_by(label.id)
            .on_hover_text(
                "how UVs outside 0..1 read the image, on both axes (the filter stays the \
                 shading panel's, trilinear unless set there)",
            );
    });
    changed
}

/// A slot's image file: the path (typed, or chosen with "browse…"), "load", and the last
/// error. `shown`: the slot reads an image now (then the row stays open).
pub(super) fn image_row(lab: &mut LabUi, ui: &mut egui::Ui, side: Side, slot: Slot, shown: bool) {
    let id = letter(side);
    let key = (side, slot);
    let name = format!("{id} {} image", slot.name());
    let mut load = false;
    ui.horizontal(|ui| {
        ui.label("image");
        let path = lab.paths.entry(key).or_default();
        // As wide as the room left, not as the path: the field scrolls its text.
        let field = ui
            .add(
                egui::TextEdit::singleline(path)
                    .desired_width(ui.available_width())
                    .hint_text("path of a PNG, JPEG, HDR or EXR file"),
            )
            .accessible_name(format!("{name} path"));
        load |= field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    });
    let reading = lab.loads.iter().any(|l| l.side == side && l.slot == slot);
    ui.horizontal(|ui| {
        load |= ui
            .small_button("load")
            .accessible_name(format!("{name} load"))
            .on_hover_text(format!(
                "reads the file as every material's {} texture (side {id})",
                slot.name()
            ))
            .clicked();
        if ui
            .small_button("browse…")
            .accessible_name(format!("{name} browse"))
            .clicked()
        {
            lab.requests.push(Request::Browse(side, slot));
        }
        if !shown
            && ui
                .small_button("close")
                .accessible_name(format!("{name} close"))
                .clicked()
        {
            lab.paths.remove(&key);
            lab.errors.remove(&key);
        }
        if reading {
            ui.label("reading…");
        }
    });
    if load {
        let typed = lab.paths.get(&key).map_or("", |p| p.trim());
        if typed.is_empty() {
            let message = "no image file given: type its path or browse…".to_owned();
            lab.errors.insert(
                key,
                ImageError {
                    path: String::new(),
                    message,
                },
            );
        } else {
            lab.requests
                .push(Request::Load(side, slot, PathBuf::from(typed)));
        }
    }
    if let Some(e) = lab.errors.get(&key).cloned() {
        // The file on a line of its own, cut in the middle so that its name shows (the whole
        // message on hover and to a screen reader), and why under it.
        let reason = match e.message.strip_prefix(e.path.as_str()) {
            Some(r) if !e.path.is_empty() => {
                error_path(ui, &e);
                r.trim_start_matches(':').trim_start()
            }
            _ => e.message.as_str(),
        };
        ui.horizontal_wrapped(|ui| {
            ui.colored_label(ERROR_RED, reason);
            if ui
                .small_button("dismiss")
                .accessible_name(format!("{name} dismiss"))
                .clicked()
            {
                lab.errors.remove(&key);
            }
        });
    }
}

/// The path of a file that could not be used, elided in the middle to the width left.
pub(super) fn error_path(ui: &mut egui::Ui, e: &ImageError) {
    // A little short of the edge, which a vertical scroll bar may cover.
    let width = ui.available_width() - 6.0;
    let font = egui::TextStyle::Body.resolve(ui.style());
    let painter = ui.painter().clone();
    let fits = |t: &str| {
        painter
            .layout_no_wrap(t.to_owned(), font.clone(), egui::Color32::WHITE)
            .size()
            .x
            <= width
    };
    let shown = crate::panels::text::elide_middle(&e.path, fits);
    let label = egui::Label::new(egui::RichText::new(shown.as_ref()).color(ERROR_RED))
        .wrap_mode(egui::TextWrapMode::Extend);
    let r = ui.add(label);
    r.widget_info(|| {
        egui::WidgetInfo::labeled(egui::accesskit::Role::Label, true, e.message.as_str())
    });
    r.on_hover_text(e.message.as_str());
}

/// The UV map: the model's texture coordinates, chosen on side A for both.
pub(super) fn uv_row(lab: &mut LabUi, ui: &mut egui::Ui, side: Side, uv: UvView) {
    let name = |c: Option<UvGenerator>| match c {
        None => "mesh (the file's UVs)".to_owned(),
        Some(g) => g.to_string(),
    };
    ui.horizontal(|ui| {
        let label = ui.label("UV map");
        if side == Side::B {
            ui.label(format!(
                "{} (set on side A for both)",
                lab::uv_name(uv.chosen)
            ));
            return;
        }
        egui::ComboBox::from_id_salt("uv-map")
            .selected_text(lab::uv_name(uv.chosen))
            .show_ui(ui, |ui| {
                for choice in std::iter::once(None).chain(UvGenerator::PRESETS.map(Some)) {
                    if ui
                        .selectable_label(uv.chosen == choice, name(choice))
                        .clicked()
                        && uv.chosen != choice
                    {
                        lab.requests.push(Request::Uv(choice));
                    }
                }
            })
            .response
            .labelled_by(label.id)
            .on_hover_text(
                "texture coordinates of every mesh (the textbook's §9.5): the file's, or UV \
                 set 0 generated by a planar, cylindrical, spherical or box map fitted to the \
                 mesh's bounding box (what `--uv` and the scene-file key `uv` choose). A model \
                 without UVs becomes texturable. Kept on reload; both sides draw it.",
            );
        if uv.pending {
            ui.label("generating…");
        }
    });
}
