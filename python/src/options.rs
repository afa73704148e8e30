//! The keyword arguments of `render` and `render_many` as realist's [`Settings`], checked
//! with the command line's messages (realist's numeric settings table).

use glam::Vec4;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use realist::render::{numeric, Environment, Ground, Settings, ToneMap};
use realist::scene::Up;
use realist::shade::Shading;
use realist::texture::env::default_cache_dir;

/// Everything but the scene and the camera: what every frame of a `render_many` shares.
#[derive(Clone, Debug)]
pub(crate) struct Options {
    pub settings: Settings,
    /// `None`: the camera's size (intrinsics), else realist's default 1280x720.
    pub size: Option<(u32, u32)>,
    pub up: Up,
    /// Shadows for every light that can cast them (needs the scene's lights: applied per
    /// frame).
    pub shadows: bool,
    /// Whether `Frame.ids` is computed.
    pub ids: bool,
    /// Worker threads (`None`: every core).
    pub threads: Option<usize>,
}

/// A setting's value checked against realist's table (`"msaa = 2: expected ..."`).
fn checked(key: &str, v: f64) -> PyResult<f64> {
    numeric(key).check(v).map_err(PyValueError::new_err)
}

/// `background`: linear (r, g, b[, a]) floats, or "#rrggbb[aa]" (sRGB-encoded).
fn background(v: &Bound<'_, PyAny>) -> PyResult<Vec4> {
    if let Ok(s) = v.extract::<String>() {
        let hex = s.trim().strip_prefix('#').unwrap_or("");
        let bytes: Option<Vec<u8>> = (hex.len() == 6 || hex.len() == 8)
            .then(|| {
                (0..hex.len() / 2)
                    .map(|i| u8::from_str_radix(hex.get(2 * i..2 * i + 2)?, 16).ok())
                    .collect()
            })
            .flatten();
        let Some(b) = bytes else {
            return Err(PyValueError::new_err(format!(
                "background '{s}': expected #rrggbb or #rrggbbaa, or (r, g, b[, a]) linear floats"
            )));
        };
        let lin = realist::color::srgb8_decode;
        let a = b.get(3).map_or(1.0, |&a| f32::from(a) / 255.0);
        return Ok(Vec4::new(lin(b[0]), lin(b[1]), lin(b[2]), a));
    }
    let t: Vec<f64> = v.extract().map_err(|_| {
        PyValueError::new_err("background: expected (r, g, b[, a]) linear floats or '#rrggbb'")
    })?;
    let ok = |x: &f64| x.is_finite() && *x >= 0.0;
    match t[..] {
        [r, g, b] if t.iter().all(ok) => Ok(Vec4::new(r as f32, g as f32, b as f32, 1.0)),
        [r, g, b, a] if t.iter().all(ok) && a <= 1.0 => {
            Ok(Vec4::new(r as f32, g as f32, b as f32, a as f32))
        }
        _ => Err(PyValueError::new_err(format!(
            "background {t:?}: expected 3 or 4 finite non-negative floats (alpha at most 1)"
        ))),
    }
}

/// `env`: None or "default" (the studio), "none", a built-in name or an image path.
fn environment(name: &str) -> PyResult<Environment> {
    if name == "default" {
        return Ok(Environment::Auto);
    }
    let cache = default_cache_dir();
    Environment::named(
        name,
        |s: &str| std::path::PathBuf::from(s),
        cache.as_deref(),
    )
    .map(|(env, _note)| env)
    .map_err(|e| crate::RealistError::new_err(format!("env {name}: {e}")))
}

/// `size`: (width, height), each 1 to 16384.
pub(crate) fn size(v: (i64, i64)) -> PyResult<(u32, u32)> {
    let ok = |x: i64| (1..=16384).contains(&x);
    if ok(v.0) && ok(v.1) {
        Ok((v.0 as u32, v.1 as u32))
    } else {
        Err(PyValueError::new_err(format!(
            "size {v:?}: expected (width, height), each 1 to 16384 pixels"
        )))
    }
}

/// The keyword arguments shared by `render` and `render_many`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn parse(
    size_arg: Option<(i64, i64)>,
    shading: Option<&str>,
    env: Option<&str>,
    env_background: Option<f64>,
    bg: Option<&Bound<'_, PyAny>>,
    msaa: u32,
    samples: u32,
    exposure: Option<f64>,
    tone: Option<&str>,
    double_sided: bool,
    ground: bool,
    shadows: bool,
    up: &str,
    ids: bool,
    threads: Option<usize>,
) -> PyResult<Options> {
    let mut s = Settings::default();
    if let Some(m) = shading {
        s.shading = Some(m.parse::<Shading>().map_err(PyValueError::new_err)?);
    }
    if let Some(e) = env {
        s.environment = environment(e)?;
    }
    if let Some(b) = env_background {
        s.env_background = Some(checked("env_background", b)? as f32);
    }
    if let Some(b) = bg {
        s.background = background(b)?;
    }
    s.msaa = checked("msaa", f64::from(msaa))? as u32;
    s.samples = checked("samples", f64::from(samples))? as u32;
    if let Some(ev) = exposure {
        s.exposure = checked("exposure", ev)? as f32;
    }
    if let Some(t) = tone {
        s.tone = t.parse::<ToneMap>().map_err(PyValueError::new_err)?;
    }
    s.double_sided = double_sided;
    if ground {
        s.ground = Some(Ground::default());
    }
    let up = up.parse::<Up>().map_err(PyValueError::new_err)?;
    if let Some(n) = threads.filter(|n| !(1..=1024).contains(n)) {
        return Err(PyValueError::new_err(format!(
            "threads {n}: expected 1 to 1024 (None: every core)"
        )));
    }
    Ok(Options {
        settings: s,
        size: size_arg.map(size).transpose()?,
        up,
        shadows,
        ids,
        threads,
    })
}

/// An item of `render_many`: a scene, a path, or a (scene or path, camera) pair.
pub(crate) fn split_item<'py>(
    item: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
    if let Ok(t) = item.cast::<PyTuple>() {
        return match t.len() {
            2 => Ok((t.get_item(0)?, Some(t.get_item(1)?))),
            n => Err(PyValueError::new_err(format!(
                "a render_many item that is a tuple must be (scene or path, camera), got {n} values"
            ))),
        };
    }
    Ok((item.clone(), None))
}
