//! Subcommands: `view`, `render`, `info`, `bench`, `color`, `chroma`, `batch`, `thumbnail`.
//! Without a subcommand (or with just a model file) the viewer opens; without a display it
//! renders to a PNG instead.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// `println!` that returns an error instead of panicking when stdout is closed (e.g. `| head`).
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)?
    }};
}
use clap::{Args, Parser, Subcommand};

use realist::load::{self, LoadOptions};
use realist::mesh::NormalOptions;
use realist::scene::Scene;

mod accuracy;
mod batch;
mod bench;
mod chroma;
mod color;
mod info;
mod lighting;
mod render;
mod sequence;
mod thumbnail;

use bench::bench;
use chroma::{chroma, ChromaArgs};
use color::{color, ColorArgs};
use info::info;
use render::{render, RenderArgs};

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
    /// A model or scene file to open in the viewer (as `realist view MODEL`).
    #[arg(value_name = "MODEL")]
    model: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Open the viewer on a model or scene file (or the built-in demo); without a display,
    /// render it to a PNG instead.
    View(ViewArgs),
    /// Render a model (or the built-in demo) headless to a PNG.
    Render(Box<RenderArgs>),
    /// Print the load report and the topology of every mesh.
    Info(InfoArgs),
    /// Time warm frames of a model (median of rounds), with the camera and light that
    /// `benches/peer.sh` gives Mesa's llvmpipe, so the two can be compared as ratios.
    Bench(BenchArgs),
    /// Convert one colour (#rrggbb or r,g,b in [0,1], encoded sRGB) to other colour models.
    Color(ColorArgs),
    /// Draw the CIE chromaticity diagram (gamuts, Planckian locus, an image's pixels).
    Chroma(ChromaArgs),
    /// Render a still, a turntable or a thumbnail of every model in folders or a list, one
    /// process per model, with a manifest, resume and --shard I/N for job arrays.
    Batch(Box<batch::BatchArgs>),
    /// Write a PNG thumbnail of a model (the freedesktop thumbnailer; --install registers it).
    Thumbnail(thumbnail::ThumbnailArgs),
}

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(crate) struct BenchArgs {
    #[command(subcommand)]
    sub: Option<BenchCommand>,
    /// Model file (.obj, .gltf, .glb, .stl, .ply).
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
    /// Frame time of the scene `benches/peer.sh` times Mesa's llvmpipe on: one reused
    /// renderer, warm-up then timed frames, one JSON line; --png writes the last frame as
    /// the llvmpipe harness stores it (linear values, no sRGB).
    Frame(bench::FrameArgs),
    /// Nanoseconds per shaded pixel on large triangles in each shading mode, and per triangle
    /// of set-up, on one thread by default (per core), beside the README's machine model.
    Micro(bench::MicroArgs),
    /// Time to pose a skinned mesh (the built-in tube: animation, joint matrices, skinning
    /// of every vertex, bounds), one JSON line.
    Skin(bench::SkinArgs),
    /// Ray queries of the traced modes (the textbook's §9.6): hierarchy build time and
    /// Mrays/s of primary and shadow rays on the peer's mesh on the ground plane, one JSON
    /// line.
    Rays(bench::RaysArgs),
    /// Mean absolute 8-bit difference of two RGBA PNGs over interior (non-silhouette) pixels.
    #[command(hide = true)]
    Diff(bench::DiffArgs),
}

#[derive(Args)]
pub(crate) struct NormalArgs {
    /// Crease angle in degrees for averaged normals, or "off" to average across every edge.
    #[arg(long, default_value = "60")]
    crease: String,
    /// Weighting of averaged normals: angle, area or uniform (the textbook's plain average).
    #[arg(long, default_value = "angle")]
    weighting: String,
}

