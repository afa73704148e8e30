//! `realist render`: a model, the demo or a scene file to a PNG, with command-line flags
//! overriding the file.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::render::numeric;
use realist::render::{PreparedScene, Renderer, View};
use realist::scene::{Camera, Scene, Up};
use realist::scenefile::schema::UvChoice;
use realist::scenefile::{self, SceneFile};
use realist::shade::Shading;
use realist::texture::Filter;

use super::lighting::LightingArgs;
use super::sequence::{self, Drawn, Outputs, SequenceArgs};
use super::{parse_msaa, parse_size, NormalArgs};

mod compare;
mod input;
mod write;

use input::{camera, framed_distance, output, read_input, settings, up_of};
use write::{describe, write_image};

#[derive(Args)]
pub(crate) struct RenderArgs {
    /// Model file (.obj, .gltf, .glb, .stl, .ply) or scene file (.toml, .json; see the README's "Scene
    /// files"); flags given on the command line override the scene file.
    #[arg(required_unless_present = "demo", conflicts_with = "demo")]
    pub model: Option<PathBuf>,
    /// Render the built-in demo scene (the textbook's three spheres).
    #[arg(long)]
    pub demo: bool,
    /// Output image (PNG, or the format its extension names). Default: the scene file's
    /// `output`, else NAME.png in the current folder. `{}` in the name is replaced by the
    /// frame number (frame_{}.png); an .apng name writes one animated PNG of every frame.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Image size WIDTHxHEIGHT (default 1280x720, or the scene file's).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// The shading mode (default: pbr for glTF materials, textured for a model with
    /// textures, else phong; the demo keeps its per-sphere styles unless a mode is given).
    #[arg(long, long_help = shading_help())]
    pub shading: Option<Shading>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// AZIMUTH,ELEVATION[,DISTANCE]: an orbit camera in degrees (azimuth around +Y,
    /// elevation above the horizon) and scene units (default distance frames the scene);
    /// or gltf:N, the file's camera N (0-based).
    #[arg(long, value_parser = parse_camera, allow_hyphen_values = true)]
    pub camera: Option<CameraArg>,
    /// The world's up axis, y (default) or z: the default view, --camera's azimuth and
    /// --turntable turn about it (z for scans and CAD models, often STL and PLY files, that
    /// lie on their back; a scene file says `up = "z"`).
    #[arg(long, value_name = "y|z")]
    pub up: Option<Up>,
    /// Vertical field of view in degrees (default 45).
    #[arg(long, conflicts_with = "zoom")]
    pub fov: Option<f32>,
    /// The textbook's zoom factor, zoom = 1/tan(fov/2) (1 = 90 degrees, 2.414 = 45 degrees).
    #[arg(long)]
    pub zoom: Option<f32>,
    /// Base-colour texture of every material, replacing the file's: an image file, or a
    /// procedural texture (the textbook's §9.5): checker[:N], grid[:N] (a UV test grid),
    /// wood, marble or noise[:OCTAVES]. Images and 2D patterns need UVs (see --uv); wood,
    /// marble and noise are solid textures read at the object-space position.
    #[arg(long, value_name = "IMG|checker:N|grid|wood|marble|noise")]
    pub texture: Option<String>,
    /// Bump mapping: a height image (its R channel, 1 = a full step over one texel is a 45°
    /// slope), noise:SCALE (solid fBm noise displaced by SCALE bounding radii), or another
    /// procedural texture as --texture names them.
    #[arg(long, value_name = "IMG|noise:SCALE")]
    pub bump: Option<String>,
    /// The bump height, replacing the default of --bump's kind.
    #[arg(long, value_name = "SCALE", requires = "bump", allow_hyphen_values = true,
          value_parser = numeric("bump_scale").parser_f32())]
    pub bump_scale: Option<f32>,
    /// Whether the materials' normal maps are read (default on).
    #[arg(long, value_name = "on|off", value_parser = parse_on_off)]
    pub normal_map: Option<bool>,
    /// Texture coordinates: mesh (the file's, the default), or generated from an auxiliary
    /// surface, the textbook's §9.5: planar:x|y|z, cylindrical[:x|y|z], spherical[:x|y|z]
    /// (about y by default) or box; replaces UV set 0 of every mesh (added where it has
    /// none). Overrides a scene file's `uv`.
    #[arg(long, value_parser = parse_uv)]
    pub uv: Option<UvChoice>,
    /// Read every texture with this filter instead of its sampler's: nearest, bilinear,
    /// trilinear or aniso:N (N = 2 to 16 trilinear taps along the footprint's long axis).
    #[arg(long, value_name = "FILTER")]
    pub filter: Option<Filter>,
    /// Print one JSON object with counters and per-stage milliseconds.
    #[arg(long)]
    pub stats: bool,
    /// Draw every material double-sided (no back-face culling).
    #[arg(long)]
    pub double_sided: bool,
    /// Gouraud and flat shading with Blinn's N·H highlight instead of Phong's R·V (the
    /// textbook's §9.2.2 lights vertices with R·V).
    #[arg(long)]
    pub vertex_blinn: bool,
    /// Flat shading lights each triangle at its last vertex with its plane normal, as
    /// OpenGL's flat shading does (its provoking vertex), instead of each facet at its
    /// centroid.
    #[arg(long)]
    pub flat_last_vertex: bool,
    /// Multisampling: 1 (off) or 4 coverage and depth samples per pixel, shaded once per
    /// pixel and triangle, averaged in linear light.
    #[arg(long, value_parser = parse_msaa)]
    pub msaa: Option<u32>,
    /// Supersampling: N x N jittered passes per pixel, averaged in linear light (1 to 8).
    #[arg(long, value_parser = numeric("samples").parser_u32())]
    pub samples: Option<u32>,
    /// Traced rays: the most surfaces a ray may meet after the first (0 to 64, default
    /// 32): Whitted's reflection and refraction depth, the path tracer's bounces (the
    /// textbook's depth limit, §9.6.1).
    #[arg(long, value_name = "N", value_parser = numeric("ray_depth").parser_u32())]
    pub ray_depth: Option<u32>,
    /// Sub-pixel bits of the vertex snap (0 to 8, default 8): fewer bits move vertices to
    /// a coarser grid, the precision experiment of the rasterizer's fixed-point set-up.
    #[arg(long, value_name = "BITS", value_parser = numeric("subpixel_bits").parser_u32())]
    pub subpixel_bits: Option<u32>,
    /// Which scene of a glTF file to draw, 0-based in file order (`realist info` lists
    /// them). Default: the file's default scene, else its first.
    #[arg(long, value_name = "N", conflicts_with = "demo")]
    pub scene: Option<usize>,
    /// Size of points (glTF POINTS, OBJ `p`) in pixels of the image: a square centred on
    /// the pixel nearest the point (default 1, whole pixels up to 64).
    #[arg(long, value_name = "PX", value_parser = numeric("point_size").parser_f32())]
    pub point_size: Option<f32>,
    /// Width of lines (glTF LINES, LINE_LOOP, LINE_STRIP, OBJ `l`) in pixels of the image
    /// (default 1, whole pixels up to 64).
    #[arg(long, value_name = "PX", value_parser = numeric("line_width").parser_f32())]
    pub line_width: Option<f32>,
    /// The material variant to draw (a glTF file with `KHR_materials_variants`; `realist
    /// info` lists them), by name. Default: the file's default materials.
    #[arg(long, value_name = "NAME")]
    pub variant: Option<String>,
    /// Compare the rendered image with a reference PNG, for continuous integration: exit
    /// status 1 when they differ beyond --tolerance (identical bytes by default: realist's
    /// images are the same on every machine), the differing pixels counted, and a heat map
    /// (NAME.diff.png beside the image) when any pixel differs. One frame only.
    #[arg(long, value_name = "REFERENCE.png")]
    pub compare: Option<PathBuf>,
    /// --compare's tolerance, LEVELS[,PIXELS]: the largest per-channel difference in 8-bit
    /// levels that does not count, and how many pixels (a count, or a percentage such as
    /// 0.1%) may differ by more. Default 0,0: identical bytes.
    #[arg(long, value_name = "LEVELS[,PIXELS]", requires = "compare",
          value_parser = compare::parse_tolerance)]
    pub tolerance: Option<compare::Tolerance>,
    #[command(flatten)]
    pub lighting: LightingArgs,
    #[command(flatten)]
    pub normals: NormalArgs,
    #[command(flatten)]
    pub sequence: SequenceArgs,
}

