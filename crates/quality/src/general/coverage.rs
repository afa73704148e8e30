//! Visibility in f64: homogeneous triangle set-up, near/far clipping to bound the
//! samples, coverage with the tie rule, and the interpolation of a triangle's attributes.

use super::*;

/// A triangle ready for sampling: homogeneous edge functions over sample positions in
/// pixels, and the inclusive sample bounds of its visible part.
#[derive(Clone, Copy, Debug)]
pub(super) struct Setup {
    pub(super) inst: u32,
    /// Render-vertex indices.
    pub(super) v: [u32; 3],
    /// `V_1 x V_2`, `V_2 x V_0`, `V_0 x V_1` as (a, b, c): `e(p) = a px + b py + c`.
    pub(super) e: [DVec3; 3],
    /// `1 / det M`; `c_k = e_k(p) / det`.
    pub(super) inv_det: f64,
    /// Sign of `det M`: a sample is inside when `sign * e_k(p) >= 0` for all k.
    pub(super) sign: f64,
    /// Whether a sample with `e_k(p) == 0` exactly belongs to this triangle.
    pub(super) tie: [bool; 3],
    /// `z / w` as a function of the sample position, if a vertex lies outside the near or
    /// far plane (else every inside sample is between them).
    pub(super) depth: Option<DVec3>,
    pub(super) front: bool,
    /// Inclusive sample index bounds `[x0, x1, y0, y1]` within the image.
    pub(super) bounds: [i64; 4],
}

