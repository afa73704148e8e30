//! Vertex normals: read from a file, flat, or averaged from facet normals (the textbook's §9.2.2:
//! N_a = (N_1 + ... + N_k) / k), with area and angle weighting and crease-angle splitting.
//!
//! Owns the guarantee that every normal a [`Mesh`](super::Mesh) carries is a finite unit
//! vector: degenerate facets (zero normal) take no part in averaging, and a vertex with no
//! usable facet gets the normal of any adjacent facet, else [`FALLBACK_NORMAL`].
//!
//! Crease splitting follows the pairwise rule: at a vertex, the corner of facet `f` averages
//! exactly the facets around the vertex whose normal is within the crease angle of `f`'s
//! normal. The quadratic pairwise test is skipped when every facet normal at the vertex lies
//! within half the crease angle of the plain vertex normal (then, by the triangle inequality
//! on the sphere, all pairs are within the angle and the vertex keeps one normal): one pass
//! over the corners finds the few vertices on a crease, and only they pay for the pairwise
//! test. A vertex with more than [`MAX_CREASE_VALENCE`] corners is never split. A channel
//! split this way stays compact: value `v` is vertex `v`'s (first) normal, and only the
//! distinct extra normals of split vertices are appended.
//!
//! Corner angles use a polynomial `atan2` (see [`atan2`]) evaluated in `f64`.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::adjacency::{Ring, VertexCorners};
use super::{par, Channel, Facet, NormalPolicy, NormalSource};

/// How adjacent facet normals are weighted when averaged at a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize)]
pub enum Weighting {
    /// The textbook's plain average.
    Uniform,
    /// Weighted by facet area.
    Area,
    /// Weighted by the facet's corner angle at the vertex (Thürmer & Wüthrich); independent of
    /// how a surface is tessellated.
    #[default]
    Angle,
}

/// Options for averaged normals.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct NormalOptions {
    pub weighting: Weighting,
    /// Facets whose normals differ by more than this many degrees do not share a vertex
    /// normal (the vertex is split); `None` = always average (the textbook's behaviour).
    /// Values of 180 or more, and non-finite values, never split; negative values act as 0.
    pub crease_degrees: Option<f32>,
}

impl Default for NormalOptions {
    fn default() -> Self {
        Self {
            weighting: Weighting::Angle,
            crease_degrees: Some(60.0),
        }
    }
}

/// The normal of a vertex or corner that has no non-degenerate facet to take one from.
pub const FALLBACK_NORMAL: Vec3 = Vec3::Z;

/// Vertices with more corners than this are not crease-split (the pairwise test is quadratic
/// in the number of corners); they keep one averaged normal.
pub const MAX_CREASE_VALENCE: usize = 1024;

/// `atan2(y, x)` in `[-pi, pi]` from a polynomial (least-squares fit of `atan` on Chebyshev
/// nodes, max error 6.5e-8 rad): 5 to 10 times faster than libm's, and the same on every
/// platform. 0 for `(0, 0)`; NaN if either input is NaN.
#[must_use]
pub(super) fn atan2(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI};
    const C: [f64; 8] = [
        0.999_999_436_843_148_4,
        -0.333_301_066_776_889_4,
        0.199_485_089_857_651_9,
        -0.139_158_022_606_835_55,
        0.096_562_564_704_273_99,
        -0.056_063_176_728_591_98,
        0.021_946_611_032_241_853,
        -0.004_073_309_464_366_758,
    ];
    if x.is_nan() || y.is_nan() {
        return f64::NAN;
    }
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    if hi == 0.0 {
        return 0.0;
    }
    let t = lo / hi;
    let t2 = t * t;
    let t4 = t2 * t2;
    // Estrin's scheme: shorter dependency chains than Horner's.
    let p01 = C[0] + C[1] * t2;
    let p23 = C[2] + C[3] * t2;
    let p45 = C[4] + C[5] * t2;
    let p67 = C[6] + C[7] * t2;
    let mut a = t * ((p01 + p23 * t4) + (p45 + p67 * t4) * (t4 * t4));
    if ay > ax {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 {
        -a
    } else {
        a
    }
}

