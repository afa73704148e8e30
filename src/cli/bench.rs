//! `realist bench`: warm frame times with the peer harness's camera and light, so realist and
//! Mesa llvmpipe (`../shared/peer`) can be compared as ratios measured in one run.
//!
//! `realist bench frame` (`frame.rs`) renders the peer's exact scene (`peer_scene.rs`: its
//! mesh reading, normals, texture, light and camera) and times single frames; `bench diff`
//! (`diff.rs`, hidden) compares its PNG with the peer's. `benches/peer.sh` runs both.
//! `bench micro` (`micro.rs`) prints the core's cost per shaded pixel in each mode and per
//! triangle of set-up, beside the README's machine model.

use std::time::Instant;

use anyhow::Result;
use glam::Vec3;

use realist::render::{PreparedScene, Renderer, Settings, Shot};
use realist::scene::{Camera, Scene};
use realist::shade::Shading;

use super::{load_model, parse_size, BenchArgs, NormalArgs};

mod diff;
mod frame;
mod micro;
mod peer_scene;
mod rays;
mod skin;

pub(crate) use diff::{diff, DiffArgs};
pub(crate) use frame::{frame, FrameArgs};
pub(crate) use micro::{micro, MicroArgs};
pub(crate) use rays::{rays, RaysArgs};
pub(crate) use skin::{skin, SkinArgs};

/// The peer harness's view: eye = normalize(1.6, 1.2, 2.0) * 2.8 for a mesh scaled so its
/// farthest vertex from the box centre is at distance 1; FOV 45 degrees, near 0.5, far 10.
fn peer_camera(scene: &Scene) -> Camera {
    let (lo, hi) = scene.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let center = (lo + hi) * 0.5;
    let mut r: f32 = 0.0;
    for inst in &scene.instances {
        if let Some(m) = scene.meshes.get(inst.mesh) {
            for world in inst.placements() {
                for p in &m.positions {
                    let d = world.transform_point3(*p).distance(center);
                    if d.is_finite() {
                        r = r.max(d);
                    }
                }
            }
        }
    }
    let r = if r > 0.0 { r } else { 1.0 };
    Camera {
        name: "peer".into(),
        eye: center + Vec3::new(1.6, 1.2, 2.0).normalize() * 2.8 * r,
        target: center,
        near: 0.5 * r,
        far: 10.0 * r,
        ..Camera::default()
    }
}

pub(super) fn bench(args: &BenchArgs) -> Result<()> {
    let Some(model) = &args.model else {
        anyhow::bail!("bench needs a MODEL (or the `accuracy` subcommand)");
    };
    let mut scene = load_model(
        model,
        &NormalArgs {
            crease: "off".into(),
            weighting: "area".into(),
        },
    )?;
    scene.lights = vec![
        realist::scene::Light::ambient(Vec3::splat(0.1)),
        realist::scene::Light::directional(-Vec3::new(0.5, 1.0, 0.8).normalize(), Vec3::splat(0.9)),
    ];
    let camera = peer_camera(&scene);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()?;
    let prepared = pool.install(|| PreparedScene::new(scene));
    let triangles = prepared.triangle_count();
    for res in args.res.split(',') {
        let (w, h) = parse_size(res).map_err(anyhow::Error::msg)?;
        for mode in args.shading.split(',') {
            let shading: Shading = mode.parse().map_err(anyhow::Error::msg)?;
            let opts = Shot {
                width: w,
                height: h,
                camera: Some(camera.clone()),
                settings: Settings {
                    shading: Some(shading),
                    double_sided: args.no_cull,
                    ..Settings::default()
                },
            };
            // A reused renderer, as in an interactive viewer; "read" adds the sRGB encode,
            // like the peer's read-back of the RGBA8 frame.
            let view = opts.view(prepared.scene());
            let settings = opts.settings;
            let mut renderer = Renderer::new();
            let mut pixels = vec![[0u8; 4]; (w * h) as usize];
            let (rounds, reads): (Vec<f64>, Vec<f64>) = pool.install(|| {
                renderer.render(&prepared, &settings, &view);
                (0..args.rounds.max(1))
                    .map(|_| {
                        let start = Instant::now();
                        let (mut times, mut read) = (Vec::new(), Vec::new());
                        while start.elapsed().as_secs_f64() < 0.5 || times.len() < 3 {
                            let t = Instant::now();
                            std::hint::black_box(renderer.render(&prepared, &settings, &view));
                            times.push(t.elapsed().as_secs_f64() * 1e3);
                            renderer.write_rgba8(&mut pixels);
                            std::hint::black_box(&pixels);
                            read.push(t.elapsed().as_secs_f64() * 1e3);
                        }
                        (median(&mut times), median(&mut read))
                    })
                    .unzip()
            });
            let mut r = rounds.clone();
            let json = serde_json::json!({
                "mesh": model.file_name().map(|f| f.to_string_lossy().into_owned()),
                "triangles": triangles,
                "res": format!("{w}x{h}"),
                "shading": shading.name(),
                "cull": !args.no_cull,
                "threads": pool.current_num_threads(),
                "ms_median": (median(&mut r) * 1e3).round() / 1e3,
                "ms_read_median": (median(&mut reads.clone()) * 1e3).round() / 1e3,
                "ms_rounds": rounds.iter().map(|x| (x * 1e3).round() / 1e3).collect::<Vec<_>>(),
            });
            say!("{json}");
        }
    }
    Ok(())
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}
