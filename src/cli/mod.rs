//! Subcommands: `view`, `render`, `info`, `bench`, `color`, `chroma`. Without a subcommand (or
//! with just a model file) the viewer opens; without a display it renders to a PNG instead.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context, Result};

/// `println!` that returns an error instead of panicking when stdout is closed (e.g. `| head`).
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)?
    }};
}
use clap::{Args, Parser, Subcommand};
use glam::Vec3;

use realist::load::{self, LoadOptions};
use realist::mesh::NormalOptions;
use realist::render::{self, PreparedScene, RenderOptions};
use realist::scene::{self, Camera, Scene};
use realist::shade::Shading;

mod accuracy;
mod bench;
mod chroma;
mod color;
mod info;

use bench::bench;
use chroma::{chroma, ChromaArgs};
use color::{color, ColorArgs};
use info::info;

#[derive(Parser)]
#[command(
    name = "realist",
    version,
    about = "glTF 2.0 / OBJ viewer and material toolkit with a tiled CPU rasterizer"
)]
#[command(args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// A model to open in the viewer (as `realist view MODEL`).
    #[arg(value_name = "MODEL")]
    model: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Open the viewer on a model (or the built-in demo); without a display, render it to a
    /// PNG instead.
    View(ViewArgs),
    /// Render a model (or the built-in demo) headless to a PNG.
    Render(RenderArgs),
    /// Print the load report and the topology of every mesh.
    Info(InfoArgs),
    /// Time warm frames of a model (median of rounds), with the camera and light of the
    /// llvmpipe peer harness (../shared/peer) so the two can be compared as ratios.
    Bench(BenchArgs),
    /// Convert one colour (#rrggbb or r,g,b in [0,1], encoded sRGB) to other colour models.
    Color(ColorArgs),
    /// Draw the CIE chromaticity diagram (gamuts, Planckian locus, an image's pixels).
    Chroma(ChromaArgs),
}

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(crate) struct BenchArgs {
    #[command(subcommand)]
    sub: Option<BenchCommand>,
    /// Model file (.obj, .gltf, .glb).
    #[arg(required = true)]
    model: Option<PathBuf>,
    /// Comma-separated sizes, e.g. 1920x1080,640x480.
    #[arg(long, default_value = "1920x1080")]
    res: String,
    /// Comma-separated shading modes.
    #[arg(long, default_value = "phong,gouraud,flat")]
    shading: String,
    /// Rounds; each round renders frames for about 0.5 s and reports its median.
    #[arg(long, default_value_t = 5)]
    rounds: usize,
    #[arg(long)]
    threads: Option<usize>,
    /// Draw without back-face culling, as the peer harness does (the same work as llvmpipe).
    #[arg(long)]
    no_cull: bool,
}

#[derive(Subcommand)]
pub(crate) enum BenchCommand {
    /// Time versus error: vary one knob at a time against an analytic reference, write
    /// results.csv and pareto.png, print the Pareto-optimal settings.
    Accuracy(accuracy::AccuracyArgs),
    /// Frame time of the llvmpipe peer harness's exact scene (../shared/peer): one reused
    /// renderer, warm-up then timed frames, one JSON line; --png writes the last frame as the
    /// peer stores it (linear values, no sRGB).
    Frame(bench::FrameArgs),
    /// Mean absolute 8-bit difference of two RGBA PNGs over interior (non-silhouette) pixels.
    #[command(hide = true)]
    Diff(bench::DiffArgs),
}

