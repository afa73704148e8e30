//! `realist bench frame MODEL`: the frame time of the llvmpipe peer harness's exact scene
//! (`peer_scene.rs`), one reused [`Renderer`], one JSON line.
//!
//! Timed: `Renderer::render` (clear and draw; nothing is allocated after the warm-up frames).
//! Not timed: loading, `PreparedScene::new`, and the read-back, which is timed separately in
//! a second run of frames (`read_ms`: the sRGB8 encode into a preallocated buffer;
//! `frame_read_ms`: frame plus read-back, the peer's `ms_read_median`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::render::{PreparedScene, Renderer, Settings, StageTimes, VertexLighting, View};
use realist::shade::Shading;

use super::median;
use super::peer_scene::{self, CLEAR};
use crate::cli::lighting::LightingArgs;
use crate::cli::{parse_msaa, parse_size};

#[derive(Args)]
pub(crate) struct FrameArgs {
    /// An OBJ file (read exactly as the peer harness reads it), or sphere:N, the peer's UV
    /// sphere of about N triangles (sphere:1000000 is its sphere1m).
    model: String,
    /// Image size WIDTHxHEIGHT.
    #[arg(long, default_value = "1920x1080", value_parser = parse_size)]
    size: (u32, u32),
    /// phong (Blinn-Phong per pixel, the peer's `phong`), gouraud, flat, or textured (the
    /// peer's `tex`: phong with its 1024x1024 procedural texture, trilinear); pbr and
    /// whitted are realist's own (no peer row).
    #[arg(long, default_value = "phong", value_parser = parse_mode)]
    shading: PeerMode,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Timed frames (0: as many as fit in about 2 s, 10 to 500).
    #[arg(long, default_value_t = 0)]
    frames: usize,
    /// Untimed frames first.
    #[arg(long, default_value_t = 3)]
    warmup: usize,
    /// Write the last frame as the peer stores it: linear values x 255, rounded, clamped, no
    /// sRGB encoding; alpha 0 where nothing was drawn (the peer clears alpha to 0).
    #[arg(long)]
    png: Option<PathBuf>,
    /// Light Gouraud and flat with the textbook's formulas (Phong's R·V highlight, flat
    /// facets at their centroids) instead of the peer's (Blinn's N·H, flat triangles at
    /// their last vertex: `VertexLighting::GL`), as `realist render` does by default.
    #[arg(long)]
    textbook: bool,
    /// Multisampling: 1 (off, as the peer) or 4 samples per pixel.
    #[arg(long, default_value_t = 1, value_parser = parse_msaa)]
    msaa: u32,
    /// Fog, tone mapping, shadows, ground plane and extra lights (as for `render`; the
    /// peer has none of them, so a frame with them is not comparable to the peer's).
    #[command(flatten)]
    lighting: LightingArgs,
}

/// The peer's shading modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PeerMode {
    Phong,
    Gouraud,
    Flat,
    Textured,
    /// Not a peer mode: glTF metallic-roughness with the default environment, to compare
    /// its cost with `phong` on the same scene.
    Pbr,
    /// Not a peer mode: `pbr` with ray-traced shadows (Whitted's model, the textbook's
    /// §9.6.1): the hybrid frame of issue 38 (with `--ground`, the bunny on a plane).
    Whitted,
}

impl PeerMode {
    fn name(self) -> &'static str {
        match self {
            PeerMode::Phong => "phong",
            PeerMode::Gouraud => "gouraud",
            PeerMode::Flat => "flat",
            PeerMode::Textured => "textured",
            PeerMode::Pbr => "pbr",
            PeerMode::Whitted => "whitted",
        }
    }

    /// realist's mode (Gouraud and flat with the peer's formulas unless `--textbook`).
    fn shading(self) -> Shading {
        match self {
            PeerMode::Phong => Shading::Blinn,
            PeerMode::Gouraud => Shading::Gouraud,
            PeerMode::Flat => Shading::Flat,
            PeerMode::Textured => Shading::Textured,
            PeerMode::Pbr => Shading::Pbr,
            PeerMode::Whitted => Shading::Whitted,
        }
    }
}

fn parse_mode(s: &str) -> Result<PeerMode, String> {
    Ok(match s.to_ascii_lowercase().as_str() {
        "phong" | "blinn" => PeerMode::Phong,
        "gouraud" => PeerMode::Gouraud,
        "flat" => PeerMode::Flat,
        "textured" | "tex" => PeerMode::Textured,
        "pbr" => PeerMode::Pbr,
        "whitted" => PeerMode::Whitted,
        _ => {
            return Err(format!(
                "unknown shading '{s}' (expected phong, gouraud, flat, textured, pbr or whitted)"
            ))
        }
    })
}

const AUTO_SECONDS: f64 = 2.0;
const AUTO_FRAMES: (usize, usize) = (10, 500);
/// Frames of the read-back run (at most).
const READ_FRAMES: usize = 20;

