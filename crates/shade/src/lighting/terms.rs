//! What one light does at a surface point: attenuation with distance, the spot's cone and the rectangular spot's pyramid, the light arriving, its diffuse and specular reflection (the textbook's §9.2), the ambient term and the sum over every light.

use super::*;

/// The attenuation factor of `a` at distance `d`.
#[inline(always)]
#[must_use]
pub fn attenuate<T: Num>(a: Attenuation, d: T) -> T {
    match a {
        Attenuation::None => T::ONE,
        Attenuation::Linear { near, far } => {
            let ramp = (T::of(far) - d) / T::of((far - near).max(f32::MIN_POSITIVE));
            T::select(d.gt(T::of(near)), ramp.clamp01(), T::ONE)
        }
        Attenuation::InverseSquare => (d * d).max(T::of64(crate::scene::MIN_D2)).recip(),
        Attenuation::Range(r) => {
            let q = d / T::of(r);
            let q2 = q * q;
            (T::ONE - q2 * q2).clamp01() / (d * d).max(T::of64(crate::scene::MIN_D2))
        }
    }
}

/// The spot factor for `cos_axis`, the cosine of the angle between the spot's axis and the
/// ray to the point: 1 inside the hotspot, 0 outside the falloff, smoothstep between.
#[inline(always)]
#[must_use]
pub fn cone<T: Num>(s: &Source, cos_axis: T) -> T {
    let (ci, co) = (T::of(s.cos_inner), T::of(s.cos_outer));
    let w = (ci - co).max(T::of(1e-4));
    let t = ((cos_axis - co) / w).clamp01();
    t * t * (T::of(3.0) - t - t)
}

/// Where the ray from a rectangular spot to a point falls on its image, as (u, v) with the
/// pyramid at |u|, |v| <= 1, and where that is inside the pyramid (in front of the light
/// and within it). `ray` need not be unit.
#[inline(always)]
#[must_use]
pub fn pyramid<T: Num>(s: &Source, ray: T::V) -> (T, T, T::M) {
    let z = T::dot(ray, T::vec(s.axis));
    let x = T::dot(ray, T::vec(s.right)) / (z * T::of(s.tan.x));
    let y = T::dot(ray, T::vec(s.up)) / (z * T::of(s.tan.y));
    let one = T::ONE;
    let inside = z.gt(T::ZERO) & x.ge(-one) & one.ge(x) & y.ge(-one) & one.ge(y);
    (x, y, inside)
}

/// What arrives at `p` from `s` before shadowing: the unit direction towards the light,
/// the radiance after attenuation, cone or pyramid and projected image, and where any
/// arrives; `None` when nothing does anywhere.
#[inline(always)]
#[must_use]
pub fn arriving<T: Shade>(s: &Source, p: T::V) -> Option<(T::V, T::V, T::M)> {
    let mut rad = T::vec(s.radiance);
    if s.kind == LightKind::Directional {
        return Some((-T::vec(s.axis), rad, T::ONE.gt(T::ZERO)));
    }
    let to = T::vec(s.position) - p;
    let d = T::length(to);
    let ok = d.gt(T::ZERO) & d.finite();
    let l = to * T::select(ok, d.recip(), T::ZERO);
    let mut f = attenuate(s.attenuation, d);
    match s.kind {
        LightKind::Spot => f = f * cone(s, -T::dot(l, T::vec(s.axis))),
        LightKind::Rect => {
            let (x, y, inside) = pyramid::<T>(s, -l);
            f = T::select(inside, f, T::ZERO);
            if let Some(img) = &s.image {
                let half = T::of(0.5);
                let c = T::image(img, (x + T::ONE) * half, (T::ONE - y) * half, inside & ok);
                rad = rad * c;
            }
        }
        _ => {}
    }
    let live = f.gt(T::ZERO) & ok;
    if T::any(live) {
        Some((l, rad * f, live))
    } else {
        None
    }
}

