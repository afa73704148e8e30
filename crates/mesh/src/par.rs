//! Helpers for building a mesh in parallel on the current rayon pool, deterministically:
//! the work is cut into contiguous ranges (of vertices or facets) whose outputs are disjoint
//! slices of the result, so every value is computed exactly as the serial loop did and no
//! result depends on the number of threads.

use std::ops::Range;

use super::Facet;

/// Below this many corners a mesh is built on one thread (splitting costs more).
pub(super) const MIN_CORNERS: usize = 16 * 1024;

/// Tests set this to cut even tiny meshes into several ranges (results do not depend on
/// the cut, so other tests running meanwhile are not affected).
#[cfg(test)]
pub(super) static FORCE_SPLIT: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Items per parallel task for per-vertex, per-corner or per-facet maps.
pub(super) const MIN_ITEMS: usize = 4096;

/// How many ranges to cut work of `corner_count` corners into: `per_thread` per pool
/// thread, or 1 for a small mesh.
pub(super) fn parts(corner_count: usize, per_thread: usize) -> usize {
    #[cfg(test)]
    if FORCE_SPLIT.load(std::sync::atomic::Ordering::Relaxed) {
        return 3 * per_thread;
    }
    if corner_count < MIN_CORNERS {
        1
    } else {
        rayon::current_num_threads().max(1) * per_thread
    }
}

/// Cuts `0..start.len() - 1` into at most `parts` non-empty ranges of about equal weight,
/// where `start` is a prefix sum (item `i` weighs `start[i + 1] - start[i]`).
pub(super) fn balanced(start: &[u32], parts: usize) -> Vec<Range<usize>> {
    let count = start.len().saturating_sub(1);
    let total = u64::from(start.last().copied().unwrap_or(0));
    let parts = parts.max(1) as u64;
    let mut out = Vec::with_capacity(parts as usize);
    let mut lo = 0usize;
    for k in 1..=parts {
        let hi = if k == parts {
            count
        } else {
            let target = total * k / parts;
            start[..=count]
                .partition_point(|&s| u64::from(s) < target)
                .min(count)
        };
        if hi > lo {
            out.push(lo..hi);
            lo = hi;
        }
    }
    out
}

/// Cuts the facets into at most `parts` ranges of about equal corner counts (facets cover
/// the corners contiguously, in order).
pub(super) fn facet_ranges(facets: &[Facet], parts: usize) -> Vec<Range<usize>> {
    let parts = parts.clamp(1, facets.len().max(1));
    let corners = facets.last().map_or(0, |f| (f.first + f.len) as usize);
    let mut out = Vec::with_capacity(parts);
    let mut lo = 0usize;
    for k in 1..=parts {
        let hi = if k == parts {
            facets.len()
        } else {
            let target = corners * k / parts;
            facets.partition_point(|f| (f.first as usize) < target)
        };
        if hi > lo {
            out.push(lo..hi);
            lo = hi;
        }
    }
    out
}

/// `slice` cut into consecutive pieces of the given lengths (which must add up to at most
/// its length).
pub(super) fn split_lengths<T>(
    mut slice: &mut [T],
    lengths: impl IntoIterator<Item = usize>,
) -> Vec<&mut [T]> {
    let mut out = Vec::new();
    for len in lengths {
        let (head, tail) = std::mem::take(&mut slice).split_at_mut(len);
        out.push(head);
        slice = tail;
    }
    out
}
