//! The pipeline's stages one at a time, for benchmarks (`benches/stages.rs`) and
//! diagnostics. [`draw`](super::draw) runs the same code fused and batched; nothing here is
//! needed to render.
//!
//! | stage | function |
//! |---|---|
//! | transform | [`transform_positions`](super::transform_positions) |
//! | clip / cull | [`clip_cull`] |
//! | setup (with clip / cull) | [`setup_all`] |
//! | bin | [`bin_all`] |
//! | fill + shade | [`fill_all`] |
//! | encode | [`Target::to_srgb8`](super::Target) |

use glam::Vec2;

use super::clip::{clip_polygon, outcode, ClipVertex, Poly};
use super::pipeline::{assemble, bin, flush, guard, Chunk, CHUNK};
use super::setup::Viewport;
use super::{Bins, Draw, FragmentShader, Stats, Target};
use crate::simd::KernelKind;

/// Triangles after setup, in chunks as the pipeline makes them (opaque).
pub struct SetupBatch {
    chunks: Vec<Chunk>,
    /// Counters of the clip / cull / setup stage.
    pub stats: Stats,
}

impl SetupBatch {
    /// Number of set-up triangles.
    #[must_use]
    pub fn len(&self) -> usize {
        self.chunks.iter().map(|c| c.tris.len()).sum()
    }

    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Total tile-list entries after [`bin_all`].
    #[must_use]
    pub fn entries(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| c.bins.iter().map(Vec::len).sum::<usize>())
            .sum()
    }
}

/// Trivial frustum rejection and homogeneous clipping of every triangle of `d` for a
/// `width` x `height` target, without setup; returns the number of output polygons' fan
/// triangles.
#[must_use]
pub fn clip_cull(d: &Draw<'_>, width: u32, height: u32) -> usize {
    let g = guard(width, height);
    let s = d.stride;
    let mut pieces = 0;
    for t in d.triangles {
        let fetch = |i: u32| -> Option<ClipVertex> {
            let p = d.clip.get(i as usize)?;
            let v = d.varyings.get(i as usize * s..(i as usize + 1) * s)?;
            p.is_finite().then(|| ClipVertex::new(*p, v))
        };
        let (Some(a), Some(b), Some(c)) = (fetch(t[0]), fetch(t[1]), fetch(t[2])) else {
            continue;
        };
        let f = [a.pos, b.pos, c.pos].map(|p| outcode(p, Vec2::ONE));
        if f[0] & f[1] & f[2] != 0 {
            continue;
        }
        let need = [a.pos, b.pos, c.pos]
            .iter()
            .fold(0, |acc, &p| acc | outcode(p, g));
        if need == 0 {
            pieces += 1;
        } else {
            pieces += clip_polygon(Poly::triangle([a, b, c], s), need, g)
                .as_slice()
                .len()
                .saturating_sub(2);
        }
    }
    pieces
}

/// Clip / cull and fixed-point setup of every triangle of `d` (sequentially, in the
/// pipeline's chunks), without binning.
#[must_use]
pub fn setup_all(d: &Draw<'_>, width: u32, height: u32) -> SetupBatch {
    let g = guard(width, height);
    let mut stats = Stats::default();
    let chunks = d
        .triangles
        .chunks(CHUNK)
        .map(|tris| {
            let mut c = Chunk::default();
            for t in tris {
                let vp = Viewport {
                    width,
                    height,
                    reach: 0,
                };
                assemble(d, None, t, g, vp, None, &mut c);
            }
            stats.add(&c.stats);
            c
        })
        .collect();
    SetupBatch { chunks, stats }
}

/// Bins every triangle of `batch` into `target`'s tiles (replacing earlier lists).
pub fn bin_all(target: &Target, batch: &mut SetupBatch) {
    let tiles = target.tiles.len();
    for c in &mut batch.chunks {
        c.bins.resize_with(tiles, Vec::new);
        c.bins.iter_mut().for_each(Vec::clear);
        for (i, t) in c.tris.iter().enumerate() {
            bin(target.tiles_x, target.reach(), t, i as u16, &mut c.bins);
        }
    }
}

/// Fills and shades every binned triangle (in parallel over tiles) with `kernel`.
pub fn fill_all<S: FragmentShader>(
    target: &mut Target,
    batch: &SetupBatch,
    shader: &S,
    stats: &mut Stats,
    kernel: KernelKind,
) {
    let mut bins = Bins::with_kernel(kernel);
    bins.fit(target.tiles.len());
    flush(target, &batch.chunks, &mut bins, shader, stats, &|| false);
}