/// `v / |v|`, or `None` for a zero or non-finite `v`. Scales first, so vectors with huge or
/// tiny components still normalise.
#[must_use]
pub(super) fn unit(v: Vec3) -> Option<Vec3> {
    // `max_element` skips NaN: test finiteness of the vector itself.
    let m = v.abs().max_element();
    if !(v.is_finite() && m > 0.0) {
        return None;
    }
    let w = v / m;
    Some(w / w.length())
}

/// Normals read from a file: renormalised; corners whose value is zero or non-finite get
/// their facet's normal instead. A per-vertex channel stays per vertex when every corner of
/// each bad vertex gets the same normal (a vertex of one facet, or of degenerate facets
/// only: a sphere's pole); otherwise it becomes per corner.
///
/// `facet_normal(f)` is facet `f`'s normal as [`usable`] makes it.
pub(super) fn from_file(
    mut ch: Channel<Vec3>,
    corners: &[u32],
    ring: &Ring,
    facet_normal: impl Fn(usize) -> Vec3,
) -> Channel<Vec3> {
    let mut bad = vec![false; ch.values.len()];
    for (value, bad) in ch.values.iter_mut().zip(&mut bad) {
        match unit(*value) {
            Some(n) => *value = n,
            None => (*value, *bad) = (FALLBACK_NORMAL, true),
        }
    }
    let used_bad = match &ch.indices {
        None => corners.iter().any(|&v| bad[v as usize]),
        Some(ix) => ix.iter().any(|&i| bad[i as usize]),
    };
    if !used_bad {
        return ch;
    }
    if ch.indices.is_none() && repair_per_vertex(&mut ch.values, &bad, corners, ring, &facet_normal)
    {
        return ch;
    }
    let mut indices = ch.indices.take().unwrap_or_else(|| corners.to_vec());
    // One replacement value per facet that needs one, appended on first use.
    let mut replacement = std::collections::HashMap::new();
    for (c, index) in indices.iter_mut().enumerate() {
        if bad[*index as usize] {
            let f = ring.facet(c);
            *index = *replacement.entry(f).or_insert_with(|| {
                ch.values.push(facet_normal(f));
                (ch.values.len() - 1) as u32
            });
        }
    }
    ch.indices = Some(indices);
    ch
}

/// Gives every bad vertex of a per-vertex channel the normal of its facets, if all its
/// corners agree on it bit for bit; false (and `values` unchanged) if one does not.
fn repair_per_vertex(
    values: &mut [Vec3],
    bad: &[bool],
    corners: &[u32],
    ring: &Ring,
    facet_normal: &impl Fn(usize) -> Vec3,
) -> bool {
    let mut want: std::collections::BTreeMap<u32, [u32; 3]> = Default::default();
    for (c, &v) in corners.iter().enumerate() {
        if !bad[v as usize] {
            continue;
        }
        let n = facet_normal(ring.facet(c)).to_array().map(f32::to_bits);
        if *want.entry(v).or_insert(n) != n {
            return false;
        }
    }
    for (v, n) in want {
        values[v as usize] = Vec3::from_array(n.map(f32::from_bits));
    }
    true
}

fn facet_normal(facet: &Facet) -> Vec3 {
    usable(facet.normal)
}

/// A facet normal as a vertex may take it: [`FALLBACK_NORMAL`] for a degenerate facet's
/// zero.
pub(super) fn usable(normal: Vec3) -> Vec3 {
    if normal == Vec3::ZERO {
        FALLBACK_NORMAL
    } else {
        normal
    }
}

/// Normals generated by `policy`, and the matching [`NormalSource`].
pub(super) fn generate(
    positions: &[Vec3],
    corners: &[u32],
    ring: &Ring,
    around: &VertexCorners,
    policy: NormalPolicy,
) -> (Channel<Vec3>, NormalSource) {
    match policy {
        NormalPolicy::Flat => {
            let flat = Channel {
                values: ring.facets.iter().map(facet_normal).collect(),
                indices: Some(ring.facet_table(corners.len())),
            };
            (flat, NormalSource::Flat)
        }
        NormalPolicy::Average(opts) => {
            let mesh = Neighbourhood {
                positions,
                corners,
                facets: ring.facets,
                ring,
                around,
            };
            (mesh.averaged(opts), NormalSource::Averaged(opts))
        }
    }
}