pub(crate) fn frame(args: &FrameArgs) -> Result<()> {
    let t0 = Instant::now();
    let (name, mesh) = peer_scene::peer_mesh(&args.model)?;
    let textured = args.shading == PeerMode::Textured;
    if textured && mesh.uvs.is_none() {
        bail!(
            "{}: no texture coordinates (textured needs vt on every face corner)",
            args.model
        );
    }
    let scene = peer_scene::scene(&name, mesh, textured)?;
    let scene_lights = scene.lights.clone();
    let t_load = t0.elapsed();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("could not start worker threads")?;
    let t = Instant::now();
    let prepared = pool.install(|| PreparedScene::new(scene));
    let t_prepare = t.elapsed();
    let (w, h) = args.size;
    let mut settings = Settings {
        shading: Some(args.shading.shading()),
        background: CLEAR,
        double_sided: true,
        msaa: args.msaa,
        vertex_lighting: if args.textbook {
            VertexLighting::default()
        } else {
            VertexLighting::GL
        },
        ..Settings::default()
    };
    args.lighting.apply(&mut settings, &scene_lights)?;
    let view = View {
        camera: peer_scene::camera(),
        width: w,
        height: h,
    };
    let mut renderer = Renderer::new();
    let mut pixels = vec![[0u8; 4]; w as usize * h as usize];
    let run = pool.install(|| {
        time_frames(
            args,
            &prepared,
            &settings,
            &view,
            &mut renderer,
            &mut pixels,
        )
    });
    let Run {
        mut frames,
        mut stages,
        mut reads,
        mut frame_reads,
    } = run;
    let n = frames.len();
    let (min, max) = frames
        .iter()
        .fold((f64::INFINITY, 0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let stage = |f: fn(&StageTimes) -> f64, v: &mut Vec<StageTimes>| {
        let mut x: Vec<f64> = v.iter().map(f).collect();
        round3(median(&mut x))
    };
    let stages_json = serde_json::json!({
        "setup": stage(|s| s.setup, &mut stages),
        "vertex": stage(|s| s.vertex, &mut stages),
        "raster": stage(|s| s.raster, &mut stages),
        "fill": stage(|s| s.fill, &mut stages),
        "resolve": stage(|s| s.resolve, &mut stages),
        "total": stage(|s| s.total, &mut stages),
    });
    if let Some(path) = &args.png {
        write_png(&renderer, path)?;
    }
    let report = renderer.report();
    let json = serde_json::json!({
        "mesh": name,
        "triangles": prepared.triangle_count(),
        "size": format!("{w}x{h}"),
        "shading": args.shading.name(),
        "realist_mode": args.shading.shading().name(),
        "threads": pool.current_num_threads(),
        "warmup": args.warmup,
        "frames": n,
        "median_ms": round3(median(&mut frames)),
        "min_ms": round3(min),
        "max_ms": round3(max),
        "stages_ms": stages_json,
        "read_ms": round3(median(&mut reads)),
        "frame_read_ms": round3(median(&mut frame_reads)),
        "pixels_shaded": report.stats.pixels_shaded,
        "shader_calls": report.stats.shader_calls,
        "lights_skipped": report.stats.lights_skipped,
        "shadow_maps": report.stats.shadow_maps,
        "load_ms": round3(t_load.as_secs_f64() * 1e3),
        "prepare_ms": round3(t_prepare.as_secs_f64() * 1e3),
        "png": args.png.as_ref().map(|p| p.display().to_string()),
    });
    say!("{json}");
    Ok(())
}

/// Per-frame milliseconds.
struct Run {
    frames: Vec<f64>,
    stages: Vec<StageTimes>,
    reads: Vec<f64>,
    frame_reads: Vec<f64>,
}

/// Warm-up, the timed frames, then the read-back run; every buffer is reserved up front.
fn time_frames(
    args: &FrameArgs,
    prepared: &PreparedScene,
    settings: &Settings,
    view: &View,
    renderer: &mut Renderer,
    pixels: &mut [[u8; 4]],
) -> Run {
    let mut last = f64::INFINITY;
    for _ in 0..args.warmup.max(1) {
        let t = Instant::now();
        renderer.render(prepared, settings, view);
        last = t.elapsed().as_secs_f64();
    }
    let n = match args.frames {
        0 => ((AUTO_SECONDS / last.max(1e-6)) as usize).clamp(AUTO_FRAMES.0, AUTO_FRAMES.1),
        n => n,
    };
    let mut run = Run {
        frames: Vec::with_capacity(n),
        stages: Vec::with_capacity(n),
        reads: Vec::with_capacity(n.min(READ_FRAMES)),
        frame_reads: Vec::with_capacity(n.min(READ_FRAMES)),
    };
    for _ in 0..n {
        let t = Instant::now();
        let report = renderer.render(prepared, settings, view);
        run.frames.push(t.elapsed().as_secs_f64() * 1e3);
        run.stages.push(report.times);
    }
    for _ in 0..n.min(READ_FRAMES) {
        let t = Instant::now();
        renderer.render(prepared, settings, view);
        let r = Instant::now();
        renderer.write_rgba8(pixels);
        std::hint::black_box(&*pixels);
        run.reads.push(r.elapsed().as_secs_f64() * 1e3);
        run.frame_reads.push(t.elapsed().as_secs_f64() * 1e3);
    }
    run
}

/// The last frame as the peer's PNG: linear RGB x 255 rounded (no sRGB), alpha 255 where a
/// fragment was drawn (depth > 0) and 0 elsewhere.
fn write_png(renderer: &Renderer, path: &std::path::Path) -> Result<()> {
    let target = renderer.target().context("no frame was rendered")?;
    let fb = target.resolve();
    let byte = realist::color::unorm8;
    let bytes: Vec<u8> = fb
        .color
        .iter()
        .zip(&fb.depth)
        .flat_map(|(c, &d)| {
            [
                byte(c.x),
                byte(c.y),
                byte(c.z),
                if d > 0.0 { 255 } else { 0 },
            ]
        })
        .collect();
    // Linear values: no sRGB chunk.
    realist::color::png::Png {
        srgb: false,
        ..realist::color::png::Png::rgba(fb.width, fb.height, &bytes)
    }
    .with_text(
        "Description",
        "linear RGB x 255 (no sRGB encoding), alpha: drawn",
    )
    .write(path)
    .map_err(anyhow::Error::msg)
}

fn round3(x: f64) -> f64 {
    (x * 1e3).round() / 1e3
}
