//! File values to renderer values: range checks with the key that failed, degrees to
//! radians, defaults. Functions here return `(key, reason)` or a reason; their callers
//! (`lib.rs`, `settings.rs`) add the file's path.

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

use super::schema::{
    AlphaKind, AttenuationMode, AttenuationSpec, CameraSpec, LightSpec, MaterialSpec,
    PrimitiveSpec, Rgba, Shape,
};
use crate::mesh::Mesh;
use crate::scene::{
    clamp_fov, AlphaMode, Attenuation, Camera, Light, LightKind, Material, Scene, Up, DEFAULT_YFOV,
};
use crate::shade::MAX_HALF_ANGLE;

mod camera;
mod light_flag;
mod material;
pub use camera::orbit_camera;
pub(super) use camera::{camera, check_camera};
pub use light_flag::*;
pub(super) use material::{check_material, materials};

/// `(key, reason)`.
pub(super) type Bad = (String, String);

pub(super) fn bad(key: impl Into<String>, reason: impl Into<String>) -> Bad {
    (key.into(), reason.into())
}

/// Largest coordinate accepted for positions, distances and extents.
const MAX_COORD: f64 = 1e7;

/// A finite `f32` within `lo..=hi`.
pub(super) fn ranged(key: &str, v: f64, lo: f64, hi: f64) -> Result<f32, Bad> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v as f32)
    } else {
        Err(bad(key, format!("{v} is not between {lo} and {hi}")))
    }
}

pub(super) fn vec3(key: &str, v: [f64; 3]) -> Result<Vec3, Bad> {
    if v.iter().all(|c| c.is_finite() && c.abs() <= MAX_COORD) {
        Ok(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32))
    } else {
        Err(bad(
            key,
            format!("{v:?} is not 3 finite numbers within ±{MAX_COORD}"),
        ))
    }
}

/// A non-zero direction.
fn nonzero(key: &str, v: [f64; 3]) -> Result<Vec3, Bad> {
    let d = vec3(key, v)?;
    if d.length_squared() > 1e-20 {
        Ok(d)
    } else {
        Err(bad(key, "is the zero vector"))
    }
}

/// A colour's components: finite, non-negative, at most `max`; `alpha` says whether a
/// fourth is allowed (it must be in 0..=1).
pub(super) fn color(key: &str, c: &Rgba, max: f64, alpha: bool) -> Result<Vec4, Bad> {
    let v = &c.0;
    if v.len() == 4 && !alpha {
        return Err(bad(key, "has 3 components here (no alpha)"));
    }
    if let Some(x) = v
        .iter()
        .find(|x| !(x.is_finite() && (0.0..=max).contains(*x)))
    {
        return Err(bad(
            key,
            format!("component {x} is not between 0 and {max}"),
        ));
    }
    if v.len() == 4 && v[3] > 1.0 {
        return Err(bad(key, format!("alpha {} is above 1", v[3])));
    }
    let a = v.get(3).copied().unwrap_or(1.0);
    Ok(Vec4::new(v[0] as f32, v[1] as f32, v[2] as f32, a as f32))
}

/// Largest light colour component or intensity.
const MAX_RADIANCE: f64 = 1e6;

/// Degrees in `lo..=hi` to radians.
fn degrees(key: &str, v: f64, lo: f64, hi: f64) -> Result<f32, Bad> {
    Ok(f64::from(ranged(key, v, lo, hi)?).to_radians() as f32)
}

