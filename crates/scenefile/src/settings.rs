//! A checked file to [`Settings`]: [`SceneFile::check`] (everything that needs no model),
//! [`SceneFile::settings`] and the light-list helpers the command line shares.

use super::convert::{self, color, ranged, Bad};
use super::schema::LightsMode;
use super::{
    ModelSource, SceneFile, SceneFileError, MAX_LIGHTS, MAX_PIXELS, MAX_SIDE, MAX_VARIANTS,
};
use crate::render::{Environment, Ground, Lights, Output, Sections, Settings, VertexLighting};
use crate::scene::{Light, Scene, Slot, SlotOverride, SlotOverrides, TextureSource};
use crate::shade::{Fog, ShadowSettings};

impl SceneFile {
    /// What the file draws, with a model path resolved against the file's folder.
    ///
    /// # Errors
    /// Neither or both of `model` and `[primitive]`, or an empty model path.
    pub fn model(&self) -> Result<ModelSource, SceneFileError> {
        match (&self.doc.model, &self.doc.primitive) {
            (Some(_), Some(_)) => Err(self.invalid("model", "give model or [primitive], not both")),
            (None, None) => Err(self.invalid(
                "model",
                "missing: set model = \"PATH\" (relative to this file) or \"demo\", or a [primitive] table",
            )),
            (Some(m), None) if m.trim().is_empty() => Err(self.invalid("model", "is empty")),
            (Some(m), None) if m == "demo" => Ok(ModelSource::Demo),
            (Some(m), None) => Ok(ModelSource::File(self.resolve_path(m))),
            (None, Some(p)) => Ok(ModelSource::Primitive(p.clone())),
        }
    }

    /// Checks everything that does not need the model.
    pub(super) fn check(&self) -> Result<(), SceneFileError> {
        let err = |(key, reason): Bad| self.invalid(key, reason);
        let d = &self.doc;
        self.model()?;
        if let Some(p) = &d.primitive {
            convert::check_primitive(p).map_err(|r| self.invalid("primitive", r))?;
        }
        if let Some(s) = d.light_scale {
            ranged("light_scale", s, 0.0, 1e9).map_err(err)?;
        }
        if let Some([w, h]) = d.size {
            if !(1..=MAX_SIDE).contains(&w) || !(1..=MAX_SIDE).contains(&h) {
                return Err(self.invalid(
                    "size",
                    format!("{w}x{h}: each side must be 1 to {MAX_SIDE}"),
                ));
            }
            let px = u64::from(w) * u64::from(h) * d.msaa.map_or(1.0, |c| c.0).max(1.0) as u64;
            if px > MAX_PIXELS {
                return Err(self.invalid(
                    "size",
                    format!(
                        "{w}x{h} with {}x multisampling is {px} samples; at most {MAX_PIXELS}",
                        d.msaa.map_or(1.0, |c| c.0)
                    ),
                ));
            }
        }
        if let Some(o) = &d.output {
            if o.trim().is_empty() {
                return Err(self.invalid("output", "is empty"));
            }
        }
        if let Some(c) = &d.camera {
            convert::check_camera(c).map_err(|(k, r)| self.invalid(format!("camera.{k}"), r))?;
        }
        if d.light.len() > MAX_LIGHTS {
            return Err(self.invalid(
                "light",
                format!("{} lights; at most {MAX_LIGHTS}", d.light.len()),
            ));
        }
        for (i, l) in d.light.iter().enumerate() {
            convert::light(&format!("light[{i}]"), l).map_err(err)?;
        }
        if d.lights.map(|m| m.0) == Some(LightsMode::Auto) && !d.light.is_empty() {
            return Err(self.invalid("lights", "is \"auto\" (the model's lights or the default rig), but the file lists [[light]]s"));
        }
        if d.lights_follow_camera.is_some() && self.lights_mode() == LightsMode::Auto {
            return Err(self.invalid(
                "lights_follow_camera",
                "needs lights = \"custom\" or a [[light]]",
            ));
        }
        for (i, m) in d.material.iter().enumerate() {
            convert::check_material(&format!("material[{i}]"), m).map_err(err)?;
        }
        self.base_settings(false)?;
        if let Some(c) = &d.compare {
            self.check_compare(c)?;
        }
        Ok(())
    }

    /// `auto` unless the file says `custom` or lists lights.
    fn lights_mode(&self) -> LightsMode {
        match self.doc.lights {
            Some(m) => m.0,
            None if self.doc.light.is_empty() => LightsMode::Auto,
            None => LightsMode::Custom,
        }
    }