/// Diffuse and specular reflection of unit light direction `l` at unit normal `n`, unit
/// view vector `v` (zero without a specular term), per unit irradiance, where `lit`
/// (`ndl = N·L > 0` there): `K_d (N·L)` and `K_s S` with `S` as in the module
/// documentation, or the glTF BRDF times `N·L` ([`brdf::pbr`]) when the surface has PBR
/// parameters; zero elsewhere.
#[inline(always)]
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn reflect<T: Shade>(
    s: &SurfaceAt<T>,
    n: T::V,
    l: T::V,
    v: T::V,
    lit: T::M,
    ndl: T,
    back: T::M,
    blinn: bool,
) -> Terms<T> {
    let zero = T::splat(T::ZERO);
    let raw = ndl;
    let ndl = T::select(lit, ndl, T::ZERO);
    if let Some(p) = &s.pbr {
        let t = brdf::pbr(s, p, brdf::alpha(p.roughness), n, l, v, ndl);
        let mut diffuse = T::vselect(lit, t.diffuse, zero);
        // A translucent base passes on the light from behind (`back`: where it arrives).
        if let Some(tr) = &p.translucency {
            let through = brdf::translucent(p, tr, n, l, v, raw);
            diffuse = diffuse + T::vselect(back, through, zero);
        }
        return Terms {
            diffuse,
            specular: T::vselect(lit, t.specular, zero),
            ..t
        };
    }
    let diffuse = s.kd * ndl;
    let mut specular = zero;
    if s.has_specular {
        let base = if blinn {
            T::dot(n, T::normalize_or_zero(l + v))
        } else {
            T::dot(n * (ndl + ndl) - l, v)
        };
        let on = lit & base.gt(T::ZERO);
        if T::any(on) {
            let lobe = match s.whole_shininess {
                Some(n) => base.powi(n),
                None => base.powf(s.shininess),
            };
            let lobe = T::select(on, lobe, T::ZERO);
            specular = s.ks * lobe;
        }
    }
    Terms {
        diffuse,
        specular,
        d: T::ZERO,
        vis: T::ZERO,
        fresnel: zero,
        sheen: zero,
        coat: zero,
    }
}

/// Light `s`'s share of the colour at `p` (normal `n`, view vector `v`), shadow included.
#[inline(always)]
#[must_use]
pub fn contribution<T: Shade>(
    set: &LightSet,
    s: &Source,
    surf: &SurfaceAt<T>,
    p: T::V,
    n: T::V,
    v: T::V,
    blinn: bool,
) -> T::V {
    let zero = T::splat(T::ZERO);
    let Some((l, rad, live)) = arriving::<T>(s, p) else {
        return zero;
    };
    let ndl = T::dot(n, l);
    let mut lit = ndl.gt(T::ZERO) & live;
    // Light from behind reaches the front of a translucent base.
    let back = match surf.pbr.as_ref().and_then(|p| p.translucency.as_ref()) {
        Some(_) => T::ZERO.gt(ndl) & live,
        None => T::ZERO.gt(T::ONE),
    };
    let coat = surf
        .pbr
        .as_ref()
        .and_then(|p| p.layers.as_ref()?.coat_normal);
    let ndl = match coat {
        // A clear coat with its own normal can see the light where the mapped base cannot
        // (the base's terms then have N·L 0).
        Some(nc) => {
            lit = lit | (T::dot(nc, l).gt(T::ZERO) & live);
            ndl.max(T::ZERO)
        }
        None => ndl,
    };
    if !T::any(lit | back) {
        return zero;
    }
    let r = reflect(surf, n, l, v, lit, ndl, back, blinn);
    let t = (r.diffuse + r.specular) * rad;
    match set.shadow_of(s) {
        // The shadow map's test offset towards the light: off the back for light from behind.
        Some(map) => t * T::shadow(map, p, T::vselect(back, -n, n), l, lit | back),
        None => t,
    }
}

/// The view vector for the specular term: unit towards the eye, or zero when the surface
/// has no specular term (none is needed).
#[inline(always)]
#[must_use]
pub fn view_vector<T: Num>(surf: &SurfaceAt<T>, p: T::V, eye: T::V) -> T::V {
    if surf.has_specular {
        T::normalize_or_zero(eye - p)
    } else {
        T::splat(T::ZERO)
    }
}

/// The ambient term: `g_amb K_a K_d` times the occlusion (Phong), or for `pbr` the
/// ambient light as a uniform environment of that radiance, reflected by the split-sum
/// image-based term ([`brdf::ibl_fresnel`]) and times the occlusion.
#[inline(always)]
#[must_use]
pub fn ambient<T: Shade>(set: &LightSet, s: &SurfaceAt<T>, n: T::V, v: T::V) -> T::V {
    let mut s = *s;
    ambient_at(set, &mut s, n, v)
}

/// [`ambient`], setting on `s` what the punctual lights then read at this point and view:
/// `E_ss` for the compensation ([`crate::brdf::Pbr::ess`]: 1 for Phong, or when
/// `set.single_scatter`) and the layers' values ([`crate::brdf::Layers::view`]), from the
/// same table lookups.
#[inline(always)]
#[must_use]
pub fn ambient_at<T: Shade>(set: &LightSet, s: &mut SurfaceAt<T>, n: T::V, v: T::V) -> T::V {
    let (diffuse, specular) = ambient_terms(set, s, n, v);
    let c = diffuse + specular;
    match s.occlusion {
        Some(ao) => c * ao,
        None => c,
    }
}

