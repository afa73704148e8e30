//! The lighting flags shared by `render` and `bench frame`: fog, tone mapping, shadows,
//! the ground plane, extra lights and section planes. Each flag given overrides the scene
//! file.

use anyhow::Result;
use clap::Args;
use glam::{Vec3, Vec4};

use realist::render::numeric;
use realist::render::{Environment, Ground, Sections, Settings, ToneMap};
use realist::scene::Light;
use realist::scenefile;
use realist::shade::{Fog, FogDistance};
use realist::texture::env::default_cache_dir;

#[derive(Args, Clone, Debug, Default)]
pub(crate) struct LightingArgs {
    /// Linear fog: NEAR,FAR[,euclidean|depth][,COLOUR] with COLOUR as R,G,B (linear) or
    /// #rrggbb (sRGB), e.g. 2,12,depth,0.6,0.6,0.7 (distance default euclidean, colour 0.6 grey).
    #[arg(long, value_parser = parse_fog, allow_hyphen_values = true)]
    pub fog: Option<Fog>,
    /// Out-of-range colour: auto (the default: pbr-neutral when every model is drawn in the
    /// pbr mode, as the Khronos glTF Sample Viewer does, else clamp), clamp, scale-max (divide
    /// by the largest channel), reinhard, pbr-neutral (Khronos PBR Neutral), aces-narkowicz or
    /// aces-hill (ACES filmic fits). The background colour is never tone mapped.
    #[arg(long)]
    pub tone: Option<ToneMap>,
    /// Exposure in EV (stops): colours are multiplied by 2^EV before the tone map
    /// (default 0). glTF lights are in lux and candela: a white surface facing a 1-lux
    /// light reflects 1/π.
    #[arg(long, allow_hyphen_values = true, value_parser = numeric("exposure").parser_f32())]
    pub exposure: Option<f32>,
    /// The environment that lights the pbr mode (image-based lighting): studio (the
    /// default), sky, uniform (radiance 1 everywhere), none, or an equirectangular .hdr or
    /// .exr file (prefiltered once and cached by content).
    #[arg(long, value_name = "none|studio|sky|uniform|FILE")]
    pub env: Option<String>,
    /// Turns the environment about +Y by DEG degrees (default 90: the image centre faces
    /// +Z, as the Khronos sample viewer does).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          value_parser = numeric("env_rotate").parser_f32())]
    pub env_rotate: Option<f32>,
    /// Multiplies the environment's radiance (default 1).
    #[arg(long, value_name = "X", allow_hyphen_values = true,
          value_parser = numeric("env_intensity").parser_f32())]
    pub env_intensity: Option<f32>,
    /// Shows the environment behind the model, blurred to roughness BLUR (0 to 1, default
    /// 0: sharp), instead of the background colour.
    #[arg(long, value_name = "BLUR", num_args = 0..=1, default_missing_value = "0",
          allow_hyphen_values = true, value_parser = numeric("env_background").parser_f32())]
    pub env_background: Option<f32>,
    /// Shadows for every light that can cast them (directional, spot, rect); the default
    /// rig or the model's lights become explicit.
    #[arg(long)]
    pub shadows: bool,
    /// Shadow-map size in texels per side (16 to 8192, default 1024).
    #[arg(long, value_parser = numeric("shadow.size").parser_u32())]
    pub shadow_size: Option<u32>,
    /// Percentage-closer filtering radius r: (2r+1)^2 taps (0 to 16, default 1).
    #[arg(long, allow_hyphen_values = true, value_parser = numeric("shadow.pcf").parser_u32())]
    pub pcf: Option<u32>,
    /// Show a ground plane under the model (it catches shadows).
    #[arg(long)]
    pub ground: bool,
    /// Add a light (repeatable); replaces the default rig, joins the model's or the scene
    /// file's lights.
    #[arg(long = "light", value_name = "KIND[:KEY=VALUE]...", value_parser = scenefile::parse_light,
          long_help = light_help(), allow_hyphen_values = true)]
    pub lights: Vec<Light>,
    /// The punctual lights reflect off pbr surfaces by the glTF specification's
    /// single-scattering BRDF, without the compensation for the energy rough surfaces lose
    /// between microfacets (default: compensated, as three.js does; the environment always
    /// is).
    #[arg(long)]
    pub single_scatter: bool,
    /// Cut the model open with the plane NX*x + NY*y + NZ*z + D = 0, removing the side the
    /// normal points away from (repeatable, up to 3 planes; replaces the scene file's). Where
    /// a solid's inside shows, the cut is filled with the cap colour. E.g. `--section
    /// 1,0,0,0` removes everything at x < 0.
    #[arg(long = "section", value_name = "NX,NY,NZ,D", allow_hyphen_values = true,
          value_parser = Sections::parse_plane)]
    pub sections: Vec<Vec4>,
    /// The section caps' colour: R,G,B (linear, 0 to 1) or #rrggbb (sRGB), or `none` to leave
    /// the cut open (default #db6050).
    #[arg(long, value_name = "COLOUR|none", value_parser = parse_cap)]
    pub section_cap: Option<Cap>,
}

/// `--section-cap`: a colour, or none.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cap(Option<Vec3>);

fn parse_cap(s: &str) -> Result<Cap, String> {
    if s.eq_ignore_ascii_case("none") || s.eq_ignore_ascii_case("off") {
        return Ok(Cap(None));
    }
    parse_colour(s)
        .filter(|c| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0)
        .map(|c| Cap(Some(c)))
        .ok_or_else(|| format!("--section-cap {s}: expected R,G,B in 0..1, #rrggbb or none"))
}

