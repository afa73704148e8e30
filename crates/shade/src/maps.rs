//! What a material's texture maps do to the surface at a point, beyond colour: the
//! tangent-space normal map and ambient occlusion (glTF's conventions, the specification's
//! "Additional Textures"). Written once per precision family: [`perturb`] over [`Real`]
//! (`f32` for the probe, `f64` for the reference) and [`perturb_lanes`] on eight lanes for
//! the shaders, with the same steps in the same order.

use super::Real;
use crate::simd::{Level, F8, V3};

/// The unit normal `n` perturbed by a normal-map texel `c` (RGB = (m + 1) / 2, linear) with
/// scale `scale`, in the frame of the tangent `t` (made orthogonal to `n`, Gram-Schmidt) and
/// the bitangent `B = w (n × t)`, `w` the tangent's handedness (its sign counts):
/// `m = normalize(scale (2r - 1), scale (2g - 1), 2b - 1)`, `n' = normalize(mₓ T + m_y B +
/// m_z n)`. Returns `n` itself where the tangent is degenerate (parallel to `n`, or zero).
#[must_use]
#[inline]
pub fn perturb<T: Real>(n: T::V, t: T::V, w: T, c: [T; 3], scale: T) -> T::V {
    let t = T::normalize_or_zero(t - n * T::dot(n, t));
    if T::dot(t, t) == T::ZERO {
        return n;
    }
    let sign = if w < T::ZERO { -T::ONE } else { T::ONE };
    let b = T::cross(n, t) * sign;
    let two = T::ONE + T::ONE;
    let (x, y, z) = (
        (c[0] * two - T::ONE) * scale,
        (c[1] * two - T::ONE) * scale,
        c[2] * two - T::ONE,
    );
    let len2 = x * x + y * y + z * z;
    if !(len2 > T::ZERO && len2.is_finite()) {
        return n;
    }
    let inv = T::ONE / len2.sqrt();
    T::normalize_or_zero(t * (x * inv) + b * (y * inv) + n * (z * inv))
}

/// [`perturb`] on eight lanes.
#[inline(always)]
#[must_use]
pub fn perturb_lanes<L: Level>(n: V3<L>, t: V3<L>, w: F8<L>, c: [F8<L>; 4], scale: f32) -> V3<L> {
    let t = (t - n.scale(n.dot(t))).normalize_or_zero();
    let sign = F8::select(w.lt(F8::ZERO), -F8::ONE, F8::ONE);
    let b = n.cross(t).scale(sign);
    let two = F8::splat(2.0);
    let x = (c[0] * two - F8::ONE) * scale;
    let y = (c[1] * two - F8::ONE) * scale;
    let z = c[2] * two - F8::ONE;
    let m = V3::new(x, y, z).normalize_or_zero();
    let p = (t.scale(m.x) + b.scale(m.y) + n.scale(m.z)).normalize_or_zero();
    let ok = t.dot(t).gt(F8::ZERO);
    V3::new(
        F8::select(ok, p.x, n.x),
        F8::select(ok, p.y, n.y),
        F8::select(ok, p.z, n.z),
    )
}

/// The surface gradient of a scalar field `f` on a surface with unit normal `n`, from its
/// changes `df1`, `df2` along two vectors `s1`, `s2` that span the tangent plane (the
/// screen-space derivatives of the position, or two edges of a triangle): the vector `g` in
/// the plane with `g · s1 = df1`, `g · s2 = df2`, by Mikkelsen's dual basis ("Bump Mapping
/// Unparametrized Surfaces on the GPU", 2010) `g = (df1 (s2 × n) + df2 (n × s1)) / (s1 ·
/// (s2 × n))`. Any basis of the plane gives the same `g`. `None` where `s1` and `s2` do not
/// span a plane (a surface seen edge-on, or a degenerate triangle).
#[must_use]
#[inline]
pub fn surface_gradient<T: Real>(n: T::V, s1: T::V, s2: T::V, df1: T, df2: T) -> Option<T::V> {
    let r1 = T::cross(s2, n);
    let r2 = T::cross(n, s1);
    let det = T::dot(s1, r1);
    let scale = T::length(s1) * T::length(s2);
    let magnitude = if det < T::ZERO { -det } else { det };
    if !(magnitude > scale * T::of(1e-6) && det.is_finite()) {
        return None;
    }
    let g = (r1 * df1 + r2 * df2) * (T::ONE / det);
    T::dot(g, g).is_finite().then_some(g)
}

/// The tangent dP/du and its handedness `w` for a surface without tangents, from two
/// vectors `s1`, `s2` spanning its tangent plane and the UV's changes along them (`du` =
/// (du1, du2), `dv` = (dv1, dv2)), by the chain rule's 2 x 2 system: the screen-space
/// derivatives of the position and UV per pixel in the renderer, a triangle's edges in the
/// pixel probe and the f64 reference. `w` makes `B = w (N × T)` run along -v, the convention
/// of [`crate::mesh::Mesh::tangents`]. `None` where the UVs do not span the plane.
#[must_use]
#[inline]
pub fn uv_tangent<T: Real>(
    n: T::V,
    s1: T::V,
    s2: T::V,
    du: (T, T),
    dv: (T, T),
) -> Option<(T::V, T)> {
    let det = du.0 * dv.1 - du.1 * dv.0;
    if !(det != T::ZERO && det.is_finite()) {
        return None;
    }
    let inv = T::ONE / det;
    let dp_du = (s1 * dv.1 - s2 * dv.0) * inv;
    let dp_dv = (s2 * du.0 - s1 * du.1) * inv;
    if !(T::dot(dp_du, dp_du).is_finite() && T::dot(dp_dv, dp_dv).is_finite()) {
        return None;
    }
    let w = if T::dot(T::cross(n, dp_du), dp_dv) > T::ZERO {
        -T::ONE
    } else {
        T::ONE
    };
    Some((dp_du, w))
}