#[derive(Args)]
struct ViewArgs {
    /// Model file (.obj, .gltf, .glb, .stl, .ply) or scene file (.toml, .json); the built-in demo if
    /// absent.
    model: Option<PathBuf>,
    /// Window's inner size WIDTHxHEIGHT in points.
    #[arg(long, default_value = "1440x900", value_parser = parse_size)]
    window: (u32, u32),
    /// Start with the side panels hidden (Tab shows them).
    #[arg(long)]
    no_panels: bool,
    /// Open animated files paused (Space plays); by default they play at once, looping.
    #[arg(long)]
    paused: bool,
    /// The world's up axis, y (default) or z (scans and CAD models that lie on their back;
    /// Ctrl+Y and Ctrl+Z change it in the window).
    #[arg(long, value_name = "y|z")]
    up: Option<realist::scene::Up>,
}

#[derive(Args)]
pub(crate) struct InfoArgs {
    /// Model file (.obj, .gltf, .glb, .stl, .ply).
    model: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Generate texture coordinates as `render --uv` does (the textbook's §9.5) and report
    /// them.
    #[arg(long, value_parser = render::parse_uv)]
    uv: Option<realist::scenefile::schema::UvChoice>,
    /// Report scene N of a glTF file (0-based) instead of its default scene.
    #[arg(long, value_name = "N")]
    scene: Option<usize>,
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

/// `--msaa`: a sample count the rasterizer supports ([`realist::render::NUMERIC`]'s `msaa`).
pub(crate) fn parse_msaa(s: &str) -> Result<u32, String> {
    realist::render::numeric("msaa").parser_u32()(s)
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
            Some(BenchCommand::Micro(a)) => bench::micro(a),
            Some(BenchCommand::Diff(a)) => bench::diff(a),
            Some(BenchCommand::Skin(a)) => bench::skin(a),
            Some(BenchCommand::Rays(a)) => bench::rays(a),
            None => bench(&args),
        },
        Some(Command::Color(args)) => color(&args),
        Some(Command::Chroma(args)) => chroma(&args),
        Some(Command::Batch(args)) => batch::batch(&args),
        Some(Command::Thumbnail(args)) => thumbnail::thumbnail(&args),
        Some(Command::View(args)) => view(
            args.model,
            args.window,
            args.no_panels,
            args.paused,
            args.up,
        ),
        None => view(cli.model, (1440, 900), false, false, None),
    }
}

/// The viewer, or without a display a headless render to a PNG named on the way out.
fn view(
    model: Option<PathBuf>,
    window: (u32, u32),
    no_panels: bool,
    paused: bool,
    up: Option<realist::scene::Up>,
) -> Result<()> {
    #[cfg(feature = "viewer")]
    {
        if realist::viewer::display_available() {
            let opts = realist::viewer::ViewerOptions {
                model: model.clone(),
                hide_panels: no_panels,
                paused,
                up,
                ..Default::default()
            };
            match realist::viewer::run(opts, window) {
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
        let _ = (window, no_panels, paused);
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
        output: Some(out.clone()),
        size: None,
        shading: None,
        threads: None,
        camera: None,
        up,
        fov: None,
        zoom: None,
        texture: None,
        bump: None,
        bump_scale: None,
        normal_map: None,
        uv: None,
        filter: None,
        stats: false,
        double_sided: false,
        vertex_blinn: false,
        flat_last_vertex: false,
        msaa: Some(4),
        samples: None,
        ray_depth: None,
        subpixel_bits: None,
        scene: None,
        point_size: None,
        line_width: None,
        variant: None,
        compare: None,
        tolerance: None,
        lighting: lighting::LightingArgs::default(),
        normals: NormalArgs {
            crease: "60".into(),
            weighting: "angle".into(),
        },
        sequence: sequence::SequenceArgs::default(),
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

/// The peak resident memory of this process so far (`VmHWM` of `/proc/self/status`), where
/// the system reports it (Linux); `None` elsewhere.
pub(crate) fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb * 1024)
}
