//! The path tracer's random numbers and directions: the per-sample generator, the frame
//! around a normal, the power heuristic, Smith's masking and the GGX visible normals, and
//! the BRDF's sampling lobes.

use crate::scalar::Scalar;
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
pub(super) fn frame<T: Scalar>(n: T::V) -> (T::V, T::V) {
    let [nx, ny, nz] = T::xyz(n);
    let one = T::ONE;
    let s = one.copysign(nz);
    let a = -one / (s + nz);
    let b = nx * ny * a;
    (
        T::new3(one + s * nx * nx * a, s * b, -s * nx),
        T::new3(b, s + ny * ny * a, -ny),
    )
}

pub(super) fn luminance<T: Scalar>(c: T::V) -> T {
    let [r, g, b] = T::xyz(c);
    T::of(0.2126) * r + T::of(0.7152) * g + T::of(0.0722) * b
}

/// The power heuristic's weight of a sample of density `a` against `b`.
pub(super) fn mis<T: Scalar>(a: T, b: T) -> T {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > T::ZERO && (a2 + b2).is_finite() {
        a2 / (a2 + b2)
    } else if a.to_f64().is_infinite() {
        T::ONE
    } else {
        T::ZERO
    }
}

/// Smith's masking of the view for GGX α at `NV`.
pub(super) fn g1<T: Scalar>(nv: T, a: T) -> T {
    let a2 = a * a;
    T::of(2.0) * nv / (nv + (a2 + (T::ONE - a2) * nv * nv).sqrt())
}

/// A microfacet normal of GGX (roughness `alpha`) about unit normal `n`, drawn among those
/// visible from unit direction `v` in proportion to their projected area (Heitz 2018,
/// "Sampling the GGX Distribution of Visible Normals"); `None` if `v` is below the surface.
pub(super) fn vndf<T: Scalar>(n: T::V, v: T::V, alpha: T, rng: &mut Rng) -> Option<T::V> {
    let (t, b) = frame::<T>(n);
    let (vx, vy, vz) = (T::dot(v, t), T::dot(v, b), T::dot(v, n));
    if vz <= T::ZERO {
        return None;
    }
    let [hx, hy, hz] = T::xyz(T::normalize_or_zero(T::new3(alpha * vx, alpha * vy, vz)));
    let vh = T::new3(hx, hy, hz);
    let len2 = hx * hx + hy * hy;
    let t1 = if len2 > T::ZERO {
        T::vdiv(T::new3(-hy, hx, T::ZERO), len2.sqrt())
    } else {
        T::new3(T::ONE, T::ZERO, T::ZERO)
    };
    let t2 = T::cross(vh, t1);
    let (u1, u2) = (T::of(rng.f()), T::of(rng.f()));
    let r = u1.sqrt();
    let phi = T::of64(std::f64::consts::TAU) * u2;
    let p1 = r * phi.cos();
    let s = T::of(0.5) * (T::ONE + hz);
    let p2 = (T::ONE - s) * (T::ONE - p1 * p1).max(T::ZERO).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (T::ONE - p1 * p1 - p2 * p2).max(T::ZERO).sqrt();
    let [nx, ny, nz] = T::xyz(nh);
    let [x, y, z] = T::xyz(T::normalize_or_zero(T::new3(
        alpha * nx,
        alpha * ny,
        nz.max(T::ZERO),
    )));
    Some(t * x + b * y + n * z)
}

/// The BRDF's sampling lobes at a point.
pub(super) struct Lobes<T: Scalar> {
    pub(super) n: T::V,
    pub(super) v: T::V,
    pub(super) alpha: T,
    /// Chance of drawing from the specular lobe (else the cosine lobe).
    pub(super) p_spec: T,
}

impl<T: Scalar> Lobes<T> {
    /// A direction and its density under the mixture.
    pub(super) fn sample(&self, rng: &mut Rng) -> Option<(T::V, T)> {
        let l = if T::of(rng.f()) < self.p_spec {
            let h = vndf::<T>(self.n, self.v, self.alpha, rng)?;
            h * (T::of(2.0) * T::dot(self.v, h)) - self.v
        } else {
            let (t, b) = frame::<T>(self.n);
            let (u1, u2) = (T::of(rng.f()), T::of(rng.f()));
            let r = u1.sqrt();
            let phi = T::of64(std::f64::consts::TAU) * u2;
            t * (r * phi.cos()) + b * (r * phi.sin()) + self.n * (T::ONE - u1).max(T::ZERO).sqrt()
        };
        let l = T::normalize_or_zero(l);
        let pdf = self.pdf(l);
        (pdf > T::ZERO && pdf.is_finite()).then_some((l, pdf))
    }

    /// The mixture's density of direction `l`.
    pub(super) fn pdf(&self, l: T::V) -> T {
        let nl = T::dot(self.n, l);
        if nl <= T::ZERO {
            return T::ZERO;
        }
        let diffuse = nl * T::of64(std::f64::consts::FRAC_1_PI);
        let nv = T::dot(self.n, self.v);
        let h = T::normalize_or_zero(l + self.v);
        let spec = if nv > T::ZERO {
            let d = ggx::<T>(T::dot(self.n, h).max(T::ZERO), self.alpha);
            g1(nv, self.alpha) * d / (T::of(4.0) * nv)
        } else {
            T::ZERO
        };
        self.p_spec * spec + (T::ONE - self.p_spec) * diffuse
    }
}
