//! The pixel probe section: what the clicked pixel shows and how it was lit, re-shaded for
//! that pixel alone by the renderer's lighting code ([`crate::render::probe`]), with the
//! colour in linear RGB, sRGB, HSV, L*a*b* and xy, and each light's diffuse and specular
//! share.

use eframe::egui::{self, Color32, RichText};
use glam::Vec3;

use super::{row, Cx, Dock, Panel, Side};
use crate::color::{self, rgb_to_hsv, srgb_decode, srgb_encode, xyz_to_xyy};

fn v3(v: Vec3) -> String {
    format!("{:.3} {:.3} {:.3}", v.x, v.y, v.z)
}

/// A swatch of a linear colour.
fn swatch(ui: &mut egui::Ui, linear: Vec3) {
    let e = |v: f32| color::srgb8_f64(f64::from(v));
    let (rect, _) = ui.allocate_exact_size(egui::vec2(28.0, 14.0), egui::Sense::hover());
    ui.painter().rect_filled(
        rect,
        2.0,
        Color32::from_rgb(e(linear.x), e(linear.y), e(linear.z)),
    );
}

/// The colour of a linear RGB value in the models the textbook names.
fn colour_rows(ui: &mut egui::Ui, linear: Vec3) {
    let lin = linear.to_array().map(f64::from);
    let clipped = lin.map(|v| v.clamp(0.0, 1.0));
    let enc = clipped.map(srgb_encode);
    let hsv = rgb_to_hsv(enc);
    let lab = color::srgb_to_lab(enc);
    let xyy = xyz_to_xyy(color::srgb_to_xyz(enc));
    let bytes = enc.map(|v| (v * 255.0).round() as u8);
    row(
        ui,
        "linear RGB",
        format!("{:.4} {:.4} {:.4}", lin[0], lin[1], lin[2]),
    );
    row(
        ui,
        "sRGB",
        format!(
            "#{:02x}{:02x}{:02x}  ({} {} {})",
            bytes[0], bytes[1], bytes[2], bytes[0], bytes[1], bytes[2]
        ),
    );
    row(
        ui,
        "HSV",
        format!("h {:.1}°  s {:.3}  v {:.3}", hsv[0] * 360.0, hsv[1], hsv[2]),
    );
    row(
        ui,
        "L*a*b*",
        format!("{:.2} {:.2} {:.2}", lab[0], lab[1], lab[2]),
    );
    row(
        ui,
        "xy (Y)",
        format!("{:.4} {:.4} ({:.4})", xyy[0], xyy[1], xyy[2]),
    );
    if lin.iter().any(|v| *v > 1.0) {
        row(ui, "note", "above 1: clamped on screen".into());
    }
}

/// The pixel probe section (the probed pixel is in [`super::Shared`]: the viewport's click
/// sets it).
pub struct ProbePanel;

impl Panel for ProbePanel {
    fn dock(&self) -> Dock {
        Dock::Right
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        let open = std::mem::take(&mut cx.shared.open_probe).then_some(true);
        egui::CollapsingHeader::new("Pixel probe")
            .default_open(true)
            .open(open)
            .show(ui, |ui| show(ui, cx));
    }
}