/// Bump mapping (Blinn): the unit normal `n` tilted against the surface gradient `g` of the
/// displacement, `normalize(n - g)`; `n` itself where that is not finite or zero.
#[must_use]
#[inline]
pub fn bump<T: Real>(n: T::V, g: T::V) -> T::V {
    let p = T::normalize_or_zero(n - g);
    if T::dot(p, p) > T::ZERO {
        p
    } else {
        n
    }
}

/// The surface gradient of a displacement given as a height field over texture space,
/// `scale · h(u, v)` measured in units of UV (as if one unit of UV were one unit of length
/// on the surface, the way a tangent-space normal map is): `scale (h_u û + h_v v̂)` with
/// `û`, `v̂` the unit surface gradients of u and v (the directions in which they grow), each
/// from [`surface_gradient`] with the UV's changes `du`, `dv` along `s1`, `s2`. This is the
/// normal map `(-scale h_u, scale h_v, 1)` in the tangent frame glTF uses (bitangent along
/// -v), with no tangent attribute needed. `None` where u or v has no gradient.
#[must_use]
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn uv_height_gradient<T: Real>(
    n: T::V,
    s1: T::V,
    s2: T::V,
    du: (T, T),
    dv: (T, T),
    h_uv: (T, T),
    scale: T,
) -> Option<T::V> {
    let gu = T::normalize_or_zero(surface_gradient::<T>(n, s1, s2, du.0, du.1)?);
    let gv = T::normalize_or_zero(surface_gradient::<T>(n, s1, s2, dv.0, dv.1)?);
    Some((gu * h_uv.0 + gv * h_uv.1) * scale)
}

/// glTF's occlusion: `1 + strength (r - 1)` for the texel's R, applied to the ambient
/// (indirect) light only.
#[must_use]
#[inline]
pub fn occlusion<T: Real>(r: T, strength: T) -> T {
    T::ONE + strength * (r - T::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::kernel::{dispatch, KernelJob};
    use crate::simd::KernelKind;
    use glam::{DVec3, Vec3};

    #[test]
    fn a_flat_texel_keeps_the_normal_and_tilts_follow_the_tangent_frame() {
        let n = DVec3::Z;
        let t = DVec3::X;
        let flat = perturb::<f64>(n, t, 1.0, [0.5, 0.5, 1.0], 1.0);
        assert!((flat - n).length() < 1e-12, "{flat}");
        // +x in the map tilts towards +T; +y towards B = w (n × t) = +Y for w = 1, -Y for -1.
        let x = perturb::<f64>(n, t, 1.0, [1.0, 0.5, 0.5], 1.0);
        assert!((x - DVec3::X).length() < 1e-12, "{x}");
        let y = perturb::<f64>(n, t, 1.0, [0.5, 1.0, 0.5], 1.0);
        assert!((y - DVec3::Y).length() < 1e-12, "{y}");
        let y = perturb::<f64>(n, t, -1.0, [0.5, 1.0, 0.5], 1.0);
        assert!((y + DVec3::Y).length() < 1e-12, "{y}");
        // Scale 0 flattens the map; a tangent along n leaves n.
        let s0 = perturb::<f64>(n, t, 1.0, [0.9, 0.1, 0.7], 0.0);
        assert!((s0 - n).length() < 1e-12, "{s0}");
        assert_eq!(perturb::<f64>(n, n, 1.0, [0.9, 0.1, 0.7], 1.0), n);
        // A tangent not orthogonal to n is straightened first.
        let tilted = perturb::<f64>(n, DVec3::new(1.0, 0.0, 0.7), 1.0, [1.0, 0.5, 0.5], 1.0);
        assert!((tilted - DVec3::X).length() < 1e-12, "{tilted}");
    }

    struct Job;
    impl KernelJob for Job {
        type Output = f32;
        #[inline(always)]
        fn run<L: Level>(self) -> f32 {
            let mut worst = 0.0f32;
            let mut seed = 3u32;
            let mut r = move || {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (seed >> 8) as f32 / (1u32 << 24) as f32
            };
            for _ in 0..200 {
                let mut lanes = [[0.0f32; 11]; 8];
                for l in &mut lanes {
                    for v in l.iter_mut() {
                        *v = r();
                    }
                }
                let f = |i: usize| F8::<L>::from_array(lanes.map(|l| l[i]));
                let n0 = V3::new(f(0) - 0.5, f(1) - 0.5, f(2) + 0.2).normalize_or_zero();
                let t0 = V3::new(f(3) - 0.5, f(4) - 0.5, f(5) - 0.5);
                let w = f(6) - 0.5;
                let c = [f(7), f(8), f(9), F8::ONE];
                let got = perturb_lanes(n0, t0, w, c, 1.3);
                for i in 0..8 {
                    let g = |v: F8<L>| v.lane(i);
                    let n = Vec3::new(g(n0.x), g(n0.y), g(n0.z));
                    let t = Vec3::new(g(t0.x), g(t0.y), g(t0.z));
                    let want = perturb::<f32>(n, t, g(w), [g(c[0]), g(c[1]), g(c[2])], 1.3);
                    let have = Vec3::new(g(got.x), g(got.y), g(got.z));
                    worst = worst.max((have - want).abs().max_element());
                }
            }
            worst
        }
    }

    #[test]
    fn the_lanes_agree_with_the_scalar_form_on_every_kernel() {
        for kind in KernelKind::available_kinds() {
            let worst = dispatch(kind, Job);
            assert!(worst < 1e-5, "{kind:?}: {worst}");
        }
    }
}