/// [`ambient`] before the occlusion, as its diffuse and specular parts (the pixel probe
/// lists both; Phong's is all diffuse; the layers' reflection is in the specular part).
#[inline(always)]
#[must_use]
pub fn ambient_split<T: Shade>(set: &LightSet, s: &SurfaceAt<T>, n: T::V, v: T::V) -> (T::V, T::V) {
    let mut s = *s;
    ambient_terms(set, &mut s, n, v)
}

/// Sets on `s` the values that depend on the view at this point, as [`ambient_at`] does
/// (for a caller that lights the point without an ambient term, the pixel probe).
#[inline(always)]
pub fn view_terms<T: Shade>(s: &mut SurfaceAt<T>, n: T::V, v: T::V, single_scatter: bool) {
    let Some(p) = &mut s.pbr else {
        return;
    };
    let nv = T::dot(n, v).max(T::of(1e-4));
    let ess = T::brdf_lut(nv, p.roughness).2;
    p.ess = if single_scatter { T::ONE } else { ess };
    if let Some(i) = &mut p.iridescence {
        i.view(nv, p.f0, s.kd);
    }
    if let Some(y) = &mut p.layers {
        let e = sheen_view::<T>(y, nv);
        y.view(coat_nv(y, v, nv), e);
    }
}

/// `N·V` with the coat's normal (`nv`, the shading normal's, when it has none of its own).
#[inline(always)]
fn coat_nv<T: Num>(y: &crate::brdf::Layers<T>, v: T::V, nv: T) -> T {
    match y.coat_normal {
        Some(nc) => T::dot(nc, v).max(T::of(1e-4)),
        None => nv,
    }
}

/// The sheen's albedo at the view, when there is a sheen (zero otherwise: no lookup).
#[inline(always)]
fn sheen_view<T: Shade>(y: &crate::brdf::Layers<T>, nv: T) -> T {
    if T::any(y.sheen_max.gt(T::ZERO)) {
        T::sheen_albedo(nv, y.sheen_roughness)
    } else {
        T::ZERO
    }
}

/// The direction to read a lobe of `roughness` from the specular chain: Frostbite's
/// dominant direction (Lagarde & de Rousiers 2014, §4.9.3): a rough lobe's peak leans from
/// the mirror direction toward the normal; at grazing views on rough metal, reading the
/// chain along the mirror direction measured 18 % too bright against the integral.
#[inline(always)]
fn dominant<T: Num>(n: T::V, v: T::V, nv: T, roughness: T) -> T::V {
    let alpha = brdf::alpha(roughness);
    let smooth = T::ONE - alpha;
    let lean = smooth * (smooth.sqrt() + alpha);
    n + (n * (nv + nv) - v - n) * lean
}

