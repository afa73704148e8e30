//! One pass over a list of draws: every vertex projected once, the triangles set up and
//! binned chunk by chunk, and each batch of chunks flushed to the tiles' fill.

use std::time::Instant;

use rayon::prelude::*;

use super::{
    flush, guard, Bins, Chunk, Draw, DrawList, PreVert, ProjectJob, RasterScratch, SetupJob, Stats,
    BATCH, CHUNK, PROJECT_CHUNK,
};
use crate::framebuffer::Target;
use crate::setup::Viewport;
use crate::simd::kernel::{dispatch, KernelKind};
use crate::FragmentShader;

/// Rasterizes `draws` in order into `target` with `shader`. Runs on the current rayon pool;
/// the image does not depend on its thread count. Allocates its working memory; a caller
/// that draws every frame uses [`draw_list`] with memory it keeps.
pub fn draw<S: FragmentShader>(
    target: &mut Target,
    draws: &[Draw<'_>],
    shader: &S,
    stats: &mut Stats,
) {
    draw_with_kernel(target, draws, shader, stats, KernelKind::best());
}

/// [`draw`] with a given kernel (the portable one if the CPU lacks it).
pub fn draw_with_kernel<S: FragmentShader>(
    target: &mut Target,
    draws: &[Draw<'_>],
    shader: &S,
    stats: &mut Stats,
    kernel: KernelKind,
) {
    let mut bins = Bins::with_kernel(kernel);
    let mut scratch = RasterScratch::default();
    draw_list(
        target,
        draws,
        shader,
        stats,
        &mut bins,
        &mut scratch,
        &|| false,
    );
}

/// [`draw`] with kept memory and a stop signal: `stop` is asked before each tile is filled,
/// and once it answers true the remaining tiles of the pass are skipped and `false` is
/// returned (the target then holds a partial image). Returns `true` if the pass completed.
/// Allocates nothing once `bins` and `scratch` have served a pass of this size.
pub fn draw_list<S: FragmentShader, L: DrawList + ?Sized>(
    target: &mut Target,
    draws: &L,
    shader: &S,
    stats: &mut Stats,
    bins: &mut Bins,
    scratch: &mut RasterScratch,
    stop: &(dyn Fn() -> bool + Sync),
) -> bool {
    let g = guard(target.width, target.height);
    let (w, h, tiles_x) = (target.width, target.height, target.tiles_x);
    let vp = Viewport {
        width: w,
        height: h,
        reach: target.reach(),
    };
    let tiles = target.tiles.len();
    bins.fit(tiles);
    let RasterScratch {
        chunks,
        starts,
        pre,
        pre_starts,
    } = scratch;
    let kernel = bins.kernel;
    starts.clear();
    pre.clear();
    pre_starts.clear();
    let mut total = 0;
    let half = (w as f32 * 0.5, h as f32 * 0.5);
    for i in 0..draws.count() {
        let d = draws.draw(i);
        starts.push(total);
        total += d.triangles.len();
        let first = pre.len();
        pre_starts.push(first);
        pre.resize(first + d.clip.len(), PreVert::default());
        pre[first..]
            .par_chunks_mut(PROJECT_CHUNK)
            .zip(d.clip.par_chunks(PROJECT_CHUNK))
            .for_each(|(out, clip)| {
                let job = ProjectJob {
                    clip,
                    out,
                    g,
                    half,
                    bits: d.state.subpixel_bits,
                };
                dispatch(kernel, job);
            });
    }
    stats.triangles_in += total as u64;
    let (starts, pre, pre_starts) = (&*starts, &*pre, &*pre_starts);
    let mut complete = true;
    let mut batch = 0;
    while batch < total && complete {
        let start = Instant::now();
        let end = (batch + BATCH).min(total);
        let n = (end - batch).div_ceil(CHUNK);
        if chunks.len() < n {
            chunks.resize_with(n, Chunk::default);
        }
        chunks[..n]
            .par_iter_mut()
            .enumerate()
            .for_each(|(c, chunk)| {
                chunk.reset(tiles);
                let lo = batch + c * CHUNK;
                let hi = (lo + CHUNK).min(end);
                let job = SetupJob {
                    draws,
                    starts,
                    pre,
                    pre_starts,
                    lo,
                    hi,
                    g,
                    vp,
                    tiles_x,
                    chunk,
                };
                dispatch(kernel, job);
            });
        for c in &chunks[..n] {
            stats.add(&c.stats);
        }
        bins.setup_nanos += start.elapsed().as_nanos() as u64;
        complete = flush(target, &chunks[..n], bins, shader, stats, stop);
        batch = end;
    }
    complete
}
