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
use super::pipeline::{assemble, bin, flush, guard};
use super::setup::SetupTri;
use super::{Draw, FragmentShader, Stats, Target, Varying};

/// Triangles after setup, ready for binning (opaque).
pub struct SetupBatch<V> {
    tris: Vec<SetupTri<V>>,
    /// Counters of the clip / cull / setup stage.
    pub stats: Stats,
}

impl<V> SetupBatch<V> {
    /// Number of set-up triangles.
    #[must_use]
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }
}

/// Per-tile lists of triangle indices (opaque).
pub struct Binned(super::Bins);

impl Binned {
    /// Total entries over all tiles.
    #[must_use]
    pub fn entries(&self) -> usize {
        self.0.entries()
    }
}

/// Trivial frustum rejection and homogeneous clipping of every triangle of `d` for a
/// `width` x `height` target, without setup; returns the number of output polygons' fan
/// triangles.
#[must_use]
pub fn clip_cull<V: Varying>(d: &Draw<'_, V>, width: u32, height: u32) -> usize {
    let g = guard(width, height);
    let mut pieces = 0;
    for t in d.triangles {
        let fetch = |i: u32| -> Option<ClipVertex<V>> {
            let (p, v) = (d.clip.get(i as usize)?, d.varyings.get(i as usize)?);
            p.is_finite().then_some(ClipVertex { pos: *p, var: *v })
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
            pieces += clip_polygon(Poly::triangle([a, b, c]), need, g)
                .as_slice()
                .len()
                .saturating_sub(2);
        }
    }
    pieces
}

/// Clip / cull and fixed-point setup of every triangle of `d` (sequentially).
#[must_use]
pub fn setup_all<V: Varying>(d: &Draw<'_, V>, width: u32, height: u32) -> SetupBatch<V> {
    let g = guard(width, height);
    let mut tris = Vec::with_capacity(d.triangles.len());
    let mut stats = Stats::default();
    for t in d.triangles {
        assemble(d, t, g, width, height, &mut tris, &mut stats);
    }
    SetupBatch { tris, stats }
}

/// Bins every triangle of `batch` into `target`'s tiles.
#[must_use]
pub fn bin_all<V>(target: &Target, batch: &SetupBatch<V>) -> Binned {
    let mut bins = super::Bins::default();
    bins.fit(target.tiles.len());
    for (i, t) in batch.tris.iter().enumerate() {
        bin(target, t, i as u32, bins.lists());
    }
    Binned(bins)
}

/// Fills and shades every binned triangle (in parallel over tiles); consumes the bins.
pub fn fill_all<S: FragmentShader>(
    target: &mut Target,
    batch: &mut SetupBatch<S::Varying>,
    mut bins: Binned,
    shader: &S,
    stats: &mut Stats,
) {
    flush(target, &mut batch.tris, &mut bins.0, shader, stats, &|| {
        false
    });
}
