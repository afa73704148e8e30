//! The image-based term of a `pbr` surface point integrated by sampling ([`reference_env`]):
//! GGX half vectors and cosine directions over the environment's full-resolution radiance.

use super::*;

/// The image-based term of a `pbr` surface point, integrated ([`reference_env`]); `at` is
/// the sample position, which seeds the offset of the point sets.
pub(super) fn environment(
    view: &View,
    s: &SurfaceAt<f64>,
    pb: &Pbr<f64>,
    n: DVec3,
    v: DVec3,
    at: (f64, f64),
) -> DVec3 {
    use std::f64::consts::PI;
    let g = view.lights.ambient.as_dvec3();
    let radiance = |l: DVec3| match &view.lights.env {
        Some(env) => g + env.radiance_f64(l),
        None => g,
    };
    let count = view.env_samples;
    // A Cranley-Patterson offset from the sample position (splitmix64 of its bits).
    let mut h = at.0.to_bits() ^ at.1.to_bits().rotate_left(29) ^ 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        h = h.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as f64 / u64::MAX as f64
    };
    let offset = (next(), next());
    let point = |i: u32| {
        let (a, b) = microfacet::hammersley(i, count);
        ((a + offset.0).fract(), (b + offset.1).fract())
    };
    let (t, b) = n.any_orthonormal_pair();
    let world = |d: DVec3| t * d.x + b * d.y + n * d.z;
    // E/π: cosine-distributed directions, pdf NL/π.
    // And behind (about -n) for a translucent base.
    let (mut irradiance, mut behind) = (DVec3::ZERO, DVec3::ZERO);
    for i in 0..count {
        let (u1, u2) = point(i);
        let (r, phi) = (u1.sqrt(), 2.0 * PI * u2);
        let d = world(DVec3::new(
            r * libm::cos(phi),
            r * libm::sin(phi),
            (1.0 - u1).sqrt(),
        ));
        irradiance += radiance(d);
        if pb.translucency.is_some() {
            behind += radiance(-d);
        }
    }
    irradiance /= f64::from(count);
    behind /= f64::from(count);
    // The specular lobe: GGX half vectors, pdf(l) = D NH / (4 VH), so the weight of
    // D Vis NL is g = 4 Vis NL VH / NH.
    let nv = n.dot(v).max(1e-4);
    let alpha = microfacet::alpha::<f64>(pb.roughness);
    let (mut a, mut bias) = (0.0, 0.0);
    let (mut spec_d, mut spec_m) = (DVec3::ZERO, DVec3::ZERO);
    // A thin film's Fresnel at each sample's V·H, the extension's model (the renderer takes
    // it at N·V), and the dielectric lobe's albedo with it.
    let film = pb.iridescence.as_ref();
    let mut film_albedo = DVec3::ZERO;
    for i in 0..count {
        let hv = world(microfacet::sample_h(point(i), alpha));
        let vh = v.dot(hv);
        let l = hv * (2.0 * vh) - v;
        let (nl, nh) = (n.dot(l), n.dot(hv));
        if vh <= 0.0 || nl <= 0.0 || nh <= 0.0 {
            continue;
        }
        let g = 4.0 * microfacet::smith_vis::<f64>(nl, nv, alpha) * nl * vh / nh;
        let w = microfacet::schlick_weight::<f64>(vh);
        a += (1.0 - w) * g;
        bias += w * g;
        let light = radiance(l) * g;
        let (mut fd, mut fm) = (
            microfacet::schlick::<f64>(pb.f0, pb.f90, w),
            microfacet::schlick::<f64>(s.kd, 1.0, w),
        );
        if let Some(f) = film {
            let at = |f0| iridescence::fresnel::<f64>(1.0, f.ior, vh, f.thickness, f0);
            fd = f.mix(fd, at(pb.f0));
            fm = f.mix(fm, at(s.kd));
            film_albedo += fd * g;
        }
        spec_d += fd * light;
        spec_m += fm * light;
    }
    let k = 1.0 / f64::from(count);
    let (a, bias, spec_d, spec_m) = (a * k, bias * k, spec_d * k, spec_m * k);
    let (mut d_ss, d_ms) = brdf::ibl_fresnel::<f64>(pb.f0, pb.f90, a, bias);
    if film.is_some() {
        d_ss = film_albedo * k;
    }
    let (_, m_ms) = brdf::ibl_fresnel::<f64>(s.kd, 1.0, a, bias);
    let lit_diffuse = match &pb.translucency {
        Some(tr) => s.kd * irradiance * (1.0 - tr.factor) + tr.color * behind * tr.factor,
        None => s.kd * irradiance,
    };
    let diel = lit_diffuse * (DVec3::ONE - d_ss - d_ms) + spec_d + d_ms * irradiance;
    let metal = spec_m + m_ms * irradiance;
    let base = diel * (1.0 - pb.metallic) + metal * pb.metallic;
    let Some(y) = &pb.layers else {
        return base;
    };
    // The layers (`brdf::Layers`), their lobes integrated here rather than tabulated.
    let mut out = base;
    if y.sheen_max > 0.0 {
        // The sheen: cosine-distributed directions (pdf NL/π), so `∫ f NL L dω` is the mean
        // of π f L, and its albedo E the mean of π f.
        let (mut e, mut light) = (0.0, DVec3::ZERO);
        for i in 0..count {
            let (u1, u2) = point(i);
            let (r, phi) = (u1.sqrt(), 2.0 * PI * u2);
            let l = world(DVec3::new(
                r * libm::cos(phi),
                r * libm::sin(phi),
                (1.0 - u1).sqrt(),
            ));
            let nl = n.dot(l);
            if nl <= 0.0 {
                continue;
            }
            let nh = n.dot((l + v).normalize_or_zero()).max(0.0);
            let f = crate::shade::sheen::charlie_d(nh, y.sheen_alpha)
                * crate::shade::sheen::charlie_v(nl, nv, y.sheen_alpha)
                * PI;
            e += f;
            light += radiance(l) * f;
        }
        let (e, light) = (e * k, light * k);
        out = out * (1.0 - y.sheen_max * e).max(0.0) + y.sheen * light;
    }
    if y.coat > 0.0 {
        // The coat: its GGX lobe D Vis NL against the surround (about its own normal),
        // weighted by clearcoat Fr(N·V) over what lies beneath.
        let alpha = y.coat_alpha;
        let nc = y.coat_normal.unwrap_or(n);
        let cnv = nc.dot(v).max(1e-4);
        let (ct, cb) = nc.any_orthonormal_pair();
        let mut light = DVec3::ZERO;
        for i in 0..count {
            let h = microfacet::sample_h(point(i), alpha);
            let hv = ct * h.x + cb * h.y + nc * h.z;
            let vh = v.dot(hv);
            let l = hv * (2.0 * vh) - v;
            let (nl, nh) = (nc.dot(l), nc.dot(hv));
            if vh <= 0.0 || nl <= 0.0 || nh <= 0.0 {
                continue;
            }
            light +=
                radiance(l) * (4.0 * microfacet::smith_vis::<f64>(nl, cnv, alpha) * nl * vh / nh);
        }
        let fr = f64::from(brdf::COAT_F0)
            + (1.0 - f64::from(brdf::COAT_F0)) * microfacet::schlick_weight::<f64>(cnv);
        let weight = y.coat * fr;
        out = out * (1.0 - weight) + light * (k * weight);
    }
    out
}