#[derive(Args)]
struct RenderArgs {
    /// Model file (.obj, .gltf, .glb).
    #[arg(required_unless_present = "demo", conflicts_with = "demo")]
    model: Option<PathBuf>,
    /// Render the built-in demo scene (the seed's three spheres).
    #[arg(long)]
    demo: bool,
    /// Output PNG.
    #[arg(short, long)]
    output: PathBuf,
    /// Image size WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    size: (u32, u32),
    /// wireframe, flat, gouraud, phong, blinn, textured, normals, depth or uv (default: phong;
    /// the demo keeps its per-sphere styles unless a mode is given).
    #[arg(long)]
    shading: Option<Shading>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Orbit camera: azimuth,elevation in degrees, optionally ,distance in scene units
    /// (default distance frames the scene).
    #[arg(long, value_parser = parse_camera)]
    camera: Option<(f32, f32, Option<f32>)>,
    /// Vertical field of view in degrees (default 45).
    #[arg(long, conflicts_with = "zoom")]
    fov: Option<f32>,
    /// The seed's zoom factor, zoom = 1/tan(fov/2) (1 = 90 degrees, 2.414 = 45 degrees).
    #[arg(long)]
    zoom: Option<f32>,
    /// Texture applied to meshes that have UVs but no material texture (e.g. spot.obj).
    #[arg(long)]
    texture: Option<PathBuf>,
    /// Print one JSON object with counters and per-stage milliseconds.
    #[arg(long)]
    stats: bool,
    /// Draw every material double-sided (no back-face culling).
    #[arg(long)]
    double_sided: bool,
    /// Multisampling: 1 (off) or 4 coverage and depth samples per pixel, shaded once per
    /// pixel and triangle, averaged in linear light.
    #[arg(long, default_value_t = 1, value_parser = parse_msaa)]
    msaa: u32,
    #[command(flatten)]
    normals: NormalArgs,
}

#[derive(Args)]
pub(crate) struct NormalArgs {
    /// Crease angle in degrees for averaged normals, or "off" to average across every edge.
    #[arg(long, default_value = "60")]
    crease: String,
    /// Weighting of averaged normals: angle, area or uniform (the seed's plain average).
    #[arg(long, default_value = "angle")]
    weighting: String,
}

#[derive(Args)]
struct ViewArgs {
    /// Model file (.obj, .gltf, .glb); the built-in demo if absent.
    model: Option<PathBuf>,
    /// Window's inner size WIDTHxHEIGHT in points.
    #[arg(long, default_value = "1440x900", value_parser = parse_size)]
    window: (u32, u32),
    /// Start with the side panels hidden (Tab shows them).
    #[arg(long)]
    no_panels: bool,
}

#[derive(Args)]
pub(crate) struct InfoArgs {
    /// Model file (.obj, .gltf, .glb).
    model: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    normals: NormalArgs,
}

pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or("expected WIDTHxHEIGHT, e.g. 1280x720")?;
    let w: u32 = w.trim().parse().map_err(|_| format!("bad width '{w}'"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("bad height '{h}'"))?;
    if !(1..=16384).contains(&w) || !(1..=16384).contains(&h) {
        return Err("width and height must be between 1 and 16384".into());
    }
    Ok((w, h))
}

/// `--msaa`: a sample count the rasterizer supports.
pub(crate) fn parse_msaa(s: &str) -> Result<u32, String> {
    let n: u32 = s
        .trim()
        .parse()
        .map_err(|_| format!("bad sample count '{s}'"))?;
    if realist::raster::SAMPLE_COUNTS.contains(&n) {
        Ok(n)
    } else {
        Err(format!(
            "{n} samples per pixel is not supported (choose from {:?})",
            realist::raster::SAMPLE_COUNTS
        ))
    }
}

fn parse_camera(s: &str) -> Result<(f32, f32, Option<f32>), String> {
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
        [a, e] => Ok((a, e, None)),
        [a, e, d] if d > 0.0 => Ok((a, e, Some(d))),
        [_, _, _] => Err("--camera distance must be positive".into()),
        _ => Err("expected --camera azimuth,elevation[,distance]".into()),
    }
}

impl NormalArgs {
    fn options(&self) -> Result<NormalOptions> {
        let crease_degrees = if self.crease.eq_ignore_ascii_case("off") {
            None
        } else {
            let d: f32 = self
                .crease
                .parse()
                .with_context(|| format!("bad --crease '{}'", self.crease))?;
            if !(0.0..=180.0).contains(&d) {
                bail!("--crease must be between 0 and 180 degrees, or off");
            }
            Some(d)
        };
        let weighting = match self.weighting.to_ascii_lowercase().as_str() {
            "angle" => realist::mesh::Weighting::Angle,
            "area" => realist::mesh::Weighting::Area,
            "uniform" => realist::mesh::Weighting::Uniform,
            w => bail!("unknown --weighting '{w}' (expected angle, area or uniform)"),
        };
        Ok(NormalOptions {
            weighting,
            crease_degrees,
        })
    }
}

