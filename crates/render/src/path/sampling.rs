//! The path tracer's random numbers and directions: the per-sample generator, the frame
//! around a normal, the power heuristic, Smith's masking and the GGX visible normals, and
//! the BRDF's sampling lobes.

use glam::Vec3;

use crate::texture::microfacet::ggx;

/// A small, fast generator (PCG32), seeded per pixel sample.
pub(super) struct Rng(u64);

impl Rng {
    pub(super) fn new(x: u32, y: u32, sample: u32, seed: u64) -> Self {
        let mut h = seed ^ 0x9e37_79b9_7f4a_7c15;
        for v in [x, y, sample] {
            h = (h ^ u64::from(v)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            h ^= h >> 31;
        }
        let mut r = Self(h);
        r.next();
        r
    }

    pub(super) fn next(&mut self) -> u32 {
        let old = self.0;
        self.0 = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in `[0, 1)`.
    pub(super) fn f(&mut self) -> f32 {
        (self.next() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

/// An orthonormal frame around unit `n` (Duff et al. 2017).
pub(super) fn frame(n: Vec3) -> (Vec3, Vec3) {
    let s = 1f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

pub(super) fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The power heuristic's weight of a sample of density `a` against `b`.
pub(super) fn mis(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && (a2 + b2).is_finite() {
        a2 / (a2 + b2)
    } else if a.is_infinite() {
        1.0
    } else {
        0.0
    }
}

/// Smith's masking of the view for GGX α at `NV`.
pub(super) fn g1(nv: f32, a: f32) -> f32 {
    let a2 = a * a;
    2.0 * nv / (nv + (a2 + (1.0 - a2) * nv * nv).sqrt())
}

/// A microfacet normal of GGX (roughness `alpha`) about unit normal `n`, drawn among those
/// visible from unit direction `v` in proportion to their projected area (Heitz 2018,
/// "Sampling the GGX Distribution of Visible Normals"); `None` if `v` is below the surface.
pub(super) fn vndf(n: Vec3, v: Vec3, alpha: f32, rng: &mut Rng) -> Option<Vec3> {
    let (t, b) = frame(n);
    let v = Vec3::new(v.dot(t), v.dot(b), v.dot(n));
    if v.z <= 0.0 {
        return None;
    }
    let vh = Vec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        Vec3::X
    };
    let t2 = vh.cross(t1);
    let (u1, u2) = (rng.f(), rng.f());
    let r = u1.sqrt();
    let phi = std::f32::consts::TAU * u2;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    let h = Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize();
    Some(t * h.x + b * h.y + n * h.z)
}

/// The BRDF's sampling lobes at a point.
pub(super) struct Lobes {
    pub(super) n: Vec3,
    pub(super) v: Vec3,
    pub(super) alpha: f32,
    /// Chance of drawing from the specular lobe (else the cosine lobe).
    pub(super) p_spec: f32,
}

impl Lobes {
    /// A direction and its density under the mixture.
    pub(super) fn sample(&self, rng: &mut Rng) -> Option<(Vec3, f32)> {
        let l = if rng.f() < self.p_spec {
            let h = vndf(self.n, self.v, self.alpha, rng)?;
            2.0 * self.v.dot(h) * h - self.v
        } else {
            let (t, b) = frame(self.n);
            let (u1, u2) = (rng.f(), rng.f());
            let r = u1.sqrt();
            let phi = std::f32::consts::TAU * u2;
            t * (r * phi.cos()) + b * (r * phi.sin()) + self.n * (1.0 - u1).max(0.0).sqrt()
        };
        let l = l.normalize_or_zero();
        let pdf = self.pdf(l);
        (pdf > 0.0 && pdf.is_finite()).then_some((l, pdf))
    }

    /// The mixture's density of direction `l`.
    pub(super) fn pdf(&self, l: Vec3) -> f32 {
        let nl = self.n.dot(l);
        if nl <= 0.0 {
            return 0.0;
        }
        let diffuse = nl * std::f32::consts::FRAC_1_PI;
        let nv = self.n.dot(self.v);
        let h = (l + self.v).normalize_or_zero();
        let spec = if nv > 0.0 {
            let d = ggx::<f32>(self.n.dot(h).max(0.0), self.alpha);
            g1(nv, self.alpha) * d / (4.0 * nv)
        } else {
            0.0
        };
        self.p_spec * spec + (1.0 - self.p_spec) * diffuse
    }
}
