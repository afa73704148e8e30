//! What `realist render` draws and how: the model, scene file or demo it reads, then its
//! settings, up axis, camera and output path, each the scene file's unless a flag says.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{bail, Result};

use realist::load::{self, LoadOptions};
use realist::render::{default_camera, default_camera_up, Settings};
use realist::scene::{self, Camera, Scene, Slot, SlotOverride, TextureSource, Up};
use realist::scenefile::schema::{Kw, UvChoice};
use realist::scenefile::{self, Format, SceneFile};
use realist::shade::Shading;

use super::{file_camera, CameraArg, Input, RenderArgs};

pub(super) fn read_input(args: &RenderArgs) -> Result<Input> {
    let opts = LoadOptions {
        normals: args.normals.options()?,
        uv: args.uv.and_then(UvChoice::generator),
        scene: args.scene,
        ..LoadOptions::default()
    };
    match &args.model {
        Some(path) if Format::of(path).is_some() => {
            let mut file = SceneFile::read(path)?;
            if let Some(uv) = args.uv {
                file.doc.uv = Some(Kw(uv)); // `--uv mesh` too overrides the file
            }
            if let Some(up) = args.up {
                file.doc.up = Some(Kw(up)); // and `--up` its up axis (its camera too)
            }
            let scene = file.load_model(&opts)?;
            let source = match file.model()? {
                scenefile::ModelSource::Demo => "the demo scene".into(),
                scenefile::ModelSource::File(p) => p.display().to_string(),
                scenefile::ModelSource::Primitive(_) => format!("{}'s [primitive]", path.display()),
            };
            Ok(Input {
                scene,
                file: Some(file),
                source,
            })
        }
        Some(path) => Ok(Input {
            scene: load::load(path, &opts)?,
            file: None,
            source: path.display().to_string(),
        }),
        None => Ok(Input {
            scene: demo(opts.uv.as_ref()),
            file: None,
            source: "the demo scene".into(),
        }),
    }
}

/// The demo scene, with generated texture coordinates if asked for.
fn demo(uv: Option<&realist::texture::UvGenerator>) -> Scene {
    let mut scene = scene::demo();
    if let Some(g) = uv {
        scene.apply_uv_generator(g);
        scene.check_texture_slots();
    }
    scene
}

/// The settings: the scene file's (or the defaults), then the flags given.
pub(super) fn settings(args: &RenderArgs, input: &Input) -> Result<Settings> {
    let mut s = match &input.file {
        Some(f) => f.settings(&input.scene)?,
        None => Settings::default(),
    };
    if args.shading.is_some() {
        s.shading = args.shading;
    }
    if args.double_sided {
        s.double_sided = true;
    }
    if args.vertex_blinn {
        s.vertex_lighting.blinn = true;
    }
    if args.flat_last_vertex {
        s.vertex_lighting.provoking_vertex = true;
    }
    if let Some(m) = args.msaa {
        s.msaa = m;
    }
    if args.filter.is_some() {
        s.filter = args.filter;
    }
    if let Some(n) = args.samples {
        s.samples = n;
    }
    if let Some(n) = args.ray_depth {
        s.ray_depth = n;
    }
    if let Some(bits) = args.subpixel_bits {
        s.subpixel_bits = bits as u8;
    }
    if let Some(px) = args.point_size {
        s.point_size = px;
    }
    if let Some(px) = args.line_width {
        s.line_width = px;
    }
    let image = |p: &std::path::Path, srgb: bool| load::load_image(p, srgb).map(Arc::new);
    if let Some(t) = &args.texture {
        let source = TextureSource::from_spec(t, Slot::BaseColor, image)
            .map_err(|e| anyhow::anyhow!("--texture {t}: {e}"))?;
        s.slots
            .set(Slot::BaseColor, Some(SlotOverride::source(source, 1.0)));
    }
    if let Some(b) = &args.bump {
        let (source, scale) = TextureSource::bump_from_spec(b, image)
            .map_err(|e| anyhow::anyhow!("--bump {b}: {e}"))?;
        let scale = args.bump_scale.unwrap_or(scale);
        s.slots
            .set(Slot::Bump, Some(SlotOverride::source(source, scale)));
    }
    match args.normal_map {
        Some(false) => s.slots.set(Slot::Normal, Some(SlotOverride::Off)),
        Some(true) => s.slots.set(Slot::Normal, None),
        None => {}
    }
    let maps = args.texture.is_some() || args.bump.is_some();
    if maps && s.shading.is_some_and(|m| m != Shading::Textured) {
        eprintln!(
            "warning: --texture and --bump are drawn in textured mode (the default when a \
             model has a texture)"
        );
    }
    args.lighting.apply(&mut s, &input.scene.lights)?;
    if let Some(v) = &args.variant {
        let scene = &input.scene;
        if !scene.variants.contains(v) {
            anyhow::bail!(
                "--variant {v}: not a material variant of {} ({})",
                scene.report.file,
                scenefile::variant_list(&scene.variants)
            );
        }
        s.variant = Some(v.clone());
    }
    Ok(s)
}

