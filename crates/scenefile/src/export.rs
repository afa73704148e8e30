//! Renderer state to a file ([`super::SceneFile::from_settings`]): every setting written
//! explicitly (so the experiment does not change when defaults do), numbers as the
//! shortest decimals that read back to the same `f32`, angles in degrees.

use glam::{Vec3, Vec4};

use super::schema::{
    AlphaKind, AttenuationMode, AttenuationSpec, CameraSpec, FogSpec, GroundSpec, Kw, LightSpec,
    LightsMode, MaterialSpec, Rgba, SceneDoc, SectionSpec, ShadowSpec,
};
use super::ModelSource;
use crate::render::{Environment, Lights, Output, Settings, View};
use crate::scene::{AlphaMode, Attenuation, Light, Material, Slot, SlotOverride, TextureSource};
use crate::shade::MAX_HALF_ANGLE;
use crate::texture::Texture;

/// The shortest decimal that reads back (as `f64`, then `as f32`) to `v`.
pub(super) fn tidy(v: f32) -> f64 {
    // Rust's `Display` for f32 is the shortest round-tripping form.
    format!("{v}").parse().unwrap_or(f64::from(v))
}

/// Radians to the shortest degrees that convert back (`to_radians() as f32`) to `rad`.
pub(super) fn tidy_degrees(rad: f32) -> f64 {
    let exact = f64::from(rad).to_degrees();
    for digits in 0..=17 {
        let d: f64 = format!("{exact:.digits$}").parse().unwrap_or(exact);
        if d.to_radians() as f32 == rad {
            return d;
        }
    }
    exact
}

fn v3(v: Vec3) -> [f64; 3] {
    [tidy(v.x), tidy(v.y), tidy(v.z)]
}

fn rgb(v: Vec3) -> Rgba {
    Rgba(v3(v).to_vec())
}

fn rgba(v: Vec4) -> Rgba {
    Rgba(vec![tidy(v.x), tidy(v.y), tidy(v.z), tidy(v.w)])
}

/// The path of an image (its texture's name) if it names an existing file.
fn image_path(t: &Texture) -> Option<String> {
    let p = std::path::Path::new(&t.name);
    (p.is_absolute() && p.is_file()).then(|| t.name.clone())
}