/// One `[[light]]` (key prefix `key`), its image path unresolved (the caller loads it).
pub(super) fn light(key: &str, s: &LightSpec) -> Result<Light, Bad> {
    let k = |f: &str| format!("{key}.{f}");
    let d = Light::default();
    let kind = s.kind.0;
    let position = s
        .position
        .map_or(Ok(d.position), |p| vec3(&k("position"), p))?;
    let direction = match (s.direction, s.target) {
        (Some(_), Some(_)) => return Err(bad(k("target"), "give direction or target, not both")),
        // A zero direction is an error only where it is used (a kind can be switched in
        // an editor, so unused fields are kept as they are).
        (Some(v), None) if kind.directed() => nonzero(&k("direction"), v)?,
        (Some(v), None) => vec3(&k("direction"), v)?,
        (None, Some(t)) => {
            let t = vec3(&k("target"), t)?;
            let v = t - position;
            if v.length_squared() <= 1e-20 {
                return Err(bad(k("target"), "is the light's position"));
            }
            v
        }
        (None, None) => d.direction,
    };
    let max_deg = f64::from(MAX_HALF_ANGLE.to_degrees().round());
    let inner = s
        .inner
        .map_or(Ok(d.inner), |v| degrees(&k("inner"), v, 0.0, max_deg))?;
    let outer = s
        .outer
        .map_or(Ok(d.outer), |v| degrees(&k("outer"), v, 0.0, max_deg))?;
    if outer <= 0.0 {
        return Err(bad(k("outer"), "is 0: the cone is empty"));
    }
    if inner > outer {
        return Err(bad(
            k("inner"),
            format!(
                "{} degrees is wider than outer ({} degrees)",
                inner.to_degrees(),
                outer.to_degrees()
            ),
        ));
    }
    let rect = match s.rect {
        None => d.rect,
        Some([h, v]) => {
            let key = k("rect");
            let (h, v) = (
                degrees(&key, h, 0.0, max_deg)?,
                degrees(&key, v, 0.0, max_deg)?,
            );
            if h <= 0.0 || v <= 0.0 {
                return Err(bad(key, "half-angles must be above 0"));
            }
            Vec2::new(h, v)
        }
    };
    let up = match s.up {
        None => d.up,
        Some(u) if kind == LightKind::Rect => nonzero(&k("up"), u)?,
        Some(u) => vec3(&k("up"), u)?,
    };
    let color = s.color.as_ref().map_or(Ok(Vec4::ONE), |c| {
        self::color(&k("color"), c, MAX_RADIANCE, false)
    })?;
    let intensity = s
        .intensity
        .map_or(Ok(1.0), |i| ranged(&k("intensity"), i, 0.0, MAX_RADIANCE))?;
    let attenuation = match &s.attenuation {
        None => Attenuation::None,
        Some(a) => attenuation(&k("attenuation"), a)?,
    };
    Ok(Light {
        name: s.name.clone().unwrap_or_default().into(),
        kind,
        color: color.truncate(),
        intensity,
        position,
        direction,
        inner,
        outer,
        rect,
        up,
        image: None,
        attenuation,
        shadow: s.shadow.unwrap_or(false),
    })
}

fn attenuation(key: &str, a: &AttenuationSpec) -> Result<Attenuation, Bad> {
    let k = |f: &str| format!("{key}.{f}");
    let unused = |name: &str, present: bool| {
        if present {
            Err(bad(
                k(name),
                format!(
                    "is not used by mode = \"{}\"",
                    super::schema::Keyword::keyword(a.mode.0)
                ),
            ))
        } else {
            Ok(())
        }
    };
    let need = |name: &str, v: Option<f64>| {
        v.ok_or_else(|| bad(k(name), "is required by this mode"))
            .and_then(|v| ranged(&k(name), v, 0.0, MAX_COORD))
    };
    Ok(match a.mode.0 {
        AttenuationMode::None | AttenuationMode::InverseSquare => {
            unused("near", a.near.is_some())?;
            unused("far", a.far.is_some())?;
            unused("range", a.range.is_some())?;
            if a.mode.0 == AttenuationMode::None {
                Attenuation::None
            } else {
                Attenuation::InverseSquare
            }
        }
        AttenuationMode::Linear => {
            unused("range", a.range.is_some())?;
            let (near, far) = (need("near", a.near)?, need("far", a.far)?);
            if !(near <= far && far > 0.0) {
                return Err(bad(
                    k("far"),
                    format!("{far} must be above 0 and not below near ({near})"),
                ));
            }
            Attenuation::Linear { near, far }
        }
        AttenuationMode::Range => {
            unused("near", a.near.is_some())?;
            unused("far", a.far.is_some())?;
            let r = need("range", a.range)?;
            if r <= 0.0 {
                return Err(bad(k("range"), "must be above 0"));
            }
            Attenuation::Range(r)
        }
    })
}