/// `--shading`'s long help: the default, then every mode from its description.
fn shading_help() -> String {
    format!(
        "The shading mode (default: pbr for glTF materials, textured for a model with \
         textures, else phong; the demo keeps its per-sphere styles unless a mode is given):\n\n{}",
        Shading::help()
    )
}

/// `on` or `off` (also true/false, yes/no, 1/0).
fn parse_on_off(s: &str) -> Result<bool, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "on" | "true" | "yes" | "1" => Ok(true),
        "off" | "false" | "no" | "0" => Ok(false),
        _ => Err(format!("expected on or off, not '{s}'")),
    }
}

/// `--camera`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum CameraArg {
    Orbit(f32, f32, Option<f32>),
    Gltf(usize),
}

/// `--uv` (also `realist info --uv`).
pub(crate) fn parse_uv(s: &str) -> Result<UvChoice, String> {
    s.parse()
}

fn parse_camera(s: &str) -> Result<CameraArg, String> {
    if let Some(n) = s.strip_prefix("gltf:") {
        return n
            .trim()
            .parse()
            .map(CameraArg::Gltf)
            .map_err(|_| format!("--camera gltf:N: bad camera number '{n}'"));
    }
    let parts: Vec<f32> = s
        .split(',')
        .map(|p| {
            p.trim()
                .parse::<f32>()
                .map_err(|_| format!("bad number '{p}' in --camera"))
        })
        .collect::<Result<_, _>>()?;
    if parts.iter().any(|p| !p.is_finite()) {
        return Err("--camera values must be finite".into());
    }
    match parts[..] {
        [a, e] => Ok(CameraArg::Orbit(a, e, None)),
        [a, e, d] if d > 0.0 => Ok(CameraArg::Orbit(a, e, Some(d))),
        [_, _, _] => Err("--camera distance must be positive".into()),
        _ => Err("expected --camera azimuth,elevation[,distance] or gltf:N".into()),
    }
}

