//! `realist bench micro`: what the render core costs per unit of work, per core, beside the
//! machine model of issue 22 (README, "Performance against llvmpipe").
//!
//! - Large triangles: a plane of 4 x 4 quads (32 triangles) filling the image, facing the
//!   camera, drawn in each shading mode with the peer harness's light and material
//!   (`peer_scene`): nanoseconds of the fill stage per shaded pixel. The `empty` row draws
//!   the same plane facing away (culled): its frame time per pixel is the fixed cost of a
//!   frame (clear and store; the fill stage has no tile to fill). The textured plane repeats the peer's 1024 x 1024 texture
//!   three times across the width: about 1.6 texels a pixel, so trilinear filtering blends
//!   levels 0 and 1.
//! - Set-up: a grid of triangles of about two pixels each (2 x 2-pixel cells split in two,
//!   about a million at 1920x1080) in Gouraud: nanoseconds per triangle of the raster stage
//!   (clipping, culling, set-up and binning), per vertex of the vertex stage and per
//!   triangle of the fill.
//!
//! One thread by default, so the figures are per core. Medians of the timed frames; one
//! reused [`Renderer`], nothing allocated after the warm-up.

use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use glam::{Vec2, Vec3};

use realist::render::{PreparedScene, Renderer, Settings, StageTimes, VertexLighting, View};
use realist::scene::Camera;
use realist::shade::Shading;
use realist::simd::KernelKind;

use super::median;
use super::peer_scene::{self, PeerMesh, CLEAR};
use crate::cli::parse_size;

#[derive(Args)]
pub(crate) struct MicroArgs {
    /// Image size WIDTHxHEIGHT (each side 16 to 8192).
    #[arg(long, default_value = "1920x1080", value_parser = parse_size)]
    size: (u32, u32),
    /// Worker threads (default 1: the figures are per core).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Timed frames per row (0: as many as fit in about 1 s, 5 to 200).
    #[arg(long, default_value_t = 0)]
    frames: usize,
    /// One JSON line per row instead of the table.
    #[arg(long)]
    json: bool,
    /// Comma-separated rows to run (empty, flat, gouraud, blinn-phong, textured, pbr,
    /// set-up); all by default.
    #[arg(long)]
    rows: Option<String>,
}

const ROW_NAMES: [&str; 7] = [
    "empty",
    "flat",
    "gouraud",
    "blinn-phong",
    "textured",
    "pbr",
    "set-up",
];

/// The machine model's cost per shaded pixel per core (issue 22): Gouraud with depth about
/// 1 ns, Blinn-Phong about 3 ns, trilinear textured about 4 ns; set-up about 15 ns a
/// triangle.
const MODEL_SETUP_NS: f64 = 15.0;

struct Row {
    name: &'static str,
    shading: Shading,
    textured: bool,
    model_ns: Option<f64>,
}

const ROWS: [Row; 5] = [
    Row {
        name: "flat",
        shading: Shading::Flat,
        textured: false,
        model_ns: Some(1.0),
    },
    Row {
        name: "gouraud",
        shading: Shading::Gouraud,
        textured: false,
        model_ns: Some(1.0),
    },
    Row {
        name: "blinn-phong",
        shading: Shading::Blinn,
        textured: false,
        model_ns: Some(3.0),
    },
    Row {
        name: "textured",
        shading: Shading::Textured,
        textured: true,
        model_ns: Some(4.0),
    },
    Row {
        name: "pbr",
        shading: Shading::Pbr,
        textured: false,
        model_ns: None,
    },
];

const AUTO_SECONDS: f64 = 1.0;
const AUTO_FRAMES: (usize, usize) = (5, 200);
/// Repeats of the texture across the image's width.
const TEXTURE_REPEATS: f32 = 3.0;