/// A `[primitive]`: one instance of one generated mesh with one material ("primitive").
pub(super) fn primitive(s: &PrimitiveSpec) -> Result<Scene, String> {
    check_primitive(s)?;
    let shape = s.shape.0;
    let r = |d: f32| s.radius.map_or(d, |v| v as f32);
    let h = |d: f32| s.height.map_or(d, |v| v as f32);
    let slices = |d: u32| s.slices.unwrap_or(d);
    let mesh = match shape {
        Shape::Sphere => Mesh::sphere(r(1.0), slices(48), s.stacks.unwrap_or(24)),
        Shape::Cylinder => Mesh::cylinder(r(0.5), h(2.0), slices(32), s.caps.unwrap_or(true)),
        Shape::Cone => Mesh::cone(r(0.7), h(1.5), slices(32)),
        Shape::Torus => Mesh::torus(
            r(1.0),
            s.minor.map_or(0.35, |v| v as f32),
            slices(32),
            s.stacks.unwrap_or(16),
        ),
        Shape::Cube => Mesh::cube(s.size.map_or(1.0, |v| v as f32)),
    };
    let mut mesh = mesh.map_err(|e| e.to_string())?;
    let name = super::schema::Keyword::keyword(shape);
    mesh.name = name.into();
    mesh.material = Some(0);
    let mut scene = Scene {
        meshes: vec![mesh],
        materials: vec![Material {
            name: "primitive".into(),
            ..Material::default()
        }],
        ..Scene::default()
    };
    scene.instances.push(crate::scene::Instance {
        mesh: 0,
        world: glam::Mat4::IDENTITY,
        name: name.into(),
        style: crate::scene::Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    scene.report.file = format!("[primitive] {name}");
    scene.report.format = "generated".into();
    Ok(scene)
}

/// The keys each shape uses, and the ranges of the values.
pub(super) fn check_primitive(s: &PrimitiveSpec) -> Result<(), String> {
    let shape = s.shape.0;
    let uses: &[&str] = match shape {
        Shape::Sphere => &["radius", "slices", "stacks"],
        Shape::Cylinder => &["radius", "height", "slices", "caps"],
        Shape::Cone => &["radius", "height", "slices"],
        Shape::Torus => &["radius", "minor", "slices", "stacks"],
        Shape::Cube => &["size"],
    };
    let given = [
        ("radius", s.radius.is_some()),
        ("height", s.height.is_some()),
        ("minor", s.minor.is_some()),
        ("size", s.size.is_some()),
        ("slices", s.slices.is_some()),
        ("stacks", s.stacks.is_some()),
        ("caps", s.caps.is_some()),
    ];
    let shape_name = super::schema::Keyword::keyword(shape);
    if let Some((k, _)) = given.iter().find(|(k, g)| *g && !uses.contains(k)) {
        return Err(format!(
            "`{k}` is not used by a {shape_name} (it uses {})",
            uses.join(", ")
        ));
    }
    for (k, v) in [
        ("radius", s.radius),
        ("height", s.height),
        ("minor", s.minor),
        ("size", s.size),
    ] {
        if let Some(v) = v {
            ranged(k, v, 1e-6, 1e6).map_err(|(k, r)| format!("{k}: {r}"))?;
        }
    }
    let max = crate::mesh::MAX_SEGMENTS;
    for (k, v) in [("slices", s.slices), ("stacks", s.stacks)] {
        if let Some(n) = v.filter(|n| !(3..=max).contains(n)) {
            return Err(format!("{k}: {n} is not between 3 and {max}"));
        }
    }
    Ok(())
}

/// `Arc` of a texture loaded from `path` (its name set to the path, so a file written
/// by [`super::SceneFile::from_settings`] can refer to it again).
pub(super) fn image(
    path: &std::path::Path,
) -> Result<Arc<crate::texture::Texture>, crate::load::LoadError> {
    image_as(path, true)
}

/// [`image`] decoded as colour (`srgb`) or as linear data (heights, normals).
pub(super) fn image_as(
    path: &std::path::Path,
    srgb: bool,
) -> Result<Arc<crate::texture::Texture>, crate::load::LoadError> {
    let mut t = crate::load::load_image(path, srgb)?;
    t.name = std::fs::canonicalize(path)
        .unwrap_or_else(|_| path.to_owned())
        .display()
        .to_string();
    Ok(Arc::new(t))
}
