//! `realist bench rays`: the ray queries of the traced modes (the textbook's §9.6) on the
//! peer's mesh standing on the ground plane: the time to build the mesh's hierarchy, then one
//! primary ray per pixel from the peer's camera (nearest hit) and one shadow ray per hit
//! towards the peer's directional light (any hit), as Mrays/s. One JSON line, beside the
//! figures measured for issue 38 on this machine class (bunny and ground, 1920x1080, one
//! primary and one shadow ray per pixel on one core: `obvhs`'s own traversal 361 ms,
//! Embree 4.4 254 ms, the `bvh` crate 1,193 ms).

use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

use realist::render::{Ground, PreparedScene, Settings, View};
use realist::trace::{Mesh, Ray, PACKET};

use super::{median, parse_size, peer_scene};

#[derive(Args)]
pub(crate) struct RaysArgs {
    /// An OBJ file (read as the peer harness reads it), or sphere:N.
    model: String,
    /// Image size WIDTHxHEIGHT: one primary ray per pixel.
    #[arg(long, default_value = "1920x1080", value_parser = parse_size)]
    size: (u32, u32),
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Timed rounds (the median is reported).
    #[arg(long, default_value_t = 7)]
    rounds: usize,
}

pub(crate) fn rays(args: &RaysArgs) -> Result<()> {
    let (name, mesh) = peer_scene::peer_mesh(&args.model)?;
    let scene = peer_scene::scene(&name, mesh, false)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("could not start worker threads")?;
    let threads = pool.current_num_threads();
    let (w, h) = args.size;
    let rounds = args.rounds.clamp(1, 100);
    let out = pool.install(|| {
        let prepared = PreparedScene::new(scene);
        let tri = &prepared.meshes()[0].tri;
        let (positions, triangles) = (tri.positions.clone(), tri.triangles.clone());
        let mut build: Vec<f64> = (0..rounds)
            .map(|_| {
                let t = Instant::now();
                let m = Mesh::new(&positions, &triangles);
                std::hint::black_box(&m);
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        let settings = Settings {
            ground: Some(Ground::default()),
            ..Settings::default()
        };
        let t = Instant::now();
        let rays = prepared.rays(&settings);
        let scene_ms = t.elapsed().as_secs_f64() * 1e3;
        let view = View {
            camera: peer_scene::camera(),
            width: w,
            height: h,
        };
        let cam = &view.camera;
        // The pinhole's rays: from the eye through the pixel centre, to the far plane.
        let (fwd, right) = (cam.forward(), cam.forward().cross(cam.up).normalize());
        let up = right.cross(fwd);
        let half_h = libm::tanf(cam.yfov * 0.5);
        let half_w = half_h * view.aspect();
        let ray_of = |x: u32, y: u32| {
            let s = Vec2::new(
                ((x as f32 + 0.5) / w as f32 * 2.0 - 1.0) * half_w,
                (1.0 - (y as f32 + 0.5) / h as f32 * 2.0) * half_h,
            );
            Ray::new(cam.eye, fwd + right * s.x + up * s.y, cam.near, cam.far)
        };
        let light = peer_scene::LIGHT.normalize();
        let mut primary = Vec::new();
        let mut shadow = Vec::new();
        let mut packets = Vec::new();
        let mut agree = true;
        let mut hits = 0;
        let mut shadowed = 0;
        let mut points: Vec<Option<Vec3>> = vec![None; w as usize * h as usize];
        for _ in 0..rounds {
            let t = Instant::now();
            points
                .par_chunks_mut(w as usize)
                .enumerate()
                .for_each(|(y, row)| {
                    for (x, p) in row.iter_mut().enumerate() {
                        let r = ray_of(x as u32, y as u32);
                        *p = rays.closest(&r).map(|hit| r.origin + r.dir * hit.t);
                    }
                });
            primary.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            let blocked = points
                .par_iter()
                .flatten()
                .filter(|&&p| {
                    // From just above the surface towards the light.
                    let from = p + (cam.eye - p) * 1e-4;
                    rays.occluded(&Ray::new(from, light, 0.0, f32::INFINITY))
                })
                .count();
            shadow.push(t.elapsed().as_secs_f64() * 1e3);
            // The same rays in packets of eight neighbours along a row, as `whitted`
            // traces its shadows; they must find the same shadowed count.
            let t = Instant::now();
            let blocked_packets: u32 = points
                .par_chunks(w as usize)
                .map(|row| {
                    let mut count = 0;
                    let mut batch = Vec::with_capacity(PACKET);
                    let mut hits = row.iter().flatten().peekable();
                    while hits.peek().is_some() {
                        batch.clear();
                        batch.extend(hits.by_ref().take(PACKET).map(|&p| {
                            let from = p + (cam.eye - p) * 1e-4;
                            Ray::new(from, light, 0.0, f32::INFINITY)
                        }));
                        count += rays.occluded_packet(&batch).count_ones();
                    }
                    count
                })
                .sum();
            packets.push(t.elapsed().as_secs_f64() * 1e3);
            hits = points.iter().flatten().count();
            shadowed = blocked;
            agree &= blocked_packets as usize == blocked;
        }
        let tris = rays.triangles();
        (
            median(&mut build),
            scene_ms,
            median(&mut primary),
            median(&mut shadow),
            median(&mut packets),
            agree,
            hits,
            shadowed,
            tris,
            triangles.len(),
        )
    });
    let (build, scene_ms, primary, shadow, packet, agree, hits, shadowed, tris, mesh_tris) = out;
    anyhow::ensure!(
        agree,
        "shadow rays in packets found a different number of shadowed points than one by one"
    );
    let round = |v: f64| (v * 100.0).round() / 100.0;
    let json = serde_json::json!({
        "model": name,
        "triangles": mesh_tris,
        "scene_triangles": tris,
        "threads": threads,
        "size": format!("{w}x{h}"),
        "build_ms": round(build),
        "scene_ms_first": round(scene_ms),
        "primary_rays": w as usize * h as usize,
        "primary_ms": round(primary),
        "primary_mrays_s": round((w * h) as f64 / primary / 1e3),
        "shadow_rays": hits,
        "shadowed": shadowed,
        "shadow_ms": round(shadow),
        "shadow_mrays_s": round(hits as f64 / shadow / 1e3),
        "shadow_packet_ms": round(packet),
        "shadow_packet_mrays_s": round(hits as f64 / packet / 1e3),
        "primary_plus_shadow_ms": round(primary + shadow),
        "issue_38_one_core_ms": {"obvhs": 361, "embree_4_4": 254, "bvh_crate": 1193},
    });
    say!("{json}");
    Ok(())
}