pub(crate) fn micro(args: &MicroArgs) -> Result<()> {
    let (w, h) = args.size;
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        bail!("bench micro: --size {w}x{h}: each side must be 16 to 8192");
    }
    if args.threads == 0 || args.threads > 256 {
        bail!("bench micro: --threads {}: expected 1 to 256", args.threads);
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .context("could not start worker threads")?;
    let kernel = KernelKind::best();
    let view = View {
        camera: camera(),
        width: w,
        height: h,
    };
    let aspect = w as f32 / h as f32;
    let mut renderer = Renderer::new();
    let mut out = Vec::new();
    let pixels = u64::from(w) * u64::from(h);

    let wanted: Vec<&str> = match &args.rows {
        None => ROW_NAMES.to_vec(),
        Some(list) => {
            let v: Vec<&str> = list.split(',').map(str::trim).collect();
            if let Some(bad) = v.iter().find(|r| !ROW_NAMES.contains(r)) {
                bail!(
                    "bench micro: unknown row '{bad}' (expected {})",
                    ROW_NAMES.join(", ")
                );
            }
            v
        }
    };
    let want = |name: &str| wanted.contains(&name);

    // The fixed cost of a frame: the plane facing away.
    if want("empty") {
        let empty = pool.install(|| -> Result<Measured> {
            let mesh = grid(4, 4, aspect, true, false);
            measure(args, &mut renderer, mesh, Shading::Gouraud, false, &view)
        })?;
        out.push(serde_json::json!({
            "row": "empty",
            "work": "no triangle drawn (all face away): the fixed cost of a frame",
            "fill_ms": round3(empty.times.fill),
            "frame_ms": round3(empty.times.total),
            "ns_per_pixel": round3(empty.times.total * 1e6 / pixels as f64),
            "pixels_shaded": empty.pixels_shaded,
        }));
    }
    for row in ROWS.iter().filter(|r| want(r.name)) {
        let m = pool.install(|| -> Result<Measured> {
            let mesh = grid(4, 4, aspect, false, row.textured);
            measure(args, &mut renderer, mesh, row.shading, row.textured, &view)
        })?;
        let shaded = m.pixels_shaded.max(1) as f64;
        let ns = m.times.fill * 1e6 / shaded;
        out.push(serde_json::json!({
            "row": row.name,
            "work": format!("{} pixels shaded, {} triangles", m.pixels_shaded, m.triangles),
            "fill_ms": round3(m.times.fill),
            "frame_ms": round3(m.times.total),
            "ns_per_pixel": round3(ns),
            "model_ns": row.model_ns,
            "times_model": row.model_ns.map(|x| round3(ns / x)),
            "lanes_in_use": round3(m.pixels_shaded as f64 / (8.0 * m.shader_calls.max(1) as f64)),
            "pixels_shaded": m.pixels_shaded,
        }));
    }
    // Set-up: 2 x 2-pixel cells, two triangles each.
    let mut setup = None;
    if want("set-up") {
        let (cx, cy) = ((w / 2).max(1), (h / 2).max(1));
        let tiny = pool.install(|| -> Result<Measured> {
            let mesh = grid(cx, cy, aspect, false, false);
            measure(args, &mut renderer, mesh, Shading::Gouraud, false, &view)
        })?;
        let tris = tiny.triangles.max(1) as f64;
        let verts = (u64::from(cx) + 1) * (u64::from(cy) + 1);
        let ns = tiny.times.raster * 1e6 / tris;
        setup = Some(serde_json::json!({
        "row": "set-up",
        "work": format!("{} triangles of about 2 pixels, {verts} vertices", tiny.triangles),
        "raster_ms": round3(tiny.times.raster),
        "ns_per_triangle": round3(ns),
        "model_ns": MODEL_SETUP_NS,
        "times_model": round3(ns / MODEL_SETUP_NS),
        "vertex_ns_per_vertex": round3(tiny.times.vertex * 1e6 / verts as f64),
        "fill_ns_per_triangle": round3(tiny.times.fill * 1e6 / tris),
        "pixels_shaded": tiny.pixels_shaded,
        }));
    }

    if args.json {
        for mut j in out.into_iter().chain(setup) {
            j["size"] = format!("{w}x{h}").into();
            j["threads"] = args.threads.into();
            j["kernel"] = kernel.name().into();
            say!("{j}");
        }
        return Ok(());
    }
    say!(
        "realist bench micro: {w}x{h}, {} thread{}, {} kernel, medians of the timed frames",
        args.threads,
        if args.threads == 1 { "" } else { "s" },
        kernel.name()
    );
    let num = |v: &serde_json::Value| v.as_f64().map_or("-".into(), |x| format!("{x:.2}"));
    if !out.is_empty() {
        say!(
            "{:<12} {:>9} {:>9} {:>9} {:>9} {:>8} {:>6}  work",
            "row",
            "fill ms",
            "frame ms",
            "ns/pixel",
            "model ns",
            "x model",
            "lanes"
        );
    }
    for j in &out {
        say!(
            "{:<12} {:>9} {:>9} {:>9} {:>9} {:>8} {:>6}  {}",
            j["row"].as_str().unwrap_or(""),
            num(&j["fill_ms"]),
            num(&j["frame_ms"]),
            num(&j["ns_per_pixel"]),
            num(&j["model_ns"]),
            num(&j["times_model"]),
            num(&j["lanes_in_use"]),
            j["work"].as_str().unwrap_or("")
        );
    }
    if let Some(s) = &setup {
        say!(
            "set-up: {} ns a triangle ({}x the model's {}; raster stage {} ms for {}), vertex \
             stage {} ns a vertex, fill {} ns a triangle",
            num(&s["ns_per_triangle"]),
            num(&s["times_model"]),
            num(&s["model_ns"]),
            num(&s["raster_ms"]),
            s["work"].as_str().unwrap_or(""),
            num(&s["vertex_ns_per_vertex"]),
            num(&s["fill_ns_per_triangle"])
        );
    }
    say!("The empty row's ns/pixel is its whole frame per pixel; the others are the fill's per shaded pixel.");
    Ok(())
}