pub fn run() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Some(Command::Render(args)) => render(&args),
        Some(Command::Info(args)) => info(&args),
        Some(Command::Bench(args)) => match &args.sub {
            Some(BenchCommand::Accuracy(a)) => accuracy::accuracy(a),
            Some(BenchCommand::Frame(a)) => bench::frame(a),
            Some(BenchCommand::Diff(a)) => bench::diff(a),
            None => bench(&args),
        },
        Some(Command::Color(args)) => color(&args),
        Some(Command::Chroma(args)) => chroma(&args),
        Some(Command::View(args)) => view(args.model, args.window, args.no_panels),
        None => view(cli.model, (1440, 900), false),
    }
}

/// The viewer, or without a display a headless render to a PNG named on the way out.
fn view(model: Option<PathBuf>, window: (u32, u32), no_panels: bool) -> Result<()> {
    #[cfg(feature = "viewer")]
    {
        if realist::viewer::display_available() {
            match realist::viewer::run(model.clone(), window, no_panels) {
                Ok(()) => return Ok(()),
                Err(e) => {
                    // winit's message carries a source location; its last part is the reason.
                    let reason = e.rsplit(": ").next().unwrap_or(&e);
                    say!("No window could be opened ({reason}): rendering to a PNG instead.");
                }
            }
        } else {
            say!("No display (DISPLAY and WAYLAND_DISPLAY are unset): rendering to a PNG instead.");
        }
    }
    #[cfg(not(feature = "viewer"))]
    {
        let _ = (window, no_panels);
        say!("Built without the viewer (feature `viewer`): rendering to a PNG instead.");
    }
    let out = match &model {
        Some(m) => PathBuf::from(format!(
            "realist-{}.png",
            m.file_stem()
                .map_or("model".into(), |s| s.to_string_lossy())
        )),
        None => PathBuf::from("realist-demo.png"),
    };
    let args = RenderArgs {
        demo: model.is_none(),
        model,
        output: out.clone(),
        size: (1280, 720),
        shading: None,
        threads: None,
        camera: None,
        fov: None,
        zoom: None,
        texture: None,
        stats: false,
        double_sided: false,
        msaa: 4,
        normals: NormalArgs {
            crease: "60".into(),
            weighting: "angle".into(),
        },
    };
    render(&args)?;
    say!(
        "Wrote {}",
        std::fs::canonicalize(&out).unwrap_or(out).display()
    );
    Ok(())
}

pub(crate) fn load_model(path: &Path, normals: &NormalArgs) -> Result<Scene> {
    let opts = LoadOptions {
        normals: normals.options()?,
        ..LoadOptions::default()
    };
    Ok(load::load(path, &opts)?)
}

fn render(args: &RenderArgs) -> Result<()> {
    // One pool for the whole command: the load's parallel parse and mesh building use it
    // too (rather than rayon's global pool, which would be a second set of threads).
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("could not start worker threads")?;
    pool.install(|| render_in(args, &pool))
}