    /// The settings the file describes, with material overrides applied to `scene`'s
    /// materials and images loaded.
    ///
    /// # Errors
    /// A material override the model cannot take, or an image that cannot be loaded.
    pub fn settings(&self, scene: &Scene) -> Result<Settings, SceneFileError> {
        let mut s = self.base_settings(true)?;
        if !self.doc.material.is_empty() {
            let mut materials = scene.materials.clone();
            convert::materials("material", &self.doc.material, &mut materials)
                .map_err(|(k, r)| self.invalid(k, format!("{r} (model {})", scene.report.file)))?;
            s.materials = Some(materials);
        }
        if self.doc.shadow.as_ref().and_then(|s| s.all_lights) == Some(true) {
            s.lights = shadow_every_light(&s.lights, &scene.lights);
        }
        if let Some(v) = &s.variant {
            if !scene.variants.contains(v) {
                return Err(self.invalid(
                    "material_variant",
                    format!(
                        "'{v}' is not a material variant of {} ({})",
                        scene.report.file,
                        variant_list(&scene.variants)
                    ),
                ));
            }
        }
        let parts = scene.instances.len();
        if let Some((i, k)) = s.hidden.iter().enumerate().find(|&(_, k)| k >= parts) {
            return Err(self.invalid(
                format!("hidden[{i}]"),
                format!(
                    "the model has {parts} part(s) (0 to {}), not {k} (model {})",
                    parts.saturating_sub(1),
                    scene.report.file
                ),
            ));
        }
        Ok(s)
    }

    /// The `texture`, `bump` and `bump_scale` keys (under `prefix`, e.g. `compare.variant[2].`)
    /// into `slots`: each names a procedural texture or an image file (relative to the scene
    /// file).
    pub(super) fn apply_maps(
        &self,
        prefix: &str,
        texture: Option<&str>,
        bump: Option<&str>,
        bump_scale: Option<f64>,
        slots: &mut SlotOverrides,
    ) -> Result<(), SceneFileError> {
        let key = |k: &str| format!("{prefix}{k}");
        let image = |written: &str, k: &str, srgb: bool| {
            convert::image_as(&self.resolve_path(written), srgb)
                .map_err(|e| self.invalid(key(k), e.to_string()))
        };
        if let Some(t) = texture {
            let source =
                TextureSource::from_spec(t, Slot::BaseColor, |_, srgb| image(t, "texture", srgb))
                    .map_err(|e| self.invalid(key("texture"), e))?;
            slots.set(Slot::BaseColor, Some(SlotOverride::source(source, 1.0)));
        }
        if let Some(b) = bump {
            let (source, scale) =
                TextureSource::bump_from_spec(b, |_, srgb| image(b, "bump", srgb))
                    .map_err(|e| self.invalid(key("bump"), e))?;
            let scale = match bump_scale {
                Some(x) if prefix.is_empty() => self.number("bump_scale", x)? as f32,
                Some(x) => crate::render::numeric("bump_scale")
                    .check(x)
                    .map_err(|m| self.invalid(key("bump_scale"), m))?
                    as f32,
                None => scale,
            };
            slots.set(Slot::Bump, Some(SlotOverride::source(source, scale)));
        }
        Ok(())
    }