/// Sets up triangle `t` of instance `inst` (index `i`); `None` if it is degenerate, has a
/// non-finite vertex, is culled, or covers no sample of the image.
pub(super) fn setup(view: &View, inst: &Inst, i: u32, t: u32) -> Option<Setup> {
    let tri = inst.tri;
    let v = *tri.triangles.get(t as usize)?;
    let mut clip = [DVec4::ZERO; 3];
    for k in 0..3 {
        let p = tri.positions.get(v[k] as usize)?.as_dvec3();
        clip[k] = inst.mvp * p.extend(1.0);
        if !clip[k].is_finite() {
            return None;
        }
    }
    let (hw, hh) = (f64::from(view.width) * 0.5, f64::from(view.height) * 0.5);
    let hv = clip.map(|c| DVec3::new((c.x + c.w) * hw, (c.w - c.y) * hh, c.w));
    let e = [hv[1].cross(hv[2]), hv[2].cross(hv[0]), hv[0].cross(hv[1])];
    let det = hv[0].dot(e[0]);
    if det == 0.0 || !det.is_finite() || !e.iter().all(|e| e.is_finite()) {
        return None;
    }
    // det < 0: counter-clockwise in normalised device coordinates (y up), the front.
    let front = (det < 0.0) != inst.flip;
    if inst.cull && !front {
        return None;
    }
    let sign = det.signum();
    let tie = e.map(|e| {
        let (a, b) = (sign * e.x, sign * e.y);
        a > 0.0 || (a == 0.0 && b > 0.0)
    });
    // The part between the near and far planes, clipped in homogeneous space, bounds the
    // samples to visit; the per-sample test decides coverage exactly.
    let crosses = clip.iter().any(|c| c.z < 0.0 || c.z > c.w);
    let poly = if crosses {
        clip_near_far(&clip)
    } else {
        clip.to_vec()
    };
    if poly.len() < 3 {
        return None;
    }
    let depth = crosses.then(|| (e[0] * clip[0].z + e[1] * clip[1].z + e[2] * clip[2].z) / det);
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for c in &poly {
        if c.w <= 0.0 {
            // Rounding of a clipped vertex: fall back to the whole image.
            lo = DVec2::splat(f64::NEG_INFINITY);
            hi = DVec2::splat(f64::INFINITY);
            break;
        }
        let p = DVec2::new((c.x / c.w + 1.0) * hw, (1.0 - c.y / c.w) * hh);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    // Sample j sits at (j + 0.5) / s; keep a margin for the rounding of clipped vertices.
    let s = f64::from(view.samples);
    // First (`lower`) or last sample index at or inside pixel coordinate p.
    let index = |p: f64, lower: bool| {
        let margin = 1e-6 + 1e-12 * p.abs() * s;
        let x = p * s - 0.5;
        let x = if lower { x - margin } else { x + margin }.clamp(-1e15, 1e15);
        (if lower { x.ceil() } else { x.floor() }) as i64
    };
    let (sw, sh) = (
        i64::from(view.width * view.samples),
        i64::from(view.height * view.samples),
    );
    let bounds = [
        index(lo.x, true).max(0),
        index(hi.x, false).min(sw - 1),
        index(lo.y, true).max(0),
        index(hi.y, false).min(sh - 1),
    ];
    if bounds[0] > bounds[1] || bounds[2] > bounds[3] {
        return None;
    }
    Some(Setup {
        inst: i,
        v,
        e,
        inv_det: 1.0 / det,
        sign,
        tie,
        depth,
        front,
        bounds,
    })
}

/// Sutherland-Hodgman against the near (`z <= w`) and far (`z >= 0`) planes, intersections
/// computed from the inside vertex.
pub(super) fn clip_near_far(tri: &[DVec4; 3]) -> Vec<DVec4> {
    let mut poly = tri.to_vec();
    let planes: [fn(DVec4) -> f64; 2] = [|c| c.w - c.z, |c| c.z];
    for d in planes {
        let mut out = Vec::with_capacity(poly.len() + 1);
        crate::geom::clip_polygon(
            &poly,
            |p| d(*p) >= 0.0,
            |&i, &o| i + (o - i) * crate::geom::crossing(d(i), d(o)),
            &mut out,
        );
        poly = out;
        if poly.len() < 3 {
            return Vec::new();
        }
    }
    poly
}

/// Position of sample index `j` in pixels.
#[inline]
pub(super) fn sample_pos(j: i64, s: f64) -> f64 {
    (j as f64 + 0.5) / s
}

/// Calls `f(sx, sy, 1/w, px, py)` for every sample inside `g` within `x0..=x1`, `y0..=y1`
/// (sample indices), in row order.
#[inline]
pub(super) fn cover(
    g: &Setup,
    s: f64,
    [x0, x1, y0, y1]: [i64; 4],
    mut f: impl FnMut(i64, i64, f64, f64, f64),
) {
    let inside = |v: f64, k: usize| {
        let v = v * g.sign;
        v > 0.0 || (v == 0.0 && g.tie[k])
    };
    for sy in y0..=y1 {
        let py = sample_pos(sy, s);
        let r = g.e.map(|e| e.y * py + e.z);
        for sx in x0..=x1 {
            let px = sample_pos(sx, s);
            let v = [
                g.e[0].x * px + r[0],
                g.e[1].x * px + r[1],
                g.e[2].x * px + r[2],
            ];
            if !(inside(v[0], 0) && inside(v[1], 1) && inside(v[2], 2)) {
                continue;
            }
            if let Some(z) = g.depth {
                let z = z.x * px + z.y * py + z.z;
                if !(0.0..=1.0).contains(&z) {
                    continue;
                }
            }
            f(sx, sy, (v[0] + v[1] + v[2]) * g.inv_det, px, py);
        }
    }
}

/// A set-up triangle with its world-space vertices, ready to shade.
pub(super) struct Tri {
    pub(super) g: Setup,
    pub(super) p: [DVec3; 3],
    /// Unit world normals (zero where the transformed normal vanishes).
    pub(super) n: [DVec3; 3],
}

impl Tri {
    pub(super) fn new(g: Setup, inst: &Inst) -> Self {
        let (tri, v) = (inst.tri, g.v);
        Self {
            g,
            p: v.map(|k| {
                inst.world
                    .transform_point3(tri.positions[k as usize].as_dvec3())
            }),
            n: v.map(|k| {
                let n = tri.normals.get(k as usize).copied().unwrap_or_default();
                (inst.normal * n.as_dvec3()).normalize_or_zero()
            }),
        }
    }

    /// Perspective-correct barycentrics at sample position (px, py).
    #[inline]
    pub(super) fn bary(&self, px: f64, py: f64) -> DVec3 {
        let c = DVec3::from_array(
            self.g
                .e
                .map(|e| (e.x * px + e.y * py + e.z) * self.g.inv_det),
        );
        c / (c.x + c.y + c.z)
    }

    /// Base colour (material x vertex colour x texture) at barycentrics `b`.
    pub(super) fn base(&self, inst: &Inst, b: DVec3) -> DVec4 {
        let v = self.g.v.map(|k| k as usize);
        let mut base = inst.base;
        if let Some(c) = &inst.tri.colors {
            let at = |k: usize| c.get(v[k]).map_or(DVec4::ONE, |c| c.as_dvec4());
            base *= at(0) * b.x + at(1) * b.y + at(2) * b.z;
        }
        if let Some(t) = &inst.texture {
            base *= t.at(inst.tri, v, b);
        }
        base
    }

    /// The fragment at sample position (px, py): linear RGB and alpha, or `None` if the
    /// alpha test discards it.
    pub(super) fn shade(&self, view: &View, inst: &Inst, px: f64, py: f64) -> Option<DVec4> {
        let b = self.bary(px, py);
        let base = self.base(inst, b);
        let alpha = match inst.alpha {
            Alpha::Opaque => 1.0,
            Alpha::Mask(cutoff) if base.w >= cutoff => 1.0,
            Alpha::Mask(_) => return None,
            Alpha::Blend => base.w,
        };
        let p = self.p[0] * b.x + self.p[1] * b.y + self.p[2] * b.z;
        let mut n = (self.n[0] * b.x + self.n[1] * b.y + self.n[2] * b.z).normalize_or_zero();
        // Before the maps: the clear coat's normal when the base is normal- or bump-mapped.
        let mut geometric = n;
        let v = self.g.v.map(|k| k as usize);
        // A tangent-space normal map applied to `n` (the base's or the clear coat's).
        let normal_mapped = |map: &RefSlot, n: DVec3| {
            let frame = match &inst.tri.tangents {
                Some(ts) => {
                    let at = |k: usize| ts.get(v[k]).map_or(DVec4::X, |t| t.as_dvec4());
                    let t4 = at(0) * b.x + at(1) * b.y + at(2) * b.z;
                    let t = (DMat3::from_mat4(inst.world) * t4.truncate()).normalize_or_zero();
                    Some((t, t4.w * inst.handed))
                }
                None => map.uv_tangent(inst.tri, v, &self.p, n),
            };
            match frame {
                Some((t, w)) => {
                    let c = map.at(inst.tri, v, b).truncate().to_array();
                    maps::perturb::<f64>(n, t, w, c, map.scale)
                }
                None => n,
            }
        };
        if let Some(map) = &inst.normal_map {
            n = normal_mapped(map, n);
        }
        let coat_map =
            inst.layer_maps[Slot::ClearcoatNormal.layer_index().unwrap_or_default()].as_ref();
        if let Some(map) = coat_map {
            geometric = normal_mapped(map, geometric);
        }
        if let Some(bm) = &inst.bump {
            if let Some(g) = bm.bump_gradient(inst.tri, v, &self.p, b, n) {
                n = maps::bump::<f64>(n, g);
            }
        }
        if !self.g.front {
            n = -n;
            geometric = -geometric;
        }
        if inst.unlit {
            return Some(base.truncate().extend(alpha));
        }
        let mut surf = inst.surface.at::<f64>(base.truncate());
        if let (Some(y), true) = (
            surf.pbr.as_mut().and_then(|p| p.layers.as_mut()),
            inst.normal_map.is_some() || inst.bump.is_some() || coat_map.is_some(),
        ) {
            y.coat_normal = Some(geometric);
        }
        if let Some(g) = &inst.gloss {
            surf.ks *= g.at(inst.tri, v, b).truncate();
        }
        if let (Some(mr), Some(p)) = (&inst.metal_rough, &mut surf.pbr) {
            let t = mr.at(inst.tri, v, b);
            p.roughness *= t.y;
            p.metallic *= t.z;
        }
        if let (Some(p), Some(params)) = (&mut surf.pbr, &inst.surface.pbr) {
            let mut texels = LayerTexels::<f64>::default();
            for (slot, t) in Slot::LAYERS.iter().zip(&inst.layer_maps) {
                if let Some(t) = t {
                    texels.read(*slot, t.at(inst.tri, v, b).to_array());
                }
            }
            texels.apply(params, p);
            // Anisotropy, in the frame of the mesh's tangents, about the normal before it
            // turned to the side seen.
            if let Some(ts) = &inst.tri.tangents {
                let at = |k: usize| ts.get(v[k]).map_or(DVec4::X, |t| t.as_dvec4());
                let t4 = at(0) * b.x + at(1) * b.y + at(2) * b.z;
                let t = DMat3::from_mat4(inst.world) * t4.truncate();
                let unturned = if self.g.front { n } else { -n };
                p.anisotropy = texels.anisotropy(params, unturned, t, t4.w * inst.handed);
            }
        }
        if let Some(o) = &inst.occlusion {
            // On the ambient (or image-based) term only.
            surf.occlusion = Some(maps::occlusion(o.at(inst.tri, v, b).x, o.scale));
        }
        let mut c = match &surf.pbr {
            Some(pb) if view.env_samples > 0 => {
                let lit = illuminate::<f64>(&view.punctual, None, &surf, p, n, view.eye, false);
                let v = (view.eye - p).normalize_or_zero();
                let env = environment(view, &surf, pb, n, v, (px, py));
                lit + surf.occlusion.map_or(env, |ao| env * ao)
            }
            _ => illuminate::<f64>(&view.lights, None, &surf, p, n, view.eye, view.blinn),
        };
        let emitted = match &inst.emissive_map {
            Some(m) => inst.emissive * m.at(inst.tri, v, b).truncate(),
            None => inst.emissive,
        };
        // Seen through the clear coat, if any.
        crate::shade::view_terms(&mut surf, n, (view.eye - p).normalize_or_zero(), true);
        c += crate::shade::emission_seen(&surf, emitted);
        if let Some(fog) = &view.fog {
            c = fog.apply::<f64>(c, p, view.eye, view.forward);
        }
        Some(c.extend(alpha))
    }

    /// Whether the alpha test keeps the fragment at (px, py).
    pub(super) fn kept(&self, inst: &Inst, px: f64, py: f64) -> bool {
        match inst.alpha {
            Alpha::Mask(cutoff) => self.base(inst, self.bary(px, py)).w >= cutoff,
            _ => true,
        }
    }
}