fn render_in(args: &RenderArgs, pool: &rayon::ThreadPool) -> Result<()> {
    let t0 = Instant::now();
    let scene = match &args.model {
        Some(path) => load_model(path, &args.normals)?,
        None => scene::demo(),
    };
    for w in &scene.report.warnings {
        eprintln!("warning: {w}");
    }
    if args.texture.is_some() && args.shading.is_some_and(|m| m != Shading::Textured) {
        eprintln!(
            "warning: --texture is only drawn in textured mode (the default for models with UVs)"
        );
    }
    let texture = match &args.texture {
        Some(p) => Some(Arc::new(load::load_texture(p)?)),
        None => None,
    };
    let t_load = t0.elapsed();
    let (w, h) = args.size;
    let aspect = w as f32 / h as f32;
    let yfov = match (args.fov, args.zoom) {
        (Some(f), _) if f.is_finite() && f > 0.0 && f < 180.0 => Some(f.to_radians()),
        (Some(f), _) => bail!("--fov {f}: expected degrees between 0 and 180"),
        (None, Some(z)) if z.is_finite() && z > 0.0 => Some(2.0 * (1.0 / z).atan()),
        (None, Some(z)) => bail!("--zoom {z}: expected a positive number"),
        (None, None) => None,
    };
    let camera = match (args.camera, yfov) {
        (Some((az, el, dist)), _) => Some(orbit_camera(&scene, aspect, az, el, dist, yfov)),
        (None, _) if args.demo => scene.cameras.first().cloned().map(|mut c| {
            c.yfov = yfov.unwrap_or(c.yfov);
            c
        }),
        (None, Some(_)) => Some(orbit_camera(&scene, aspect, 35.0, 25.0, None, yfov)),
        (None, None) => None,
    };
    let opts = RenderOptions {
        width: w,
        height: h,
        shading: args.shading,
        camera,
        texture,
        double_sided: args.double_sided,
        msaa: args.msaa,
        ..RenderOptions::default()
    };
    let (prepared, t_prepare, frame, t_raster) = pool.install(|| {
        let t = Instant::now();
        let prepared = PreparedScene::new(scene);
        let t_prepare = t.elapsed();
        let t = Instant::now();
        let frame = render::render(&prepared, &opts);
        (prepared, t_prepare, frame, t.elapsed())
    });
    let t = Instant::now();
    // The scene is freed on another thread while the image is encoded (freeing its large
    // buffers took about 1 ms; the PNG encoder leaves a core idle).
    let written = std::thread::scope(|scope| {
        scope.spawn(move || drop(prepared));
        write_image(&args.output, &frame)
    });
    written.with_context(|| format!("could not write {}", args.output.display()))?;
    let t_encode = t.elapsed();
    if args.stats {
        let s = &frame.stats;
        let ms = |d: std::time::Duration| (d.as_secs_f64() * 1e6).round() / 1e3;
        let json = serde_json::json!({
            "triangles_in": s.triangles_in,
            "culled": s.culled_frustum + s.culled_backface + s.culled_degenerate,
            "clipped": s.clipped,
            "drawn": s.drawn,
            "tiles": s.tiles,
            "pixels_shaded": s.pixels_shaded,
            "shader_calls": s.shader_calls,
            "counters": s,
            "ms": {
                "load": ms(t_load),
                "prepare": ms(t_prepare),
                "raster_shade": ms(t_raster),
                "encode": ms(t_encode),
            },
        });
        say!("{json}");
    }
    Ok(())
}

/// Writes the frame as 8-bit sRGB: PNG (fast deflate, `Up` filter, see below) for a `.png`
/// name, else the format the extension names.
fn write_image(path: &Path, frame: &render::Frame) -> Result<()> {
    let (w, h) = (frame.target.width, frame.target.height);
    let rgb = frame.srgb8();
    let png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png {
        let img = image::RgbImage::from_raw(w, h, rgb).context("framebuffer size mismatch")?;
        return Ok(img.save(path)?);
    }
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    use image::ImageEncoder;
    // Measured on the bunny at 1920x1080 (PNG part only; the sRGB encode is another 7.7
    // ms): adaptive filtering 6.3 ms for 226 KB, `Up` 2.5 ms for 278 KB, `Sub` 3.7 ms for
    // 261 KB, `Paeth` 5 ms for 223 KB; no filter is slower (6 MB to write).
    let filter = FilterType::Up;
    let file = std::io::BufWriter::with_capacity(1 << 20, std::fs::File::create(path)?);
    PngEncoder::new_with_quality(file, CompressionType::Fast, filter).write_image(
        &rgb,
        w,
        h,
        image::ExtendedColorType::Rgb8,
    )?;
    Ok(())
}

/// An orbit camera around the scene's bounding sphere.
fn orbit_camera(
    scene: &Scene,
    aspect: f32,
    az: f32,
    el: f32,
    dist: Option<f32>,
    yfov: Option<f32>,
) -> Camera {
    let (lo, hi) = scene.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6));
    let yfov = yfov.unwrap_or(realist::scene::DEFAULT_YFOV);
    let framed = Camera::frame_box_fov(lo, hi, aspect, az, el, yfov);
    match dist {
        None => framed,
        Some(d) => {
            let mut cam = Camera::orbit(center, az, el, d, framed.yfov);
            cam.fit(center, radius);
            cam
        }
    }
}