/// The up axis: `--up`, else the scene file's, else +Y.
pub(super) fn up_of(args: &RenderArgs, input: &Input) -> Up {
    args.up
        .or_else(|| input.file.as_ref().map(SceneFile::up))
        .unwrap_or_default()
}

/// The camera: `--camera`, else the scene file's, else the demo's or the default view;
/// `--fov`/`--zoom` change any of them.
pub(super) fn camera(args: &RenderArgs, input: &Input, aspect: f32) -> Result<Camera> {
    let yfov = match (args.fov, args.zoom) {
        (Some(f), _) if f.is_finite() && f > 0.0 && f < 180.0 => Some(f.to_radians()),
        (Some(f), _) => bail!("--fov {f}: expected degrees between 0 and 180"),
        (None, Some(z)) if z.is_finite() && z > 0.0 => Some(2.0 * libm::atanf(1.0 / z)),
        (None, Some(z)) => bail!("--zoom {z}: expected a positive number"),
        (None, None) => None,
    };
    let scene = &input.scene;
    let up = up_of(args, input);
    let mut cam = match (args.camera, &input.file) {
        (Some(CameraArg::Orbit(az, el, dist)), _) => {
            return Ok(scenefile::orbit_camera(
                scene, aspect, az, el, dist, yfov, up,
            ))
        }
        (Some(CameraArg::Gltf(n)), _) => file_camera(scene, n, &input.source)?,
        (None, Some(f)) => match f.camera(scene, aspect)? {
            Some(c) => c,
            None => scene
                .cameras
                .first()
                .filter(|_| args.demo || is_demo(f))
                .cloned()
                .unwrap_or_else(|| default_camera_up(scene, aspect, up)),
        },
        (None, None) if args.demo => scene
            .cameras
            .first()
            .cloned()
            .unwrap_or_else(|| default_camera(scene, aspect)),
        (None, None) if yfov.is_some() => {
            return Ok(scenefile::orbit_camera(
                scene, aspect, 35.0, 25.0, None, yfov, up,
            ))
        }
        (None, None) => default_camera_up(scene, aspect, up),
    };
    if let Some(f) = yfov {
        cam.yfov = f;
    }
    Ok(cam)
}

fn is_demo(f: &SceneFile) -> bool {
    matches!(f.model(), Ok(scenefile::ModelSource::Demo))
}

/// Whether [`camera`] chose its distance to frame the scene from its own direction (the
/// default view, or an orbit without a distance or near/far): a turntable may then move it
/// back so the scene fits every frame.
pub(super) fn framed_distance(args: &RenderArgs, input: &Input) -> bool {
    let no_camera = input.scene.cameras.is_empty();
    match (args.camera, &input.file) {
        (Some(CameraArg::Orbit(_, _, d)), _) => d.is_none(),
        (Some(CameraArg::Gltf(_)), _) => false,
        (None, Some(f)) => match &f.doc.camera {
            Some(c) => {
                c.gltf.is_none()
                    && c.eye.is_none()
                    && c.distance.is_none()
                    && c.near.is_none()
                    && c.far.is_none()
            }
            None => !(args.demo || is_demo(f)) || no_camera,
        },
        (None, None) => !args.demo || no_camera,
    }
}

/// The output path: `-o`, the scene file's `output`, or NAME.png here.
pub(super) fn output(args: &RenderArgs, input: &Input) -> Result<PathBuf> {
    if let Some(o) = &args.output {
        return Ok(o.clone());
    }
    if let Some(o) = input.file.as_ref().and_then(SceneFile::output) {
        return Ok(o);
    }
    match (&args.model, &input.file) {
        (Some(p), Some(_)) => Ok(PathBuf::from(format!(
            "{}.png",
            p.file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy())
        ))),
        _ => bail!("-o OUT.png is required when rendering a model or the demo"),
    }
}