/// The document for a renderer state, and notes on what could not be written.
pub(super) fn doc(
    model: &ModelSource,
    light_scale: f32,
    s: &Settings,
    view: &View,
) -> (SceneDoc, Vec<String>) {
    let mut notes = Vec::new();
    let mut d = SceneDoc {
        size: Some([view.width, view.height]),
        camera: Some(camera(&view.camera)),
        shading: s.shading.map(Kw),
        msaa: Some(s.msaa.into()),
        samples: Some(s.samples.into()),
        ray_depth: (s.ray_depth != crate::render::DEFAULT_RAY_DEPTH).then(|| s.ray_depth.into()),
        background: Some(rgba(s.background)),
        double_sided: Some(s.double_sided),
        wireframe_overlay: Some(s.wireframe_overlay),
        vertex_blinn: s.vertex_lighting.blinn.then_some(true),
        flat_last_vertex: s.vertex_lighting.provoking_vertex.then_some(true),
        single_scatter: Some(s.single_scatter),
        overdraw: Some(s.output == Output::Overdraw),
        subpixel_bits: Some(u32::from(s.subpixel_bits).into()),
        point_size: (s.point_size != 1.0).then(|| tidy(s.point_size)),
        line_width: (s.line_width != 1.0).then(|| tidy(s.line_width)),
        filter: s.filter.map(Kw),
        tone: Some(Kw(s.tone)),
        exposure: (s.exposure != 0.0).then(|| tidy(s.exposure)),
        env_background: s.env_background.map(tidy),
        light_scale: (light_scale != 1.0).then(|| tidy(light_scale)),
        ..SceneDoc::default()
    };
    match &s.environment {
        Environment::Auto => {}
        Environment::Off => d.env = Some("none".into()),
        Environment::On(view) => {
            let name = view.env.name();
            if crate::texture::env::BUILTIN_NAMES.contains(&name) {
                d.env = Some(name.to_owned());
            } else {
                notes.push(format!(
                    "the environment image '{name}' is not written (its path is not kept); \
                     add `env = \"PATH\"`"
                ));
            }
            if view.rotation_deg != crate::texture::env::DEFAULT_ROTATION_DEG {
                d.env_rotate = Some(tidy(view.rotation_deg));
            }
            if view.intensity != 1.0 {
                d.env_intensity = Some(tidy(view.intensity));
            }
        }
    }
    match model {
        ModelSource::Demo => d.model = Some("demo".into()),
        ModelSource::File(p) => {
            d.model = Some(
                std::fs::canonicalize(p)
                    .unwrap_or_else(|_| p.clone())
                    .display()
                    .to_string(),
            );
        }
        ModelSource::Primitive(p) => d.primitive = Some(p.clone()),
    }
    // A source is written as its procedural name, or an image by its path.
    let spec = |src: &TextureSource, notes: &mut Vec<String>| match src {
        TextureSource::Image(t) => {
            let p = image_path(t);
            if p.is_none() {
                notes.push(format!(
                    "the texture '{}' is not an image file; left out",
                    t.name
                ));
            }
            p
        }
        TextureSource::Procedural(_) => Some(src.spec()),
    };
    for (slot, o) in s.slots.iter() {
        match (slot, o) {
            (Slot::BaseColor, SlotOverride::Source { source, .. }) => {
                d.texture = spec(source, &mut notes);
            }
            (Slot::Bump, SlotOverride::Source { source, scale, .. }) => {
                // In `bump`, `noise:X` means the height X (given by `bump_scale` here):
                // the noise is written by name, with its default octaves.
                d.bump = match source {
                    TextureSource::Procedural(p) if p.source().name() == "noise" => {
                        if p.source() != &crate::texture::Procedural::noise(5) {
                            notes.push("the bump noise is saved with its default octaves".into());
                        }
                        Some("noise".into())
                    }
                    _ => spec(source, &mut notes),
                };
                d.bump_scale = d.bump.as_ref().map(|_| tidy(*scale));
            }
            (Slot::Normal, SlotOverride::Off) => d.normal_map = Some(false),
            (slot, _) => notes.push(format!(
                "the {} slot's replacement is not saved (scene files have no key for it)",
                slot.name()
            )),
        }
    }
    if s.kernel.is_some() {
        notes.push("the kernel choice is not saved (it depends on the machine)".into());
    }
    match &s.lights {
        Lights::Auto => d.lights = Some(Kw(LightsMode::Auto)),
        Lights::Custom {
            lights,
            follow_camera,
        } => {
            d.lights = Some(Kw(LightsMode::Custom));
            d.lights_follow_camera = Some(*follow_camera);
            d.light = lights
                .iter()
                .enumerate()
                .map(|(i, l)| light(i, l, &mut notes))
                .collect();
        }
    }
    if let Some(ms) = &s.materials {
        d.material = ms.iter().enumerate().map(|(i, m)| material(i, m)).collect();
    }
    d.fog = s.fog.map(|f| FogSpec {
        color: Some(rgb(f.color)),
        near: tidy(f.near),
        far: tidy(f.far),
        distance: Some(Kw(f.distance)),
    });
    d.shadow = Some(ShadowSpec {
        size: Some(s.shadow.size.into()),
        pcf: Some(s.shadow.pcf.into()),
        bias: Some(tidy(s.shadow.bias)),
        slope: Some(tidy(s.shadow.slope)),
        all_lights: None,
    });
    d.ground = s.ground.map(|g| GroundSpec {
        on: Some(true),
        color: Some(rgb(g.color)),
        extent: Some(tidy(g.extent)),
    });
    d.section = (!s.sections.is_empty()).then(|| SectionSpec {
        planes: s
            .sections
            .planes
            .iter()
            .map(|p| p.to_array().map(tidy))
            .collect(),
        caps: Some(s.sections.cap.is_some()),
        cap_color: s.sections.cap.map(rgb),
    });
    d.material_variant.clone_from(&s.variant);
    d.hidden = s
        .hidden
        .iter()
        .map(|k| super::schema::Count(k as f64))
        .collect();
    (d, notes)
}

