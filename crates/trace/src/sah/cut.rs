//! How a range of primitives is cut in two: the SAH cost of the candidate cuts (planes
//! between bins of the centres, or every subset of a small range), the leaf-or-cut
//! decision, the fallbacks, and the partition of the records.
//!
//! The bins are counted in SIMD lanes: a centre's bin on each axis comes from one
//! subtract, one multiply and one add (see [`ROUND`]), and the partition tests the same
//! lane, so both agree on every centre bit for bit.

use glam::{BVec3A, Vec3A};

use super::{Prim, Range, MAX_LEAF, MEDIAN_DEPTH};
use crate::bvh::{widen, Node};

/// Bins per axis for ranges of more than 32 primitives. Measured on the bunny and the
/// ground (`realist bench rays`, 2 threads, medians of 9 interleaved runs), 16 against 32:
/// the build 10.5 ms against 10.9 (14.6 against 15.7 on one thread, warm), the tree's SAH
/// cost 0.4% higher, its rays as fast (153.1 ms primary and 57.2 shadow against 154.5 and
/// 56.2). Smaller ranges take 8 bins up to 32 primitives and 4 up to 12: sweeping mostly
/// empty bins cost them more than binning; against 16 bins down to 9 primitives the build
/// was 1.7 ms faster on one thread and the tree's cost 0.1% higher.
pub const BINS: usize = 16;

/// The cost of visiting a node, in units of testing one primitive. Measured while tuning
/// (bunny and ground, 2 threads, medians of 7 interleaved runs): 0.5 traced 149.0 ms
/// primary and 54.1 shadow, 1 traced 144.2 and 53.1, 2 traced 155.6 and 65.8 (its leaves
/// of 2.8 triangles against 1.85 built 1.2 ms faster on one thread), 3 with leaves of up
/// to 8 traced 154.6 and 66.3.
pub const NODE_COST: f32 = 1.0;

/// Ranges of up to this many primitives try each way to cut them in two (7 ways for 4),
/// not only planes: better trees, and cheaper than binning them.
const EXHAUSTIVE: usize = 4;

/// A box being grown; empty is `(+inf, -inf)`.
#[derive(Clone, Copy, Debug)]
pub struct Bounds {
    lo: Vec3A,
    hi: Vec3A,
}

impl Bounds {
    pub const EMPTY: Self = Self {
        lo: Vec3A::INFINITY,
        hi: Vec3A::NEG_INFINITY,
    };

