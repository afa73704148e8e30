//! The texture lab's controls, one row per material slot (the textbook's §9.5): what every
//! material reads in the slot (the model's own texture, nothing, or a procedural texture,
//! or an image given on the command line or in a scene file), from which UV set and through
//! which transform, and the bump height. Shown for each side of the split view, so A | B
//! compares two textures, filters or bump heights with the ΔE map.

use std::sync::Arc;

use eframe::egui;

use crate::render::Settings;
use crate::scene::{Slot, SlotOverride, TextureSource, UvTransform, DEFAULT_BUMP_SCALE};
use crate::texture::{Domain, Procedural, ProceduralTexture, PROCEDURAL_NAMES};

/// The slots the lab offers, in panel order.
const SLOTS: [Slot; 5] = [
    Slot::BaseColor,
    Slot::Specular,
    Slot::Emissive,
    Slot::Bump,
    Slot::Normal,
];

/// What a slot's menu shows for its override.
fn current(o: Option<&SlotOverride>) -> String {
    match o {
        None => "the model's".into(),
        Some(SlotOverride::Off) => "off".into(),
        Some(SlotOverride::Source { source, .. }) => match source {
            TextureSource::Image(t) => {
                super::text::elide_middle(&t.name, |x| x.chars().count() <= 28).into_owned()
            }
            TextureSource::Procedural(_) => source.spec(),
        },
    }
}

/// The override for procedural `name` in `slot`, keeping the UV set and transform of
/// `old` if it had them.
fn procedural(name: &str, slot: Slot, old: Option<&SlotOverride>) -> Option<SlotOverride> {
    let p: Procedural = name.parse().ok()?;
    let p = ProceduralTexture::new(p);
    let scale = if slot == Slot::Bump {
        DEFAULT_BUMP_SCALE[if p.domain() == Domain::Uv { 1 } else { 2 }]
    } else {
        1.0
    };
    let mut o = SlotOverride::source(TextureSource::Procedural(Arc::new(p)), scale);
    if let (
        Some(SlotOverride::Source {
            uv_set, transform, ..
        }),
        SlotOverride::Source {
            uv_set: u,
            transform: t,
            ..
        },
    ) = (old, &mut o)
    {
        (*u, *t) = (*uv_set, *transform);
    }
    Some(o)
}

/// One slot's menu, UV set, transform and scale.
fn slot_row(s: &mut Settings, ui: &mut egui::Ui, id: &str, slot: Slot) {
    let old = s.slots.get(slot).cloned();
    ui.horizontal(|ui| {
        let label = ui.label(slot.name());
        egui::ComboBox::from_id_salt((id, "slot", slot.key()))
            .selected_text(current(old.as_ref()))
            .show_ui(ui, |ui| {
                if ui.selectable_label(old.is_none(), "the model's").clicked() {
                    s.slots.set(slot, None);
                }
                let off = matches!(old, Some(SlotOverride::Off));
                if ui.selectable_label(off, "off").clicked() {
                    s.slots.set(slot, Some(SlotOverride::Off));
                }
                if slot == Slot::Normal {
                    return;
                }
                for name in PROCEDURAL_NAMES {
                    let on = matches!(&old, Some(SlotOverride::Source {
                        source: TextureSource::Procedural(p), ..
                    }) if p.source().name() == name);
                    if ui.selectable_label(on, name).clicked() && !on {
                        s.slots.set(slot, procedural(name, slot, old.as_ref()));
                    }
                }
            })
            .response
            .labelled_by(label.id)
            .on_hover_text(format!(
                "what every material reads as its {} texture (side {})",
                slot.name(),
                id.to_uppercase()
            ));
    });
    let Some(SlotOverride::Source {
        source,
        uv_set,
        transform,
        scale,
        ..
    }) = s.slots.get(slot).cloned()
    else {
        return;
    };
    let mut changed = false;
    let (mut uv_set, mut t, mut scale) = (uv_set, transform, scale);
    ui.indent((id, "slot-detail", slot.key()), |ui| {
        if source.needs_uv() {
            ui.horizontal(|ui| {
                let label = ui.label("UV set");
                changed |= ui
                    .add(egui::DragValue::new(&mut uv_set).range(0..=3))
                    .labelled_by(label.id)
                    .changed();
            });
            ui.horizontal(|ui| {
                let label = ui.label("offset");
                changed |= ui
                    .add(egui::DragValue::new(&mut t.offset.x).speed(0.01))
                    .labelled_by(label.id)
                    .changed();
                changed |= ui
                    .add(egui::DragValue::new(&mut t.offset.y).speed(0.01))
                    .changed();
            });
            ui.horizontal(|ui| {
                let label = ui.label("scale");
                changed |= ui
                    .add(egui::DragValue::new(&mut t.scale.x).speed(0.01))
                    .labelled_by(label.id)
                    .changed();
                changed |= ui
                    .add(egui::DragValue::new(&mut t.scale.y).speed(0.01))
                    .changed();
            });
            ui.horizontal(|ui| {
                let label = ui.label("rotation °");
                let mut deg = t.rotation.to_degrees();
                if ui
                    .add(egui::DragValue::new(&mut deg).speed(1.0))
                    .labelled_by(label.id)
                    .changed()
                {
                    t.rotation = deg.to_radians();
                    changed = true;
                }
                if !t.is_identity() && ui.small_button("reset").clicked() {
                    t = UvTransform::IDENTITY;
                    changed = true;
                }
            });
        }
        if slot == Slot::Bump {
            ui.horizontal(|ui| {
                let label = ui.label("height");
                changed |= ui
                    .add(
                        egui::DragValue::new(&mut scale)
                            .speed(0.001)
                            .range(-100.0..=100.0),
                    )
                    .labelled_by(label.id)
                    .on_hover_text(
                        "texels for an image, UV units for a 2D pattern, bounding radii for \
                         a solid texture",
                    )
                    .changed();
            });
        }
    });
    if changed {
        let (t, _) = t.sanitized();
        if let Some(SlotOverride::Source {
            uv_set: u,
            transform: tr,
            scale: sc,
            ..
        }) = s.slots.get_mut(slot)
        {
            (*u, *tr, *sc) = (uv_set, t, if scale.is_finite() { scale } else { 1.0 });
        }
    }
}

/// The texture lab section: one row per slot.
pub(super) fn controls(s: &mut Settings, ui: &mut egui::Ui, id: &str) {
    egui::CollapsingHeader::new("texture lab")
        .id_salt((id, "texture-lab"))
        .show(ui, |ui| {
            ui.label("drawn in the textured mode (and the texture debug views)");
            for slot in SLOTS {
                slot_row(s, ui, id, slot);
            }
            if !s.slots.is_empty() && ui.button("every slot as the model has it").clicked() {
                s.slots = crate::scene::SlotOverrides::default();
            }
        });
}
