//! `realist bench skin`: the time to pose a skinned mesh (the built-in tube of
//! [`realist::scene::skinned_tube`]): the animation sampled, world and joint matrices, every
//! vertex's position, normal (and tangent) skinned into the reused buffers in parallel,
//! facet normals and bounds. One JSON line with the median and quartiles over the frames.

use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;

use realist::render::PreparedScene;
use realist::scene::{skinned_tube, Play};

use super::median;

#[derive(Args)]
pub(crate) struct SkinArgs {
    /// Vertices of the tube (rounded to whole rings of 250).
    #[arg(long, default_value_t = 100_000)]
    vertices: u32,
    /// Joints per vertex: 4 or 8.
    #[arg(long, default_value_t = 4)]
    influences: usize,
    /// Joints in the chain.
    #[arg(long, default_value_t = 24)]
    joints: usize,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Timed poses.
    #[arg(long, default_value_t = 200)]
    frames: usize,
}

pub(crate) fn skin(args: &SkinArgs) -> Result<()> {
    let sides = 250;
    let rings = args.vertices.div_ceil(sides).max(2);
    let scene = skinned_tube(rings, sides, args.joints, args.influences)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("could not start worker threads")?;
    let threads = pool.current_num_threads();
    let (times, vertices, triangles) = pool.install(|| {
        let mut p = PreparedScene::new(scene);
        let triangles = p.triangle_count();
        let vertices = u64::from(rings) * u64::from(sides);
        for k in 0..5 {
            p.pose_at(Play::All, k as f32 * 0.1, true);
        }
        let times: Vec<f64> = (0..args.frames.max(1))
            .map(|k| {
                let t = Instant::now();
                p.pose_at(Play::All, 0.37 * k as f32, true);
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        (times, vertices, triangles)
    });
    let mut sorted = times.clone();
    let med = median(&mut sorted);
    sorted.sort_by(f64::total_cmp);
    let q = |f: f64| sorted[((sorted.len() - 1) as f64 * f).round() as usize];
    let json = serde_json::json!({
        "vertices": vertices,
        "triangles": triangles,
        "influences": args.influences,
        "joints": args.joints,
        "threads": threads,
        "frames": times.len(),
        "ms_median": (med * 1e3).round() / 1e3,
        "ms_q1": (q(0.25) * 1e3).round() / 1e3,
        "ms_q3": (q(0.75) * 1e3).round() / 1e3,
        "ns_per_vertex": (med * 1e6 / vertices as f64 * 100.0).round() / 100.0,
    });
    say!("{json}");
    Ok(())
}