/// `R,G,B` (linear) or `#rrggbb` (sRGB) as linear RGB.
fn parse_colour(s: &str) -> Option<Vec3> {
    if s.starts_with('#') {
        let c = realist::overlay::Color::hex(s)?;
        let lin = realist::color::srgb8_decode;
        return Some(Vec3::new(lin(c.r), lin(c.g), lin(c.b)));
    }
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse().ok())
        .collect::<Option<_>>()?;
    match v[..] {
        [r, g, b] => Some(Vec3::new(r, g, b)),
        _ => None,
    }
}

/// `--light`'s long help: what it does, then the syntax.
fn light_help() -> String {
    format!(
        "Add a light (repeatable). Added lights replace the default rig and join the model's \
         own lights or the scene file's list, in the same space.\n\n{}",
        scenefile::LIGHT_SYNTAX
    )
}

impl LightingArgs {
    /// Applies `--env`, `--env-rotate`, `--env-intensity` and `--env-background`.
    fn apply_env(&self, s: &mut Settings) -> Result<()> {
        if let Some(name) = &self.env {
            let (env, note) =
                Environment::named(name, |n: &str| n.into(), default_cache_dir().as_deref())
                    .map_err(|err| anyhow::anyhow!("--env {name}: {err}"))?;
            if let Some(note) = note {
                eprintln!("note: --env {name}: {note}");
            }
            s.environment = env;
        }
        s.environment = std::mem::take(&mut s.environment)
            .adjusted(self.env_rotate, self.env_intensity)
            .map_err(|err| anyhow::anyhow!("--env-rotate / --env-intensity: {err}"))?;
        if self.env_background.is_some() {
            s.env_background = self.env_background;
        }
        Ok(())
    }

    /// Applies the flags given to `s` (`scene_lights`: the model's own lights).
    pub fn apply(&self, s: &mut Settings, scene_lights: &[Light]) -> Result<()> {
        if let Some(f) = self.fog {
            s.fog = Some(f);
        }
        if let Some(t) = self.tone {
            s.tone = t;
        }
        self.apply_env(s)?;
        if let Some(ev) = self.exposure {
            s.exposure = ev;
        }
        if let Some(n) = self.shadow_size {
            s.shadow.size = n;
        }
        if let Some(r) = self.pcf {
            s.shadow.pcf = r;
        }
        if self.ground && s.ground.is_none() {
            s.ground = Some(Ground::default());
        }
        if !self.lights.is_empty() {
            s.lights = scenefile::add_lights(&s.lights, scene_lights, &self.lights);
        }
        if self.shadows {
            s.lights = scenefile::shadow_every_light(&s.lights, scene_lights);
        }
        if self.single_scatter {
            s.single_scatter = true;
        }
        if !self.sections.is_empty() {
            s.sections.planes.clear();
            for &p in &self.sections {
                s.sections
                    .push(p)
                    .map_err(|err| anyhow::anyhow!("--section: {err}"))?;
            }
        }
        if let Some(Cap(c)) = self.section_cap {
            s.sections.cap = c;
        }
        Ok(())
    }
}

/// `--fog NEAR,FAR[,euclidean|depth][,R,G,B | ,#rrggbb]`.
pub(crate) fn parse_fog(s: &str) -> Result<Fog, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let num = |p: &str| {
        p.parse::<f32>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("--fog: bad number '{p}'"))
    };
    let distance = |key: &str, p: &str| numeric(key).parse(p).map(|v| v as f32);
    let (Some(near), Some(far)) = (parts.first(), parts.get(1)) else {
        return Err("expected --fog NEAR,FAR[,euclidean|depth][,COLOUR]".into());
    };
    let mut fog = Fog {
        near: distance("fog.near", near)?,
        far: distance("fog.far", far)?,
        ..Fog::default()
    };
    let mut rest = &parts[2..];
    if let Some(d) = rest.first().and_then(|p| p.parse::<FogDistance>().ok()) {
        fog.distance = d;
        rest = &rest[1..];
    }
    match rest {
        [] => {}
        [hex] if hex.starts_with('#') => {
            fog.color = parse_colour(hex).ok_or_else(|| format!("--fog: bad colour '{hex}'"))?;
        }
        [r, g, b] => fog.color = Vec3::new(num(r)?, num(g)?, num(b)?),
        _ => {
            return Err(format!(
                "--fog {s}: after NEAR,FAR expected euclidean or depth, then R,G,B or #rrggbb"
            ))
        }
    }
    if !(fog.near >= 0.0 && fog.near < fog.far) {
        return Err(format!("--fog {s}: need 0 <= NEAR < FAR"));
    }
    if fog.color.min_element() < 0.0 {
        return Err(format!("--fog {s}: the colour must not be negative"));
    }
    Ok(fog)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fog_flag_forms() {
        let f = parse_fog("2,12").unwrap();
        assert_eq!(
            (f.near, f.far, f.distance),
            (2.0, 12.0, FogDistance::Euclidean)
        );
        let f = parse_fog("1,5,depth,0.1,0.2,0.3").unwrap();
        assert_eq!(
            (f.distance, f.color),
            (FogDistance::Depth, Vec3::new(0.1, 0.2, 0.3))
        );
        let f = parse_fog("1,5,#ffffff").unwrap();
        assert!((f.color - Vec3::ONE).abs().max_element() < 1e-6);
        for bad in [
            "5,1",
            "1",
            "1,x",
            "1,5,fuzzy",
            "1,5,0.1,0.2",
            "-1,5",
            "1,5,#zz0000",
        ] {
            assert!(parse_fog(bad).is_err(), "{bad}");
        }
    }
}
