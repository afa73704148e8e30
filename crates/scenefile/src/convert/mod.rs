//! File values to renderer values: range checks with the key that failed, degrees to
//! radians, defaults. Functions here return `(key, reason)` or a reason; the callers in
//! `mod.rs` and `check.rs` add the file's path.

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

mod light_flag;
pub use light_flag::*;

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

/// Applies material overrides `specs` (key prefix `key`, e.g. `material`) to `materials`.
pub(super) fn materials(
    key: &str,
    specs: &[MaterialSpec],
    materials: &mut [Material],
) -> Result<(), Bad> {
    for (i, s) in specs.iter().enumerate() {
        let key = format!("{key}[{i}]");
        let targets = select(&key, s, materials)?;
        for t in targets {
            override_material(&key, s, &mut materials[t])?;
        }
    }
    Ok(())
}

/// Checks an override's values without a model (every field but the selection).
pub(super) fn check_material(key: &str, s: &MaterialSpec) -> Result<(), Bad> {
    if s.index.is_some() == s.name.is_some() {
        return Err(bad(key, "give exactly one of index or name"));
    }
    override_material(key, s, &mut Material::default())
}

/// Indices of the materials an override selects.
fn select(key: &str, s: &MaterialSpec, materials: &[Material]) -> Result<Vec<usize>, Bad> {
    let count = materials.len();
    match (s.index, &s.name) {
        (Some(i), None) if i < count => Ok(vec![i]),
        (Some(i), None) if count == 0 => Err(bad(
            format!("{key}.index"),
            format!("{i}, but the model has no materials (its meshes use the default)"),
        )),
        (Some(i), None) => Err(bad(
            format!("{key}.index"),
            format!("{i}, but the model has only {count} material(s)"),
        )),
        (None, Some(name)) => {
            let hits: Vec<usize> = (0..count).filter(|&m| materials[m].name == *name).collect();
            if hits.is_empty() {
                let names: Vec<&str> = materials.iter().take(12).map(|m| m.name.as_str()).collect();
                Err(bad(
                    format!("{key}.name"),
                    format!(
                        "no material is named '{name}' (the model has: {}{})",
                        names.join(", "),
                        if count > 12 { ", ..." } else { "" }
                    ),
                ))
            } else {
                Ok(hits)
            }
        }
        _ => Err(bad(key, "give exactly one of index or name")),
    }
}

fn override_material(key: &str, s: &MaterialSpec, m: &mut Material) -> Result<(), Bad> {
    let k = |f: &str| format!("{key}.{f}");
    if let Some(c) = &s.base_color {
        let c = color(&k("base_color"), c, MAX_RADIANCE, true)?;
        m.base_color = if s.base_color.as_ref().is_some_and(|c| c.0.len() == 3) {
            c.truncate().extend(m.base_color.w)
        } else {
            c
        };
    }
    if let Some(c) = &s.specular {
        m.specular = color(&k("specular"), c, MAX_RADIANCE, false)?.truncate();
    }
    if let Some(c) = &s.ambient {
        m.ambient = color(&k("ambient"), c, MAX_RADIANCE, false)?.truncate();
    }
    if let Some(n) = s.shininess {
        m.shininess = ranged(&k("shininess"), n, 1.0, 2000.0)?;
    }
    if let Some(d) = s.double_sided {
        m.double_sided = d;
    }
    let cutoff = s
        .alpha_cutoff
        .map(|c| ranged(&k("alpha_cutoff"), c, 0.0, 1.0))
        .transpose()?;
    match (s.alpha_mode.map(|a| a.0), cutoff) {
        (Some(AlphaKind::Opaque), None) => m.alpha_mode = AlphaMode::Opaque,
        (Some(AlphaKind::Blend), None) => m.alpha_mode = AlphaMode::Blend,
        (Some(AlphaKind::Mask), c) => m.alpha_mode = AlphaMode::Mask(c.unwrap_or(0.5)),
        (None, Some(c)) if matches!(m.alpha_mode, AlphaMode::Mask(_)) => {
            m.alpha_mode = AlphaMode::Mask(c);
        }
        (_, Some(_)) => {
            return Err(bad(
                k("alpha_cutoff"),
                "is only used with alpha_mode = \"mask\"",
            ))
        }
        (None, None) => {}
    }
    Ok(())
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

/// An orbit camera around `scene`'s bounds: from `azimuth` degrees around the up axis `up`
/// and `elevation` degrees above the horizon; at `distance` (scene units) if given, else at
/// the distance that frames the bounding box. `yfov` in radians (default 45 degrees).
#[must_use]
pub fn orbit_camera(
    scene: &Scene,
    aspect: f32,
    azimuth: f32,
    elevation: f32,
    distance: Option<f32>,
    yfov: Option<f32>,
    up: Up,
) -> Camera {
    let (lo, hi) = scene.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let yfov = clamp_fov(yfov.unwrap_or(DEFAULT_YFOV));
    // Framed in the Y-up frame, turned back (the identity for Y).
    let (lo, hi) = up.box_to_y_up(lo, hi);
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6));
    let framed = Camera::frame_box_fov(lo, hi, aspect, azimuth, elevation, yfov);
    let cam = match distance {
        None => framed,
        Some(d) => {
            let mut cam = Camera::orbit(center, azimuth, elevation, d, framed.yfov);
            cam.fit(center, radius);
            cam
        }
    };
    cam.turned(up.to_y_up().inverse())
}