/// The probe section's body.
fn show(ui: &mut egui::Ui, cx: &Cx<'_>) {
    let Some(pv) = cx.shared.probe.clone() else {
        ui.label("Click a pixel to probe it: position, depth, normal, UV, what was drawn there, its colour and each light's share, recomputed for that pixel.");
        return;
    };
    ui.label(format!(
        "pixel ({}, {}) of {}x{}{}",
        pv.pixel[0],
        pv.pixel[1],
        pv.frame_size[0],
        pv.frame_size[1],
        if pv.side == Side::B {
            ", right half (B)"
        } else {
            ""
        }
    ));
    if let Some(rgb) = pv.shown_rgb {
        ui.horizontal(|ui| {
            ui.label("on screen");
            let lin = Vec3::from_array(rgb.map(|c| srgb_decode(f64::from(c) / 255.0) as f32));
            swatch(ui, lin);
            ui.monospace(format!("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]));
        });
    }
    let Some(p) = &pv.probe else {
        ui.label("background: the ray through this pixel meets nothing");
        return;
    };
    let scene = cx.session.scene.scene();
    let inst = scene.instances.get(p.instance);
    let mesh = scene.meshes.get(p.mesh);
    let material = p.material.and_then(|m| scene.materials.get(m));
    egui::Grid::new("probe-geometry")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            row(
                ui,
                "instance",
                format!("{} ({})", p.instance, inst.map_or("", |i| i.name.as_str())),
            );
            row(
                ui,
                "mesh",
                format!("{} ({})", p.mesh, mesh.map_or("", |m| m.name.as_str())),
            );
            row(
                ui,
                "material",
                material.map_or("default".into(), |m| {
                    format!("{} ({})", p.material.unwrap_or(0), m.name)
                }),
            );
            row(
                ui,
                "triangle / facet",
                format!("{} / {}", p.triangle, p.facet),
            );
            row(
                ui,
                "shading",
                format!("{}{}", p.mode, if p.front { "" } else { ", back face" }),
            );
            row(ui, "position", v3(p.position));
            row(ui, "view depth", format!("{:.5}", p.view_depth));
            row(ui, "depth (z/w)", format!("{:.7}", p.depth));
            if let Some(d) = pv.buffer_depth {
                row(
                    ui,
                    "depth buffer",
                    format!("{d:.7} (Δ {:.1e})", (d - p.depth).abs()),
                );
            }
            row(ui, "normal", v3(p.normal));
            row(ui, "face normal", v3(p.face_normal));
            row(ui, "barycentric", v3(p.barycentric));
            row(
                ui,
                "UV",
                p.uv.map_or("none".into(), |uv| format!("({:.4}, {:.4})", uv.x, uv.y)),
            );
            row(
                ui,
                "diffuse colour",
                format!(
                    "{:.3} {:.3} {:.3}, alpha {:.3}",
                    p.base.x, p.base.y, p.base.z, p.base.w
                ),
            );
        });
    ui.separator();
    ui.horizontal(|ui| {
        ui.label(RichText::new("Re-shaded colour").strong());
        swatch(ui, p.color);
    });
    if p.mode == crate::shade::Shading::Path {
        ui.add(
            egui::Label::new(format!(
                "(the path tracer's estimate: the mean of the pixel's first {} paths, before \
                 tone mapping; the rows below are the direct light alone)",
                crate::render::path::PROBE_PATHS
            ))
            .wrap(),
        );
    } else if !matches!(
        p.mode,
        crate::shade::Shading::Phong
            | crate::shade::Shading::Blinn
            | crate::shade::Shading::Textured
    ) {
        ui.label(format!(
            "(per-pixel lighting; this pixel was drawn in {} mode)",
            p.mode
        ));
    }
    egui::Grid::new("probe-colour")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| colour_rows(ui, p.color));
    ui.separator();
    light_shares(ui, p);
    if !p.rays.is_empty() {
        ui.separator();
        ray_steps(ui, p, scene);
    }
}

/// The pixel's rays, one row per ray in the order the tracer casts them (indented by
/// bounce): what it met and its share. In Whitted's model the whole ray tree of the
/// pixel's centre; in the path tracer the pixel's first path.
fn ray_steps(ui: &mut egui::Ui, p: &crate::render::Probe, scene: &crate::scene::Scene) {
    use crate::render::{RayHit, RayKind};
    let (title, about) = if p.mode == crate::shade::Shading::Path {
        (
            "First path (the textbook's §9.6: the rendering equation by random paths)",
            "the pixel's first path, as the renderer traced it (its sample 0): at each \
             bounce the ray, the next-event rays towards each light, a point drawn on an \
             emitter and a direction drawn from the environment, then the direction drawn \
             from the BRDF (or refracted), to the depth limit and Russian roulette",
        )
    } else {
        (
            "Rays (Whitted, the textbook's §9.6.1)",
            "every ray traced for this pixel's centre: the primary ray, then from each hit \
             its shadow rays and the reflection and refraction it spawns, to the depth and \
             contribution limits",
        )
    };
    ui.add(egui::Label::new(RichText::new(title).strong()).wrap())
        .on_hover_text(about);
    egui::Grid::new("probe-rays")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            for (h, what) in [
                ("ray", "why it was cast, indented by bounce"),
                ("met", "what it hit, and how far along the ray"),
                (
                    "share",
                    "of its parent's colour (Fresnel, the metal's colour, the part \
                     transmitted); the pixel's share on hover",
                ),
            ] {
                ui.label(RichText::new(h).italics()).on_hover_text(what);
            }
            ui.end_row();
            for r in &p.rays {
                let kind = match r.kind {
                    RayKind::Primary => "primary",
                    RayKind::Reflection => "reflection",
                    RayKind::Refraction => "refraction",
                    RayKind::Shadow => "shadow",
                    RayKind::Bounce => "bounce",
                    RayKind::LightSample => "light sample",
                };
                ui.monospace(format!("{}{kind}", "  ".repeat(r.depth as usize)));
                ui.label(match &r.hit {
                    RayHit::Surface {
                        instance,
                        material,
                        triangle,
                        t,
                        ..
                    } => {
                        let name = scene.instances.get(*instance).map_or("", |i| &i.name);
                        let m = material
                            .and_then(|m| scene.materials.get(m))
                            .map_or("default material".into(), |m| format!("'{}'", m.name));
                        format!("instance {instance} '{name}', {m}, triangle {triangle}, t {t:.4}")
                    }
                    RayHit::Environment => "nothing: the environment".into(),
                    RayHit::Background => "nothing: the background".into(),
                    RayHit::Light { index, lit } if *lit > 0.0 => format!("light {index}: lit"),
                    RayHit::Light { index, .. } => format!("light {index}: blocked"),
                    RayHit::Emitter {
                        instance,
                        triangle,
                        lit,
                    } => {
                        let name = scene.instances.get(*instance).map_or("", |i| &i.name);
                        let state = if *lit { "reached" } else { "blocked" };
                        format!(
                            "emitter: instance {instance} '{name}', triangle {triangle}: {state}"
                        )
                    }
                    RayHit::Sky { lit: true } => "environment sample: open".into(),
                    RayHit::Sky { lit: false } => "environment sample: blocked".into(),
                });
                ui.monospace(v3(r.share))
                    .on_hover_text(format!("of the pixel: {}", v3(r.weight)));
                ui.end_row();
            }
        });
}