    /// Everything but the materials; images are loaded only with `load_images`.
    fn base_settings(&self, load_images: bool) -> Result<Settings, SceneFileError> {
        let err = |(key, reason): Bad| self.invalid(key, reason);
        let d = &self.doc;
        let mut s = Settings {
            shading: d.shading.map(|m| m.0),
            wireframe_overlay: d.wireframe_overlay.unwrap_or(false),
            double_sided: d.double_sided.unwrap_or(false),
            vertex_lighting: VertexLighting {
                blinn: d.vertex_blinn.unwrap_or(false),
                provoking_vertex: d.flat_last_vertex.unwrap_or(false),
            },
            filter: d.filter.map(|f| f.0),
            tone: d.tone.map_or_else(Default::default, |t| t.0),
            single_scatter: d.single_scatter.unwrap_or(false),
            ..Settings::default()
        };
        if let Some(ev) = d.exposure {
            s.exposure = self.number("exposure", ev)? as f32;
        }
        if let Some(name) = &d.env {
            let builtin = matches!(name.as_str(), "none" | "off")
                || crate::texture::env::EnvImage::builtin(name).is_some();
            if builtin || load_images {
                let cache = crate::texture::env::default_cache_dir();
                let (env, note) =
                    Environment::named(name, |p| self.resolve_path(p), cache.as_deref())
                        .map_err(|e| self.invalid("env", e))?;
                if let Some(note) = note {
                    eprintln!("note: {}: env: {note}", self.path.display());
                }
                s.environment = env;
            }
        }
        let rotate = d
            .env_rotate
            .map(|v| self.number("env_rotate", v))
            .transpose()?;
        let intensity = d
            .env_intensity
            .map(|v| self.number("env_intensity", v))
            .transpose()?;
        if rotate.is_some() || intensity.is_some() {
            let key = if rotate.is_some() {
                "env_rotate"
            } else {
                "env_intensity"
            };
            s.environment = std::mem::take(&mut s.environment)
                .adjusted(rotate.map(|v| v as f32), intensity.map(|v| v as f32))
                .map_err(|e| self.invalid(key, e))?;
        }
        if let Some(b) = d.env_background {
            s.env_background = Some(self.number("env_background", b)? as f32);
        }
        if d.overdraw == Some(true) {
            s.output = Output::Overdraw;
        }
        if let Some(b) = &d.background {
            s.background = color("background", b, 1.0, true).map_err(err)?;
        }
        if let Some(bits) = d.subpixel_bits {
            s.subpixel_bits = self.number("subpixel_bits", bits.0)? as u8;
        }
        if let Some(px) = d.point_size {
            s.point_size = self.number("point_size", px)? as f32;
        }
        if let Some(px) = d.line_width {
            s.line_width = self.number("line_width", px)? as f32;
        }
        if let Some(n) = d.samples {
            s.samples = self.number("samples", n.0)? as u32;
        }
        if let Some(n) = d.ray_depth {
            s.ray_depth = self.number("ray_depth", n.0)? as u32;
        }
        if let Some(n) = d.msaa {
            s.msaa = self.number("msaa", n.0)? as u32;
        }
        let load = |written: &str, key: &str| {
            convert::image(&self.resolve_path(written))
                .map_err(|source| SceneFileError::Load {
                    path: self.path.clone(),
                    source,
                })
                .map_err(|e| match e {
                    SceneFileError::Load { source, .. } => self.invalid(key, source.to_string()),
                    other => other,
                })
        };
        if load_images {
            self.apply_maps(
                "",
                d.texture.as_deref(),
                d.bump.as_deref(),
                d.bump_scale,
                &mut s.slots,
            )?;
        }
        if d.normal_map == Some(false) {
            s.slots.set(Slot::Normal, Some(SlotOverride::Off));
        }
        if self.lights_mode() == LightsMode::Custom {
            let mut lights = Vec::with_capacity(d.light.len());
            for (i, spec) in d.light.iter().enumerate() {
                let key = format!("light[{i}]");
                let mut l = convert::light(&key, spec).map_err(err)?;
                if let (Some(p), true) = (&spec.image, load_images) {
                    l.image = Some(load(p, &format!("{key}.image"))?);
                }
                lights.push(l);
            }
            s.lights = Lights::Custom {
                lights,
                follow_camera: d.lights_follow_camera.unwrap_or(false),
            };
        }
        if let Some(f) = &d.fog {
            let mut fog = Fog {
                near: self.number("fog.near", f.near)? as f32,
                far: self.number("fog.far", f.far)? as f32,
                distance: f.distance.map_or_else(Default::default, |k| k.0),
                ..Fog::default()
            };
            if fog.near >= fog.far {
                return Err(self.invalid(
                    "fog.near",
                    format!("{} is not below far ({})", f.near, f.far),
                ));
            }
            if let Some(c) = &f.color {
                fog.color = color("fog.color", c, 1.0, false).map_err(err)?.truncate();
            }
            s.fog = Some(fog);
        }
        if let Some(sh) = &d.shadow {
            let dflt = ShadowSettings::default();
            let number =
                |key: &str, v: Option<f64>, dflt: f64| v.map_or(Ok(dflt), |v| self.number(key, v));
            s.shadow = ShadowSettings {
                size: number("shadow.size", sh.size.map(|c| c.0), f64::from(dflt.size))? as u32,
                pcf: number("shadow.pcf", sh.pcf.map(|c| c.0), f64::from(dflt.pcf))? as u32,
                bias: number("shadow.bias", sh.bias, f64::from(dflt.bias))? as f32,
                slope: number("shadow.slope", sh.slope, f64::from(dflt.slope))? as f32,
            };
        }
        if let Some(g) = &d.ground {
            let dflt = Ground::default();
            let ground = Ground {
                color: g
                    .color
                    .as_ref()
                    .map_or(Ok(dflt.color), |c| {
                        color("ground.color", c, 1.0, false).map(|c| c.truncate())
                    })
                    .map_err(err)?,
                extent: match g.extent {
                    Some(e) => self.number("ground.extent", e)? as f32,
                    None => dflt.extent,
                },
            };
            s.ground = g.on.unwrap_or(true).then_some(ground);
        }
        if let Some(sec) = &d.section {
            s.sections = self.sections(sec)?;
        }
        s.variant.clone_from(&d.material_variant);
        for (i, k) in d.hidden.iter().enumerate() {
            let max = crate::render::Hidden::MAX_INSTANCE;
            if !(k.0.fract() == 0.0 && (0.0..=max as f64).contains(&k.0)) {
                return Err(self.invalid(
                    format!("hidden[{i}]"),
                    format!(
                        "{} is not an instance number (a whole number from 0 to {max})",
                        k.0
                    ),
                ));
            }
            s.hidden.set(k.0 as usize, true);
        }
        Ok(s)
    }