/// [`ambient_split`], setting the per-point values as [`ambient_at`] does.
#[inline(always)]
fn ambient_terms<T: Shade>(set: &LightSet, s: &mut SurfaceAt<T>, n: T::V, v: T::V) -> (T::V, T::V) {
    let g = T::vec(set.ambient);
    let kd = s.kd;
    let Some(p) = &mut s.pbr else {
        return (g * s.ka * kd, T::splat(T::ZERO));
    };
    let nv = T::dot(n, v).max(T::of(1e-4));
    let (a, b, ess) = T::brdf_lut(nv, p.roughness);
    p.ess = if set.single_scatter { T::ONE } else { ess };
    // Prefiltered radiance along the reflection and irradiance over π: the ambient light
    // is a uniform environment, where both equal its radiance.
    let (prefiltered, irradiance) = match &set.env {
        Some(env) => {
            // An anisotropic base reads the light about its bent normal.
            let r = match &p.anisotropy {
                Some(a) => {
                    let bent = a.bent(n, v, p.roughness);
                    dominant::<T>(bent, v, T::dot(bent, v).max(T::of(1e-4)), p.roughness)
                }
                None => dominant::<T>(n, v, nv, p.roughness),
            };
            let (s, e) = T::env(env, n, r, p.roughness);
            (s + g, e + g)
        }
        None => (g, g),
    };
    // A thin film: each lobe's F0 mixed with the one its Fresnel at the view makes.
    let (f0, metal_f0) = match &mut p.iridescence {
        Some(i) => {
            i.view(nv, p.f0, kd);
            let film = brdf::Iridescence::<T>::to_f0(i.dielectric, nv);
            let metal = brdf::Iridescence::<T>::to_f0(i.metal, nv);
            (i.mix(p.f0, film), i.mix(kd, metal))
        }
        None => (p.f0, kd),
    };
    let (d_ss, d_ms) = brdf::ibl_fresnel::<T>(f0, p.f90, a, b);
    let (m_ss, m_ms) = brdf::ibl_fresnel::<T>(metal_f0, T::ONE, a, b);
    // Dielectric: the diffuse term gets the energy the specular lobe leaves.
    let left = T::splat(T::ONE) - d_ss - d_ms;
    let dielectric = T::ONE - p.metallic;
    let mut diffuse = kd * left * irradiance * dielectric;
    // A transmissive base: the diffuse term gives way to the light through it (the
    // shader's `transmit` stage).
    if let Some(t) = &p.transmission {
        diffuse = diffuse * (T::ONE - t.factor);
    }
    // A translucent base: `mix(base colour x irradiance, colour x the irradiance behind)`.
    if let Some(tr) = &p.translucency {
        let behind = match &set.env {
            Some(env) => T::env(env, -n, -n, p.roughness).1 + g,
            None => g,
        };
        diffuse =
            diffuse * (T::ONE - tr.factor) + tr.color * left * behind * (tr.factor * dielectric);
    }
    let specular = (d_ss * prefiltered + d_ms * irradiance) * dielectric
        + (m_ss * prefiltered + m_ms * irradiance) * p.metallic;
    let Some(y) = &mut p.layers else {
        return (diffuse, specular);
    };
    let ev = sheen_view::<T>(y, nv);
    let cnv = coat_nv(y, v, nv);
    y.view(cnv, ev);
    let (mut diffuse, mut specular) = (diffuse, specular);
    if T::any(y.sheen_max.gt(T::ZERO)) {
        // The sheen: its albedo at the view times the radiance averaged over its lobe (the
        // environment's sheen chain, prefiltered with N = V as the specular chain is).
        let sheen_light = match &set.env {
            Some(env) => T::env_sheen(env, n, y.sheen_roughness) + g,
            None => g,
        };
        let scale = (T::ONE - y.sheen_max * ev).max(T::ZERO);
        diffuse = diffuse * scale;
        specular = specular * scale + y.sheen * sheen_light * ev;
    }
    if T::any(y.coat.gt(T::ZERO)) {
        // mix(beneath, coat, clearcoat Fr(N·V)) with the coat's lobe (D Vis, no Fresnel of
        // its own) integrated against the surround: its split sum `A + B` at its roughness
        // times the prefiltered radiance.
        let nc = y.coat_normal.unwrap_or(n);
        let (ca, cb, _) = T::brdf_lut(cnv, y.coat_roughness);
        let coat_light = match &set.env {
            Some(env) => {
                let r = dominant::<T>(nc, v, cnv, y.coat_roughness);
                T::env(env, nc, r, y.coat_roughness).0 + g
            }
            None => g,
        };
        diffuse = diffuse * y.coat_keep;
        specular = specular * y.coat_keep + coat_light * ((T::ONE - y.coat_keep) * (ca + cb));
    }
    (diffuse, specular)
}

/// The lighting equation at `p` with unit normal `n` and the eye at `eye`, summed over the
/// sources `active` (indices into `set.sources`; all of them if `None`), plus the
/// surface's emission. Fog is applied separately ([`Fog::apply`]).
#[must_use]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn illuminate<T: Shade>(
    set: &LightSet,
    active: Option<&[u32]>,
    surf: &SurfaceAt<T>,
    p: T::V,
    n: T::V,
    eye: T::V,
    blinn: bool,
) -> T::V {
    let v = view_vector(surf, p, eye);
    let mut lit = *surf;
    let mut c = ambient_at(set, &mut lit, n, v);
    let surf = &lit;
    if let Some(e) = surf.emitted {
        c = c + emission_seen(surf, e);
    }
    // One loop body for both cases: it is inlined into every shader of every kernel, so a
    // second copy would double the largest functions the compiler sees.
    let count = active.map_or(set.sources.len(), <[u32]>::len);
    for k in 0..count {
        let i = active.map_or(k, |a| a[k] as usize);
        if let Some(s) = set.sources.get(i) {
            c = c + contribution(set, s, surf, p, n, v, blinn);
        }
    }
    c
}

/// The emission `e` as seen through the clear coat, if any (`1 - clearcoat Fr(N·V)` of it;
/// after [`ambient_at`] or [`view_terms`] set the point's values).
#[inline(always)]
#[must_use]
pub fn emission_seen<T: Num>(s: &SurfaceAt<T>, e: T::V) -> T::V {
    match s.pbr.as_ref().and_then(|p| p.layers.as_ref()) {
        Some(y) => e * y.coat_keep,
        None => e,
    }
}