/// Checks a `[camera]` table without a model.
pub(super) fn check_camera(s: &CameraSpec) -> Result<(), Bad> {
    let look = s.eye.is_some() || s.target.is_some() || s.up.is_some();
    let orbit = s.azimuth.is_some() || s.elevation.is_some() || s.distance.is_some();
    if s.gltf.is_some() && (look || orbit) {
        return Err(bad(
            "gltf",
            "a file camera takes no eye, target, up, azimuth, elevation or distance",
        ));
    }
    if look && orbit {
        return Err(bad(
            "eye",
            "give eye/target/up or azimuth/elevation/distance, not both",
        ));
    }
    if (s.target.is_some() || s.up.is_some()) && s.eye.is_none() {
        return Err(bad("eye", "target and up need an eye"));
    }
    for (k, v) in [("eye", s.eye), ("target", s.target)] {
        if let Some(v) = v {
            vec3(k, v)?;
        }
    }
    if let Some(u) = s.up {
        nonzero("up", u)?;
    }
    if let (Some(e), Some(t)) = (s.eye, s.target) {
        if e == t {
            return Err(bad("target", "is the eye"));
        }
    }
    if let Some(a) = s.azimuth {
        ranged("azimuth", a, -3600.0, 3600.0)?;
    }
    if let Some(e) = s.elevation {
        ranged("elevation", e, -90.0, 90.0)?;
    }
    if let Some(d) = s.distance {
        if ranged("distance", d, 0.0, MAX_COORD)? <= 0.0 {
            return Err(bad("distance", "must be above 0"));
        }
    }
    if let Some(f) = s.yfov {
        let f = ranged("yfov", f, 0.1, 179.0)?;
        debug_assert!(f > 0.0);
    }
    for (k, v) in [("near", s.near), ("far", s.far), ("ortho", s.ortho)] {
        if let Some(v) = v {
            if ranged(k, v, 0.0, MAX_COORD)? <= 0.0 {
                return Err(bad(k, "must be above 0"));
            }
        }
    }
    if let (Some(n), Some(f)) = (s.near, s.far) {
        if n >= f {
            return Err(bad("near", format!("{n} is not below far ({f})")));
        }
    }
    Ok(())
}

/// Resolves a checked `[camera]` against `scene` (keys without the `camera.` prefix).
pub(super) fn camera(s: &CameraSpec, scene: &Scene, aspect: f32, up: Up) -> Result<Camera, Bad> {
    check_camera(s)?;
    let yfov = s.yfov.map(|f| (f as f32).to_radians());
    let (lo, hi) = scene.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6));
    let mut cam = if let Some(n) = s.gltf {
        let count = scene.cameras.len();
        let file = &scene.report.file;
        let Some(c) = scene.cameras.get(n) else {
            return Err(bad(
                "gltf",
                if count == 0 {
                    format!("{file} has no cameras")
                } else {
                    format!("{file} has {count} camera(s) (0 to {}), not {n}", count - 1)
                },
            ));
        };
        let mut c = c.clone();
        if let Some(f) = yfov {
            c.yfov = f;
        }
        c
    } else if let Some(eye) = s.eye {
        let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let mut c = Camera {
            name: "scene file".into(),
            eye: v(eye),
            target: s.target.map_or(center, v),
            up: s.up.map_or(up.vector(), v),
            yfov: yfov.unwrap_or(DEFAULT_YFOV),
            ..Camera::default()
        };
        c.fit(center, radius);
        c
    } else {
        let mut c = orbit_camera(
            scene,
            aspect,
            s.azimuth.map_or(35.0, |a| a as f32),
            s.elevation.map_or(25.0, |e| e as f32),
            s.distance.map(|d| d as f32),
            yfov,
            up,
        );
        c.name = "scene file".into();
        c
    };
    if let Some(h) = s.ortho {
        cam.ortho = Some(h as f32);
    }
    if let Some(n) = s.near {
        cam.near = n as f32;
    }
    if let Some(f) = s.far {
        cam.far = f as f32;
    }
    if !(cam.near > 0.0 && cam.near < cam.far) {
        return Err(bad(
            if s.near.is_some() { "near" } else { "far" },
            format!("near {} must be below far {}", cam.near, cam.far),
        ));
    }
    Ok(cam)
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