    /// `[section]` as settings.
    fn sections(&self, sec: &super::schema::SectionSpec) -> Result<Sections, SceneFileError> {
        let mut out = Sections::default();
        for (i, p) in sec.planes.iter().enumerate() {
            let key = format!("section.planes[{i}]");
            let [x, y, z, d] = p.map(|v| v as f32);
            Sections::plane(glam::Vec3::new(x, y, z), d)
                .and_then(|pl| out.push(pl))
                .map_err(|e| self.invalid(key, e))?;
        }
        if let Some(c) = &sec.cap_color {
            out.cap = Some(
                color("section.cap_color", c, 1.0, false)
                    .map_err(|(key, reason)| self.invalid(key, reason))?
                    .truncate(),
            );
        }
        if sec.caps == Some(false) {
            out.cap = None;
        }
        Ok(out)
    }

    fn check_compare(&self, c: &super::schema::CompareSpec) -> Result<(), SceneFileError> {
        let n = c.variant.len();
        if !(1..=MAX_VARIANTS).contains(&n) {
            return Err(self.invalid(
                "compare.variant",
                format!("{n} variants; 1 to {MAX_VARIANTS} are drawn"),
            ));
        }
        let layout = super::compare::Layout::new(c, self.size().unwrap_or(super::DEFAULT_SIZE))
            .map_err(|(k, r)| self.invalid(format!("compare.{k}"), r))?;
        let _ = layout;
        for (i, v) in c.variant.iter().enumerate() {
            let key = format!("compare.variant[{i}]");
            if v.label.trim().is_empty() {
                return Err(self.invalid(format!("{key}.label"), "is empty"));
            }
            for (j, m) in v.material.iter().enumerate() {
                convert::check_material(&format!("{key}.material[{j}]"), m)
                    .map_err(|(k, r)| self.invalid(k, r))?;
            }
        }
        Ok(())
    }
}

/// `lights` with shadows turned on for every light that can cast them. The automatic
/// choice becomes explicit: the scene's own lights (world space), or the default rig
/// attached to the camera when the scene has none.
#[must_use]
pub fn shadow_every_light(lights: &Lights, scene_lights: &[Light]) -> Lights {
    let (mut lights, follow_camera) = explicit(lights, scene_lights);
    for l in lights.iter_mut().filter(|l| l.kind.can_shadow()) {
        l.shadow = true;
    }
    Lights::Custom {
        lights,
        follow_camera,
    }
}

/// `lights` with `extra` added (in the space of the list: world, or camera space when it
/// follows the camera). Added to an automatic choice, they join the scene's own lights, or
/// replace the default rig when the scene has none.
#[must_use]
pub fn add_lights(lights: &Lights, scene_lights: &[Light], extra: &[Light]) -> Lights {
    let (mut lights, follow_camera) = match lights {
        Lights::Auto if scene_lights.is_empty() => (Vec::new(), false),
        other => explicit(other, scene_lights),
    };
    lights.extend_from_slice(extra);
    Lights::Custom {
        lights,
        follow_camera,
    }
}

/// [`Lights::Auto`] spelled out as a list and whether it follows the camera: the scene's
/// lights, or the camera-attached rig.
fn explicit(lights: &Lights, scene_lights: &[Light]) -> (Vec<Light>, bool) {
    match lights {
        Lights::Custom {
            lights,
            follow_camera,
        } => (lights.clone(), *follow_camera),
        Lights::Auto if scene_lights.is_empty() => (Light::default_rig(glam::Mat3::IDENTITY), true),
        Lights::Auto => (scene_lights.to_vec(), false),
    }
}

/// A model's material variants for a message: "it has: a, b" or "it has none".
#[must_use]
pub fn variant_list(variants: &[String]) -> String {
    if variants.is_empty() {
        "it has none".into()
    } else {
        format!("it has: {}", variants.join(", "))
    }
}
