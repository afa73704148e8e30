//! The target's colours after a pass: a path sum's mean, exposure and tone mapping, and
//! the passes of a supersampled frame summed and averaged.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::raster::{Target, TILE};

/// Sets every pixel of `target` to `sum / paths` (`sum` row-major, the target's size),
/// alpha 1.
pub(super) fn write_mean(target: &mut Target, sum: &[Vec3], paths: u32) {
    let (w, n) = (target.width as usize, paths.max(1) as f32);
    target.tiles.par_iter_mut().for_each(|tile| {
        tile.materialize();
        for y in 0..tile.h {
            let row = (tile.y0 + y) as usize * w + tile.x0 as usize;
            for x in 0..tile.w {
                let o = (y * TILE + x) as usize;
                tile.set_color(o, (sum[row + x as usize] / n).extend(1.0));
            }
        }
    });
}

/// Exposes and tone maps every colour of `target` but the background colour `bg`, which
/// is shown as it is.
pub(super) fn map_tone(target: &mut Target, tone: crate::ToneMap, scale: f32, bg: Vec4) {
    target.map_colors(|c| {
        if c == bg {
            c
        } else {
            tone.apply((c.truncate() * scale).extend(c.w))
        }
    });
}

/// Adds the target's colour to `accum` (tile layout); with `scale`, replaces the target's
/// colour by `accum * scale` (the average, after the last pass).
pub(super) fn accumulate(target: &mut Target, accum: &mut [Vec4], scale: Option<f32>) {
    let n = (TILE * TILE) as usize;
    target
        .tiles
        .par_iter_mut()
        .zip(accum.par_chunks_mut(n))
        .for_each(|(tile, acc)| {
            for (o, a) in acc.iter_mut().enumerate() {
                *a += tile.color_at(o);
            }
            if let Some(s) = scale {
                tile.materialize();
                for (o, a) in acc.iter().enumerate() {
                    tile.set_color(o, *a * s);
                }
            }
        });
}