/// The scene's camera `n`, or an error naming the file and how many cameras it has.
pub(crate) fn file_camera(scene: &Scene, n: usize, source: &str) -> Result<Camera> {
    let count = scene.cameras.len();
    match scene.cameras.get(n) {
        Some(c) => Ok(c.clone()),
        None if count == 0 => bail!("--camera gltf:{n}: {source} has no cameras"),
        None => bail!(
            "--camera gltf:{n}: {source} has {count} camera(s), numbered 0 to {}",
            count - 1
        ),
    }
}

pub(crate) fn render(args: &RenderArgs) -> Result<()> {
    // One pool for the whole command: the load's parallel parse and mesh building use it
    // too (rather than rayon's global pool, which would be a second set of threads).
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("could not start worker threads")?;
    pool.install(|| render_in(args))
}

/// What to draw, where it came from.
struct Input {
    scene: Scene,
    file: Option<SceneFile>,
    /// For messages: the model's path or "the demo scene".
    source: String,
}

fn render_in(args: &RenderArgs) -> Result<()> {
    let t0 = Instant::now();
    let input = read_input(args)?;
    // Nothing to draw (a text file named `.obj`) is an error, not an empty image.
    input
        .scene
        .check_drawable(std::path::Path::new(&input.source))
        .map_err(anyhow::Error::msg)?;
    for w in &input.scene.report.warnings {
        eprintln!("warning: {w}");
    }
    let settings = settings(args, &input)?;
    // With only --animated, no per-frame image is written.
    let out = match (&args.output, &args.sequence.animated) {
        (None, Some(_)) => None,
        _ => Some(output(args, &input)?),
    };
    let t_load = t0.elapsed();
    let peak_load = super::peak_resident_bytes();
    let (w, h) = args
        .size
        .or_else(|| input.file.as_ref().and_then(SceneFile::size))
        .unwrap_or(scenefile::DEFAULT_SIZE);
    let aspect = w as f32 / h as f32;
    let camera = camera(args, &input, aspect)?;
    let framed = framed_distance(args, &input);
    let up = up_of(args, &input);
    let mut frames = sequence::frames(&args.sequence, camera, &input.scene, aspect, framed, up)?;
    if let (Some(CameraArg::Gltf(n)), None) = (args.camera, args.sequence.turntable) {
        // A file's camera under an animated node moves with it, and its animated field of
        // view (KHR_animation_pointer) applies unless --fov or --zoom sets one.
        let fov = args.fov.is_none() && args.zoom.is_none();
        for f in &mut frames {
            f.follow = Some(n);
            f.follow_fov = fov;
        }
    }
    let outputs = Outputs::plan(out.clone(), &args.sequence, frames.len(), (w, h))?;
    let reference = match (&args.compare, &out) {
        (Some(_), _) if frames.len() != 1 || outputs.animated.is_some() => bail!(
            "--compare compares one image: {} frames would be rendered",
            frames.len()
        ),
        (Some(r), Some(o)) => Some(compare::Reference::load(r, o, (w, h))?),
        (Some(_), None) => bail!("--compare needs an image to compare (give -o OUT.png)"),
        (None, _) => None,
    };
    let comparison = match &input.file {
        Some(f) => f.comparison(&input.scene, &settings)?,
        None => None,
    };
    let t = Instant::now();
    let mut prepared = PreparedScene::new(input.scene);
    sequence::frame_animation(&mut frames, &mut prepared, aspect, framed);
    let t_prepare = t.elapsed();
    let mut renderer = Renderer::new();
    let draw = |prepared: &PreparedScene, view: &View| -> Result<Drawn> {
        Ok(match &comparison {
            Some(cmp) => {
                let (img, stats) = cmp.render(prepared, view);
                Drawn {
                    width: img.width,
                    height: img.height,
                    rgb: img.rgb,
                    stats,
                }
            }
            None => {
                let stats = renderer.render(prepared, &settings, view).stats;
                let rgb = renderer
                    .target()
                    .context("no frame was rendered")?
                    .to_srgb8();
                Drawn {
                    width: view.width,
                    height: view.height,
                    rgb,
                    stats,
                }
            }
        })
    };
    let source = input.source.clone();
    let description = describe(&settings);
    let compared = std::cell::RefCell::new(None);
    let write = |path: &Path, w: u32, h: u32, rgb: Vec<u8>| {
        write_image(path, w, h, &rgb, &source, &description)?;
        if let Some(reference) = &reference {
            let tol = args.tolerance.unwrap_or_default();
            *compared.borrow_mut() = Some(reference.check(path, (w, h), &rgb, tol));
        }
        Ok(())
    };
    let done = sequence::run(&frames, (w, h), prepared, &outputs, draw, write)?;
    // A sequence always says where its frames went (on stderr when stdout holds the stats).
    let sequence = frames.len() > 1 || outputs.animated.is_some();
    let mut report = Vec::new();
    match done.images.as_slice() {
        [one] if frames.len() == 1 && (sequence || args.output.is_none()) => {
            report.push(format!("wrote {}", one.display()));
        }
        [first, last] => report.push(format!(
            "wrote {} frames: {} to {}",
            frames.len(),
            first.display(),
            last.display()
        )),
        _ => {}
    }
    if let (Some((path, aw, ah)), Some(a)) = (&done.animated, &outputs.animated) {
        report.push(format!(
            "wrote {}: {} frames of {aw}x{ah} at {} fps",
            path.display(),
            frames.len(),
            a.fps
        ));
    }
    if args.stats {
        let s = &done.stats;
        let ms = |d: std::time::Duration| (d.as_secs_f64() * 1e6).round() / 1e3;
        let mut json = serde_json::json!({
            "triangles_in": s.triangles_in,
            "culled": s.culled_frustum + s.culled_backface + s.culled_degenerate,
            "clipped": s.clipped,
            "drawn": s.drawn,
            "tiles": s.tiles,
            "pixels_shaded": s.pixels_shaded,
            "shader_calls": s.shader_calls,
            "lights_skipped": s.lights_skipped,
            "shadow_maps": s.shadow_maps,
            "counters": s,
            "ms": {
                "load": ms(t_load),
                "prepare": ms(t_prepare),
                "raster_shade": ms(done.raster),
                "encode": ms(done.encode),
            },
            // Peak resident memory of the process (Linux; null elsewhere): after loading,
            // and at the end.
            "peak_mb": {
                "load": peak_load.map(mb),
                "total": super::peak_resident_bytes().map(mb),
            },
        });
        if frames.len() > 1 {
            // Counters and times are summed over the frames.
            json["frames"] = frames.len().into();
        }
        say!("{json}");
        for line in report {
            eprintln!("{line}");
        }
    } else {
        for line in report {
            say!("{line}");
        }
    }
    match compared.into_inner() {
        Some(Ok(line)) if args.stats => eprintln!("{line}"),
        Some(Ok(line)) => say!("{line}"),
        Some(Err(e)) => return Err(e),
        None if args.compare.is_some() => bail!("--compare: no image was written"),
        None => {}
    }
    Ok(())
}

/// Bytes as MB (10^6), one decimal.
fn mb(bytes: u64) -> f64 {
    (bytes as f64 / 1e5).round() / 10.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_flag_forms() {
        assert_eq!(parse_camera("gltf:2"), Ok(CameraArg::Gltf(2)));
        assert_eq!(
            parse_camera("10,-5"),
            Ok(CameraArg::Orbit(10.0, -5.0, None))
        );
        assert_eq!(
            parse_camera("10,20,3"),
            Ok(CameraArg::Orbit(10.0, 20.0, Some(3.0)))
        );
        for bad in ["gltf:x", "gltf:-1", "1", "1,2,0", "1,nan"] {
            assert!(parse_camera(bad).is_err(), "{bad}");
        }
    }
}