/// One row per light of the frame (after attenuation, cone or pyramid, image and shadow),
/// then the ambient term, the fog factor and the final colour.
fn light_shares(ui: &mut egui::Ui, p: &crate::render::Probe) {
    ui.label(RichText::new("Each light's share (linear RGB)").strong());
    egui::Grid::new("probe-lights")
        .num_columns(5)
        .striped(true)
        .show(ui, |ui| {
            // The shares first: the columns to the right may need a sideways scroll.
            for h in ["light", "diffuse", "specular", "shadow", "arriving"] {
                ui.label(RichText::new(h).italics());
            }
            ui.end_row();
            for s in &p.lights {
                let l = &s.light;
                let name = if l.name.is_empty() {
                    format!("light {}: {}", s.index, l.kind())
                } else {
                    format!("light {}: {} '{}'", s.index, l.kind(), l.name)
                };
                ui.label(name);
                ui.monospace(v3(s.diffuse));
                ui.monospace(v3(s.specular));
                ui.monospace(if l.shadow && l.kind.can_shadow() {
                    format!("{:.2}", s.shadow)
                } else {
                    "-".into()
                })
                .on_hover_text("1 lit, 0 in shadow (a ray towards the light); - casts none");
                ui.monospace(v3(s.arriving)).on_hover_text(
                    "radiance arriving after attenuation, cone or pyramid and image, before shadow",
                );
                ui.end_row();
            }
            match p.image_based {
                Some((diffuse, specular)) => {
                    ui.label("image-based");
                    ui.monospace(v3(diffuse)).on_hover_text(
                        "the environment and the ambient light: diffuse (what the specular \
                         lobe leaves), times the occlusion",
                    );
                    ui.monospace(v3(specular)).on_hover_text(
                        "the environment and the ambient light: the split sum's specular, \
                         with multiple scattering, times the occlusion",
                    );
                }
                None => {
                    ui.label("ambient");
                    ui.monospace(v3(p.ambient))
                        .on_hover_text("every ambient light x Ka x Kd; never attenuated");
                }
            }
            ui.end_row();
            if let Some(f) = p.fog {
                ui.label("fog factor");
                ui.monospace(format!("{f:.4}"))
                    .on_hover_text("0 clear, 1 only fog");
                ui.end_row();
            }
            // The shares' total (in `path` the colour is the paths' estimate, which
            // the direct light's shares do not add up to).
            if p.mode != crate::shade::Shading::Path {
                ui.label("colour");
                ui.horizontal(|ui| {
                    swatch(ui, p.color);
                    ui.monospace(v3(p.color));
                });
                ui.end_row();
            }
        });
    if p.lights.is_empty() {
        ui.label("(no light other than ambient reaches this frame)");
    }
    if p.image_based.is_some() && !p.lights.is_empty() {
        brdf_terms(ui, p);
    }
}

/// The glTF BRDF's terms for each light at a `pbr` pixel (Appendix B of the specification).
fn brdf_terms(ui: &mut egui::Ui, p: &crate::render::Probe) {
    ui.label(RichText::new("BRDF terms per light (pbr)").strong());
    // The layers' columns only where a layer reflects something.
    let layers = p
        .lights
        .iter()
        .any(|s| s.sheen != Vec3::ZERO || s.coat != Vec3::ZERO);
    egui::Grid::new("probe-brdf")
        .num_columns(if layers { 6 } else { 4 })
        .striped(true)
        .show(ui, |ui| {
            let mut heads = vec![
                ("light", ""),
                ("D", "GGX normal distribution at N·H"),
                ("G/(4 NL NV)", "Smith height-correlated visibility"),
                (
                    "F",
                    "Fresnel (Schlick), dielectric and metal mixed by metallic",
                ),
            ];
            if layers {
                heads.push((
                    "sheen",
                    "KHR_materials_sheen: the sheen layer's reflection of the light (Charlie)",
                ));
                heads.push((
                    "coat",
                    "KHR_materials_clearcoat: the clear coat's reflection of the light",
                ));
            }
            for (h, what) in heads {
                ui.label(RichText::new(h).italics()).on_hover_text(what);
            }
            ui.end_row();
            for s in &p.lights {
                ui.label(format!("light {}", s.index));
                ui.monospace(format!("{:.4}", s.d));
                ui.monospace(format!("{:.4}", s.vis));
                ui.monospace(v3(s.fresnel));
                if layers {
                    ui.monospace(v3(s.sheen));
                    ui.monospace(v3(s.coat));
                }
                ui.end_row();
            }
        });
}