fn camera(c: &crate::scene::Camera) -> CameraSpec {
    CameraSpec {
        eye: Some(v3(c.eye)),
        target: Some(v3(c.target)),
        up: Some(v3(c.up)),
        yfov: Some(tidy_degrees(c.yfov)),
        near: Some(tidy(c.near)),
        far: Some(tidy(c.far)),
        ortho: c.ortho.map(tidy),
        ..CameraSpec::default()
    }
}

fn light(i: usize, l: &Light, notes: &mut Vec<String>) -> LightSpec {
    let clamp = |a: f32, what: &str, notes: &mut Vec<String>| {
        if a > MAX_HALF_ANGLE {
            notes.push(format!(
                "light {i}: {what} {} degrees written as the largest, {}",
                a.to_degrees(),
                MAX_HALF_ANGLE.to_degrees()
            ));
            MAX_HALF_ANGLE
        } else {
            a.max(0.0)
        }
    };
    let image = l.image.as_ref().and_then(|t| {
        let p = image_path(t);
        if p.is_none() {
            notes.push(format!(
                "light {i}: its image '{}' is not an image file; left out",
                t.name
            ));
        }
        p
    });
    let attenuation = match l.attenuation {
        Attenuation::None => None,
        a => Some(AttenuationSpec {
            mode: Kw(match a {
                Attenuation::None => AttenuationMode::None,
                Attenuation::Linear { .. } => AttenuationMode::Linear,
                Attenuation::InverseSquare => AttenuationMode::InverseSquare,
                Attenuation::Range(_) => AttenuationMode::Range,
            }),
            near: match a {
                Attenuation::Linear { near, .. } => Some(tidy(near)),
                _ => None,
            },
            far: match a {
                Attenuation::Linear { far, .. } => Some(tidy(far)),
                _ => None,
            },
            range: match a {
                Attenuation::Range(r) => Some(tidy(r)),
                _ => None,
            },
        }),
    };
    LightSpec {
        kind: Kw(l.kind),
        name: (!l.name.is_empty()).then(|| l.name.to_string()),
        color: Some(rgb(l.color)),
        intensity: Some(tidy(l.intensity)),
        position: Some(v3(l.position)),
        direction: Some(v3(l.direction)),
        target: None,
        inner: Some(tidy_degrees(clamp(l.inner.min(l.outer), "inner", notes))),
        outer: Some(tidy_degrees(clamp(l.outer, "outer", notes))),
        rect: Some([
            tidy_degrees(clamp(l.rect.x, "rect", notes)),
            tidy_degrees(clamp(l.rect.y, "rect", notes)),
        ]),
        up: Some(v3(l.up)),
        image,
        attenuation,
        shadow: Some(l.shadow),
    }
}

fn material(i: usize, m: &Material) -> MaterialSpec {
    let (alpha_mode, alpha_cutoff) = match m.alpha_mode {
        AlphaMode::Opaque => (AlphaKind::Opaque, None),
        AlphaMode::Blend => (AlphaKind::Blend, None),
        // A cutoff above 1 discards what 1 discards but alpha exactly 1.
        AlphaMode::Mask(c) => (AlphaKind::Mask, Some(tidy(c.clamp(0.0, 1.0)))),
    };
    MaterialSpec {
        index: Some(i),
        name: None,
        base_color: Some(rgba(m.base_color)),
        specular: Some(rgb(m.specular)),
        // The renderer clamps the exponent to 1..=2000 (and so does the file).
        shininess: Some(tidy(if m.shininess.is_finite() {
            m.shininess.clamp(1.0, 2000.0)
        } else {
            1.0
        })),
        ambient: Some(rgb(m.ambient)),
        double_sided: Some(m.double_sided),
        alpha_mode: Some(Kw(alpha_mode)),
        alpha_cutoff,
    }
}