/// What averaging reads of a mesh.
struct Neighbourhood<'a> {
    positions: &'a [Vec3],
    corners: &'a [u32],
    facets: &'a [Facet],
    ring: &'a Ring<'a>,
    around: &'a VertexCorners,
}

impl Neighbourhood<'_> {
    fn averaged(&self, opts: NormalOptions) -> Channel<Vec3> {
        let weights = self.weights(opts.weighting);
        match opts.crease_degrees {
            Some(a) if a.is_finite() && a < 180.0 => self.creased(&weights, a.max(0.0)),
            _ => Channel::per_vertex(self.smooth(&weights)),
        }
    }

    /// The unit normal of corner `c`'s facet (zero if degenerate).
    #[inline]
    fn normal(&self, c: usize) -> Vec3 {
        self.facets[self.ring.facet(c)].normal
    }

    /// Weight of every corner in the average at its vertex; 0 for degenerate facets. In
    /// parallel over ranges of facets (each owns its corners' weights).
    fn weights(&self, weighting: Weighting) -> Vec<f32> {
        let mut weights = vec![0.0f32; self.corners.len()];
        let largest = self.facets.iter().map(|f| f.area).fold(0.0, f32::max);
        // Area weights relative to the largest area, so sums cannot overflow.
        let area_scale = if largest > 0.0 { 1.0 / largest } else { 0.0 };
        let ranges = par::facet_ranges(self.facets, par::parts(self.corners.len(), 4));
        let lengths = ranges.iter().map(|r| {
            let (a, b) = (&self.facets[r.start], &self.facets[r.end - 1]);
            (b.first + b.len - a.first) as usize
        });
        let jobs: Vec<_> = ranges
            .iter()
            .zip(par::split_lengths(&mut weights, lengths))
            .collect();
        jobs.into_par_iter().for_each(|(r, weights)| {
            let base = self.facets[r.start].first as usize;
            for facet in self.facets[r.clone()].iter().filter(|f| !f.is_degenerate()) {
                let c = facet.corners();
                let w = &mut weights[c.start - base..c.end - base];
                match weighting {
                    Weighting::Uniform => w.fill(1.0),
                    Weighting::Area => w.fill(facet.area * area_scale),
                    Weighting::Angle => self.corner_angles(facet, w),
                }
            }
        });
        weights
    }

    /// Interior angles of a non-degenerate facet's corners, in radians (over pi at a reflex
    /// corner of a concave polygon); 0 where a side has zero length.
    fn corner_angles(&self, facet: &Facet, out: &mut [f32]) {
        let ring = &self.corners[facet.corners()];
        let at = |k: usize| self.positions[ring[k] as usize].as_dvec3();
        let normal = facet.normal.as_dvec3();
        // At corner p, the angle runs counter-clockwise about the normal from the side to
        // the next corner to the side to the previous one.
        let angle = |to_next: DVec3, to_prev: DVec3, sin: f64| {
            let a = atan2(sin, to_next.dot(to_prev));
            let a = if a < 0.0 {
                a + std::f64::consts::TAU
            } else {
                a
            };
            if a.is_finite() {
                a as f32
            } else {
                0.0
            }
        };
        if let [a, b, c] = *ring {
            // A triangle's three corners share `to_next x to_prev` (twice its area).
            let p = [a, b, c].map(|v| self.positions[v as usize].as_dvec3());
            let e = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
            let sin = e[0].cross(e[1]).dot(normal);
            out[0] = angle(e[0], -e[2], sin);
            out[1] = angle(e[1], -e[0], sin);
            out[2] = angle(e[2], -e[1], sin);
            return;
        }
        let n = ring.len();
        let (mut prev, mut here) = (at(n - 1), at(0));
        for (k, out) in out.iter_mut().enumerate() {
            let next = at(if k + 1 == n { 0 } else { k + 1 });
            let (to_next, to_prev) = (next - here, prev - here);
            *out = angle(to_next, to_prev, to_next.cross(to_prev).dot(normal));
            (prev, here) = (here, next);
        }
    }

    /// The unit weighted sum of the facet normals at every vertex (`None` if zero or not
    /// finite). In parallel over vertices; each sums its corners in corner order, as one pass
    /// over the corners would.
    fn sums(&self, weights: &[f32]) -> Vec<Option<Vec3>> {
        (0..self.positions.len())
            .into_par_iter()
            .with_min_len(par::MIN_ITEMS)
            .map(|v| {
                let mut sum = Vec3::ZERO;
                for &c in self.around.of(v) {
                    let c = c as usize;
                    if weights[c] > 0.0 {
                        sum += weights[c] * self.normal(c);
                    }
                }
                unit(sum)
            })
            .collect()
    }

    /// One normal per vertex.
    fn smooth(&self, weights: &[f32]) -> Vec<Vec3> {
        let sums = self.sums(weights);
        let mut normals: Vec<Vec3> = sums
            .par_iter()
            .with_min_len(par::MIN_ITEMS)
            .map(|s| s.unwrap_or(FALLBACK_NORMAL))
            .collect();
        if sums.iter().any(Option::is_none) {
            // Isolated vertices, all-degenerate neighbourhoods or cancelling normals (two
            // sides of a sheet): take the first non-degenerate facet normal at the vertex.
            let mut fixed = vec![false; normals.len()];
            for (c, &v) in self.corners.iter().enumerate() {
                let v = v as usize;
                let n = self.normal(c);
                if sums[v].is_none() && !fixed[v] && n != Vec3::ZERO {
                    (normals[v], fixed[v]) = (n, true);
                }
            }
        }
        normals
    }

    /// Per-vertex normals where the facets around a vertex agree within `degrees`, split
    /// (per-corner) where they do not.
    fn creased(&self, weights: &[f32], degrees: f32) -> Channel<Vec3> {
        let cos_full = libm::cosf(degrees.to_radians());
        let cos_half = libm::cosf((0.5 * degrees).to_radians());
        let mut values = self.smooth(weights);
        // Vertices with a facet normal beyond half the angle from the vertex normal: only
        // they can split (at all others, all pairs are within the angle).
        let split: Vec<bool> = (0..values.len())
            .into_par_iter()
            .with_min_len(par::MIN_ITEMS)
            .map(|v| {
                self.around.of(v).iter().any(|&c| {
                    let n = self.normal(c as usize);
                    n != Vec3::ZERO && n.dot(values[v]) < cos_half
                })
            })
            .collect();
        let mut indices: Option<Vec<u32>> = None;
        let mut distinct: Vec<(Vec3, u32)> = Vec::new();
        for v in (0..split.len()).filter(|&v| split[v]) {
            let ring = self.around.of(v);
            if ring.len() > MAX_CREASE_VALENCE || self.all_pairs_within(ring, cos_full) {
                continue; // every corner would average all the facets: keep the vertex normal
            }
            distinct.clear();
            for &c in ring {
                let c = c as usize;
                let own = self.normal(c);
                if own == Vec3::ZERO {
                    continue; // a degenerate facet's corner keeps values[v]
                }
                let mut sum = Vec3::ZERO;
                for &j in ring {
                    let j = j as usize;
                    let n = self.normal(j);
                    let same_facet = self.ring.facet(j) == self.ring.facet(c);
                    if weights[j] > 0.0 && (same_facet || n.dot(own) >= cos_full) {
                        sum += weights[j] * n;
                    }
                }
                let n = unit(sum).unwrap_or(own);
                let index = match distinct.iter().find(|d| d.0 == n) {
                    Some(d) => d.1,
                    None => {
                        let index = if distinct.is_empty() {
                            values[v] = n;
                            v as u32
                        } else {
                            values.push(n);
                            (values.len() - 1) as u32
                        };
                        distinct.push((n, index));
                        index
                    }
                };
                if index != v as u32 {
                    indices.get_or_insert_with(|| self.corners.to_vec())[c] = index;
                }
            }
        }
        Channel { values, indices }
    }

    /// True if the non-degenerate facet normals at the corners `ring` are pairwise within
    /// the crease angle (`cos_full`).
    fn all_pairs_within(&self, ring: &[u32], cos_full: f32) -> bool {
        ring.iter().enumerate().all(|(i, &a)| {
            let na = self.normal(a as usize);
            ring[i + 1..].iter().all(|&b| {
                let nb = self.normal(b as usize);
                na == Vec3::ZERO || nb == Vec3::ZERO || na.dot(nb) >= cos_full
            })
        })
    }
}