/// The peer's lens at distance 2, looking down -Z at the origin.
fn camera() -> Camera {
    Camera {
        name: "micro".into(),
        eye: Vec3::new(0.0, 0.0, 2.0),
        target: Vec3::ZERO,
        // The peer's lens: vertical FOV 45 degrees, near 0.5, far 10, +Y up.
        ..peer_scene::camera()
    }
}

/// A plane at z = 0 of `nx` x `ny` quads (two triangles each) that fills the view of
/// [`camera`] at `aspect` with a 2% margin, wound to face +Z (the camera) or, if `away`, -Z.
fn grid(nx: u32, ny: u32, aspect: f32, away: bool, textured: bool) -> PeerMesh {
    let hh = 2.0 * libm::tanf((22.5f32).to_radians()) * 1.02;
    let hw = hh * aspect;
    let (sx, sy) = (nx as usize + 1, ny as usize + 1);
    let mut positions = Vec::with_capacity(sx * sy);
    let mut uvs = Vec::with_capacity(if textured { sx * sy } else { 0 });
    for j in 0..sy {
        for i in 0..sx {
            let (u, v) = (i as f32 / nx as f32, j as f32 / ny as f32);
            positions.push(Vec3::new((2.0 * u - 1.0) * hw, (2.0 * v - 1.0) * hh, 0.0));
            if textured {
                uvs.push(Vec2::new(u, v / aspect) * TEXTURE_REPEATS);
            }
        }
    }
    let mut triangles = Vec::with_capacity(2 * nx as usize * ny as usize);
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            let (b, c, d) = (a + 1, a + nx + 2, a + nx + 1);
            if away {
                triangles.push([a, c, b]);
                triangles.push([a, d, c]);
            } else {
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
    }
    PeerMesh {
        positions,
        uvs: textured.then_some(uvs),
        triangles,
    }
}

/// Medians of one row's timed frames.
struct Measured {
    times: StageTimes,
    pixels_shaded: u64,
    shader_calls: u64,
    triangles: u64,
}

fn measure(
    args: &MicroArgs,
    renderer: &mut Renderer,
    mesh: PeerMesh,
    shading: Shading,
    textured: bool,
    view: &View,
) -> Result<Measured> {
    let mut scene = peer_scene::scene("micro", mesh, textured)?;
    for m in &mut scene.materials {
        m.double_sided = false;
    }
    let prepared = PreparedScene::new(scene);
    let settings = Settings {
        shading: Some(shading),
        background: CLEAR,
        double_sided: false,
        vertex_lighting: VertexLighting::GL,
        ..Settings::default()
    };
    let mut last = f64::INFINITY;
    for _ in 0..2 {
        let t = Instant::now();
        renderer.render(&prepared, &settings, view);
        last = t.elapsed().as_secs_f64();
    }
    let n = match args.frames {
        0 => ((AUTO_SECONDS / last.max(1e-6)) as usize).clamp(AUTO_FRAMES.0, AUTO_FRAMES.1),
        n => n,
    };
    let mut stages: Vec<StageTimes> = Vec::with_capacity(n);
    for _ in 0..n {
        stages.push(renderer.render(&prepared, &settings, view).times);
    }
    let med = |f: fn(&StageTimes) -> f64| {
        let mut v: Vec<f64> = stages.iter().map(f).collect();
        median(&mut v)
    };
    let times = StageTimes {
        setup: med(|s| s.setup),
        vertex: med(|s| s.vertex),
        raster: med(|s| s.raster),
        fill: med(|s| s.fill),
        resolve: med(|s| s.resolve),
        total: med(|s| s.total),
    };
    let stats = &renderer.report().stats;
    Ok(Measured {
        times,
        pixels_shaded: stats.pixels_shaded,
        shader_calls: stats.shader_calls,
        triangles: stats.triangles_in,
    })
}

fn round3(x: f64) -> f64 {
    (x * 1e3).round() / 1e3
}