    #[inline(always)]
    fn point(&mut self, p: Vec3A) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }

    #[inline(always)]
    fn prim(&mut self, p: &Prim) {
        self.lo = self.lo.min(p.min());
        self.hi = self.hi.max(p.max());
    }

    #[inline(always)]
    pub fn union(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// Half the surface (the SAH's weight; only ratios matter).
    #[inline(always)]
    fn half_area(&self) -> f32 {
        let e = self.hi - self.lo;
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// The node of this box, widened (Ize 2013).
    pub fn node(&self, count: u32, index: u32) -> Node {
        let (min, max) = widen(self.lo.into(), self.hi.into());
        Node::new(min, max, count, index)
    }
}

/// The box of some primitives and the box of their centres (doubled).
pub fn bounds_of(prims: &[Prim]) -> (Bounds, Bounds) {
    let (mut b, mut c) = (Bounds::EMPTY, Bounds::EMPTY);
    for p in prims {
        b.prim(p);
        c.point(p.centre2());
    }
    (b, c)
}

/// How a range is built.
enum Plan {
    Leaf,
    /// Primitives whose centre falls in a bin below `bin` on `axis` go left.
    Binned {
        binning: Binning,
        axis: usize,
        bin: usize,
        left: Bounds,
        right: Bounds,
    },
    /// The primitives whose bits are set in `mask` go left (a range of at most
    /// [`EXHAUSTIVE`]).
    Subset {
        mask: usize,
        left: Bounds,
        right: Bounds,
    },
    /// In the middle of the range: at the median centre of the widest axis, or as the
    /// records lie when every centre is the same.
    Middle,
}

/// 2^23: a number from 0 to 2^22 plus this is rounded to a whole number, which is then the
/// float's low mantissa bits. Rounding by this addition rather than converting to an
/// integer keeps the binning and the partition in SIMD lanes (the conversions were a
/// quarter of the binning's time).
const ROUND: f32 = 8_388_608.0;

/// How centres map to bins: on each axis the offset from `lo` times `scale`, rounded to a
/// whole number, is the bin (`scale` takes the centres to `0..=count - 1`, so the planes
/// between bins, at the halves, split the centres' extent evenly, and the end bins are half
/// bins). An axis along which the centres do not spread (or barely: a scale that is not
/// finite) has scale 0, all in bin 0.
#[derive(Clone, Copy, Debug)]
struct Binning {
    lo: Vec3A,
    scale: Vec3A,
    count: usize,
}

impl Binning {
    /// `count` bins over the centres' box `c`.
    fn new(c: &Bounds, count: usize) -> Self {
        let extent = c.hi - c.lo;
        let s = Vec3A::splat((count - 1) as f32 * (1.0 - 1e-5)) / extent;
        Self {
            lo: c.lo,
            scale: Vec3A::select(
                extent.cmpgt(Vec3A::ZERO) & s.is_finite_mask(),
                s,
                Vec3A::ZERO,
            ),
            count,
        }
    }

    /// The bin of centre `c` on each axis.
    #[inline(always)]
    fn of(&self, c: Vec3A) -> [usize; 3] {
        let k = ((c - self.lo) * self.scale + Vec3A::splat(ROUND)).to_array();
        let bin = |k: f32| ((k.to_bits() - ROUND.to_bits()) as usize).min(self.count - 1);
        [bin(k[0]), bin(k[1]), bin(k[2])]
    }
}

/// The cheapest way to build a range (of at least 2 primitives): every cut of a small
/// range, else the planes between bins on all three axes.
fn plan(r: &Range) -> Plan {
    let n = r.prims.len();
    if n <= EXHAUSTIVE {
        exhaustive(r)
    } else if n <= 12 {
        binned::<4>(r)
    } else if n <= 32 {
        binned::<8>(r)
    } else {
        binned::<BINS>(r)
    }
}

/// A leaf when the range may be one and that costs no more than `cut`, the SAH cost of
/// its best cut times its area.
fn leaf(r: &Range, cut: f32) -> bool {
    let (n, area) = (r.prims.len(), r.bounds.half_area());
    n <= MAX_LEAF && n as f32 * area <= NODE_COST * area + cut
}

/// [`plan`] over every cut of a range of 2 to [`EXHAUSTIVE`] primitives.
fn exhaustive(r: &Range) -> Plan {
    let all = (1 << r.prims.len()) - 1;
    // The box of each subset (bit `i`: primitive `i`), each from one with a bit fewer.
    let mut boxes = [Bounds::EMPTY; 1 << EXHAUSTIVE];
    for m in 1..=all {
        boxes[m] = boxes[m & (m - 1)];
        boxes[m].prim(&r.prims[m.trailing_zeros() as usize]);
    }
    let cost = |m: usize| boxes[m].half_area() * m.count_ones() as f32;
    // The left sides: the subsets with the first primitive (their complements are the
    // same cuts), but not all of them.
    let (best, mask) = (1..all)
        .step_by(2)
        .map(|m| (cost(m) + cost(all ^ m), m))
        .fold((f32::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
    if leaf(r, best) {
        Plan::Leaf
    } else if !best.is_finite() {
        Plan::Middle
    } else {
        Plan::Subset {
            mask,
            left: boxes[mask],
            right: boxes[all ^ mask],
        }
    }
}

/// [`plan`] with `N` bins per axis. Kept out of line so its bins (up to 2 KB) are not on
/// the stack of the recursion.
#[inline(never)]
fn binned<const N: usize>(r: &Range) -> Plan {
    let binning = Binning::new(&r.centres, N);
    if binning.scale == Vec3A::ZERO {
        // Every centre the same: no plane separates them.
        return if r.prims.len() <= MAX_LEAF {
            Plan::Leaf
        } else {
            Plan::Middle
        };
    }
    let mut boxes = [[Bounds::EMPTY; N]; 3];
    let mut counts = [[0u32; N]; 3];
    for p in r.prims.iter() {
        let k = binning.of(p.centre2());
        for axis in 0..3 {
            boxes[axis][k[axis]].prim(p);
            counts[axis][k[axis]] += 1;
        }
    }
    // (cost, axis, first bin on the right); the cost is the SAH's times the range's area.
    let mut best = (f32::INFINITY, 0, 0);
    for axis in 0..3 {
        let (boxes, counts) = (&boxes[axis], &counts[axis]);
        // Area and count of bins `i..` (the right side of a plane before bin `i`).
        let mut right_area = [0.0f32; N];
        let mut right_count = [0u32; N];
        let (mut acc, mut m) = (Bounds::EMPTY, 0);
        for i in (1..N).rev() {
            acc = acc.union(boxes[i]);
            m += counts[i];
            right_area[i] = acc.half_area();
            right_count[i] = m;
        }
        let (mut acc, mut m) = (Bounds::EMPTY, 0);
        for i in 1..N {
            acc = acc.union(boxes[i - 1]);
            m += counts[i - 1];
            if m == 0 || right_count[i] == 0 {
                continue;
            }
            let cost = acc.half_area() * m as f32 + right_area[i] * right_count[i] as f32;
            if cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    let (cost, axis, bin) = best;
    if leaf(r, cost) {
        return Plan::Leaf;
    }
    if !cost.is_finite() {
        // No plane found, or areas beyond f32: cut at the median.
        return Plan::Middle;
    }
    let union = |bins: &[Bounds]| bins.iter().fold(Bounds::EMPTY, |a, &b| a.union(b));
    Plan::Binned {
        binning,
        axis,
        bin,
        left: union(&boxes[axis][..bin]),
        right: union(&boxes[axis][bin..]),
    }
}

/// Splits `r` into its two halves (reordering its primitives), or `None` for a leaf.
pub fn split(r: Range) -> Option<(Range, Range)> {
    let n = r.prims.len();
    let plan = if n <= 1 || (r.depth >= MEDIAN_DEPTH && n <= MAX_LEAF) {
        Plan::Leaf
    } else if r.depth >= MEDIAN_DEPTH {
        Plan::Middle
    } else {
        plan(&r)
    };
    let Range {
        prims,
        first,
        centres,
        depth,
        ..
    } = r;
    let (mid, left, right, lc, rc) = match plan {
        Plan::Leaf => return None,
        Plan::Binned {
            binning,
            axis,
            bin,
            left,
            right,
        } => {
            let (mid, lc, rc) = partition(prims, &binning, axis, bin);
            (mid, left, right, lc, rc)
        }
        Plan::Subset { mask, left, right } => {
            let mut was = [prims[0]; EXHAUSTIVE];
            was[..n].copy_from_slice(prims);
            let sides =
                [true, false].map(|side| (0..n).filter(move |&i| ((mask >> i) & 1 == 1) == side));
            for (slot, i) in sides.into_iter().flatten().enumerate() {
                prims[slot] = was[i];
            }
            let mid = mask.count_ones() as usize;
            let (lc, rc) = (bounds_of(&prims[..mid]).1, bounds_of(&prims[mid..]).1);
            (mid, left, right, lc, rc)
        }
        Plan::Middle => {
            let e = centres.hi - centres.lo;
            if e.max_element() > 0.0 {
                let axis = if e.x >= e.y && e.x >= e.z {
                    0
                } else if e.y >= e.z {
                    1
                } else {
                    2
                };
                prims.select_nth_unstable_by(n / 2, |a, b| {
                    a.centre2()[axis].total_cmp(&b.centre2()[axis])
                });
            }
            let (l, r) = prims.split_at(n / 2);
            let ((lb, lc), (rb, rc)) = (bounds_of(l), bounds_of(r));
            (n / 2, lb, rb, lc, rc)
        }
    };
    let (l, r) = prims.split_at_mut(mid);
    let half = |prims, first, bounds, centres| Range {
        prims,
        first,
        bounds,
        centres,
        depth: depth + 1,
    };
    Some((
        half(l, first, left, lc),
        half(r, first + mid as u32, right, rc),
    ))
}

/// Moves the primitives whose centre's bin on `axis` is below `bin` to the front; returns
/// how many there are and the boxes of the two sides' centres.
fn partition(
    prims: &mut [Prim],
    binning: &Binning,
    axis: usize,
    bin: usize,
) -> (usize, Bounds, Bounds) {
    // The lane of [`Binning::of`]'s sum on `axis`, compared as a float: below `ROUND + bin`
    // exactly when the bin is below `bin` (both are whole numbers).
    let splat = |v: Vec3A| Vec3A::splat(v[axis]);
    let (lo, scale) = (splat(binning.lo), splat(binning.scale));
    let (round, edge) = (Vec3A::splat(ROUND), Vec3A::splat(ROUND + bin as f32));
    match axis {
        0 => sides(prims, |c| {
            ((Vec3A::splat(c.x) - lo) * scale + round).cmplt(edge)
        }),
        1 => sides(prims, |c| {
            ((Vec3A::splat(c.y) - lo) * scale + round).cmplt(edge)
        }),
        _ => sides(prims, |c| {
            ((Vec3A::splat(c.z) - lo) * scale + round).cmplt(edge)
        }),
    }
}

/// [`partition`] by `left(centre)` (all lanes set or none). Without branches (which side a
/// primitive goes is as good as random to the predictor): every record is swapped, with
/// itself or with the first of the right side.
#[inline(always)]
fn sides(prims: &mut [Prim], left: impl Fn(Vec3A) -> BVec3A) -> (usize, Bounds, Bounds) {
    let (mut lc, mut rc) = (Bounds::EMPTY, Bounds::EMPTY);
    let mut j = 0;
    for i in 0..prims.len() {
        let p = prims[i];
        let c = p.centre2();
        let m = left(c);
        lc.lo = Vec3A::select(m, lc.lo.min(c), lc.lo);
        lc.hi = Vec3A::select(m, lc.hi.max(c), lc.hi);
        rc.lo = Vec3A::select(m, rc.lo, rc.lo.min(c));
        rc.hi = Vec3A::select(m, rc.hi, rc.hi.max(c));
        prims[i] = prims[j];
        prims[j] = p;
        j += (m.bitmask() & 1) as usize;
    }
    (j, lc, rc)
}
