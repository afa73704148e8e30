use glam::{DVec3, Vec2, Vec3};

use super::*;
use crate::simd::kernel::__private::Portable;
use crate::simd::{Real, F8, V3};

type P = F8<Portable>;

fn white() -> Surface {
    Surface {
        diffuse: Vec3::ONE,
        specular: Vec3::ONE,
        ambient: Vec3::ONE,
        shininess: 10.0,
        pbr: None,
    }
}

fn lit<T: Real + Shade>(
    set: &LightSet,
    s: &Surface,
    p: Vec3,
    n: Vec3,
    eye: Vec3,
    blinn: bool,
) -> Vec3 {
    let at = s.at::<T>(T::vec(s.diffuse));
    T::to_vec3(illuminate::<T>(
        set,
        None,
        &at,
        T::vec(p),
        T::vec(n),
        T::vec(eye),
        blinn,
    ))
}

#[test]
fn lambert_and_mirror_highlight() {
    let lights = LightSet::new(&[Light::directional(-Vec3::Z, Vec3::ONE)]);
    // Light and eye straight above the surface: N.L = 1, R.V = 1.
    let c = lit::<f32>(&lights, &white(), Vec3::ZERO, Vec3::Z, Vec3::Z * 5.0, false);
    assert!((c - Vec3::splat(2.0)).abs().max_element() < 1e-6, "{c}");
    // Light at 60 degrees: diffuse 0.5; eye on the mirror direction: specular 1.
    let l = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
    let lights = LightSet::new(&[Light::directional(-l, Vec3::ONE)]);
    let eye = Vec3::new(-l.x, 0.0, l.z) * 4.0;
    for blinn in [false, true] {
        let c = lit::<f64>(&lights, &white(), Vec3::ZERO, Vec3::Z, eye, blinn);
        assert!((c.x - 1.5).abs() < 1e-5, "{c}");
    }
}

#[test]
fn back_lit_gets_only_ambient_and_ambient_never_attenuates() {
    let lights = LightSet::new(&[
        Light::ambient(Vec3::splat(0.1)).with_attenuation(Attenuation::InverseSquare),
        Light::directional(Vec3::Z, Vec3::ONE),
    ]);
    let c = lit::<f32>(&lights, &white(), Vec3::ZERO, Vec3::Z, Vec3::Z, true);
    assert!((c - Vec3::splat(0.1)).abs().max_element() < 1e-7);
}

#[test]
fn attenuation_modes_follow_their_formulas() {
    let lin = Attenuation::Linear {
        near: 2.0,
        far: 6.0,
    };
    for (d, want) in [
        (0.0, 1.0),
        (2.0, 1.0),
        (3.0, 0.75),
        (5.0, 0.25),
        (6.0, 0.0),
        (9.0, 0.0),
    ] {
        assert!((lin.factor(d) - want).abs() < 1e-12, "{d}");
        assert!((attenuate::<f32>(lin, d as f32) - want as f32).abs() < 1e-6);
    }
    assert!((Attenuation::InverseSquare.factor(4.0) - 1.0 / 16.0).abs() < 1e-15);
    let r = Attenuation::Range(10.0);
    assert!((r.factor(5.0) - (1.0 - 0.0625) / 25.0).abs() < 1e-12);
    assert_eq!(r.factor(10.0), 0.0);
    assert_eq!(r.factor(11.0), 0.0);
    assert_eq!(lin.reach(), 6.0);
    assert_eq!(Attenuation::InverseSquare.reach(), f32::INFINITY);
    assert!(!Attenuation::Linear {
        near: 3.0,
        far: 1.0
    }
    .is_valid());
    assert!(!Attenuation::Range(f32::NAN).is_valid());
}

#[test]
fn spot_cone_is_full_inside_the_hotspot_zero_outside_and_smooth_between() {
    let spot = Light::spot(
        Vec3::Z * 4.0,
        -Vec3::Z,
        Vec3::ONE,
        10f32.to_radians(),
        20f32.to_radians(),
    );
    let set = LightSet::new(std::slice::from_ref(&spot));
    let s = &set.sources[0];
    let at = |deg: f64| {
        let x = 4.0 * libm::tan(deg.to_radians());
        arriving::<f64>(s, DVec3::new(x, 0.0, 0.0)).map_or(0.0, |(_, r, _)| r.x)
    };
    assert!((at(0.0) - 1.0).abs() < 1e-9);
    assert!((at(9.9) - 1.0).abs() < 1e-9);
    assert_eq!(at(20.1), 0.0);
    let mut last = 1.0;
    for k in 0..=100 {
        let v = at(10.0 + k as f64 * 0.1);
        assert!(v <= last + 1e-12 && (0.0..=1.0).contains(&v), "{k}: {v}");
        last = v;
    }
    // Halfway in cos: smoothstep(0.5) = 0.5.
    let (ci, co) = (libm::cos(10f64.to_radians()), libm::cos(20f64.to_radians()));
    let mid = libm::acos((ci + co) / 2.0).to_degrees();
    assert!((at(mid) - 0.5).abs() < 1e-4, "{}", at(mid));
}

#[test]
fn rect_spot_lights_a_rectangle_and_projects_its_image_upright() {
    use crate::texture::Texture;
    // 2x2 image: top-left red, top-right green, bottom-left blue, bottom-right white.
    let px = [
        [255, 0, 0, 255],
        [0, 255, 0, 255],
        [0, 0, 255, 255],
        [255, 255, 255, 255],
    ];
    let img = Texture::new("slide", 2, 2, px.to_vec(), true).unwrap();
    let light = Light::rect(
        Vec3::Z * 2.0,
        -Vec3::Z,
        Vec3::Y,
        Vec2::new(libm::atanf(0.5f32), libm::atanf(0.25f32)),
        Vec3::ONE,
    )
    .with_image(std::sync::Arc::new(img));
    let set = LightSet::new(std::slice::from_ref(&light));
    let s = &set.sources[0];
    // On the plane z = 0 the pyramid covers |x| <= 1, |y| <= 0.5.
    let at = |x: f32, y: f32| arriving::<f32>(s, Vec3::new(x, y, 0.0)).map(|(_, r, _)| r);
    assert!(at(1.05, 0.0).is_none() && at(0.0, 0.55).is_none());
    let tl = at(-0.9, 0.45).unwrap();
    let tr = at(0.9, 0.45).unwrap();
    let bl = at(-0.9, -0.45).unwrap();
    assert!(tl.x > 0.9 && tl.y < 0.1 && tl.z < 0.1, "{tl}");
    assert!(tr.y > 0.9 && tr.x < 0.1, "{tr}");
    assert!(bl.z > 0.9 && bl.x < 0.1, "{bl}");
}

#[test]
fn reaches_never_skips_a_light_that_arrives() {
    let mut seed = 11u64;
    let mut r = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    };
    let mut skipped = 0;
    for case in 0..300 {
        let mut light = Light::spot(
            Vec3::new(r(), r(), r()) * 3.0,
            Vec3::new(r(), r(), r()),
            Vec3::ONE,
            0.2,
            0.2 + r().abs(),
        )
        .with_attenuation(Attenuation::Linear {
            near: 0.5,
            far: 2.0 + 3.0 * r().abs(),
        });
        if case % 3 == 1 {
            light.kind = LightKind::Rect;
            light.rect = Vec2::new(0.3 + r().abs(), 0.2 + r().abs());
            light.up = Vec3::new(r(), r(), r());
        }
        if case % 3 == 2 {
            light.kind = LightKind::Point;
        }
        let set = LightSet::new(std::slice::from_ref(&light));
        let Some(s) = set.sources.first() else {
            continue;
        };
        let c = Vec3::new(r(), r(), r()) * 4.0;
        let radius = r().abs() * 1.5;
        if s.reaches(c, radius) {
            continue;
        }
        skipped += 1;
        for _ in 0..200 {
            let q = Vec3::new(r(), r(), r());
            if q.length() > 1.0 {
                continue;
            }
            let p = c + q * radius;
            assert!(
                arriving::<f64>(s, p.as_dvec3()).is_none(),
                "case {case}: light reaches {p} inside a skipped sphere"
            );
        }
    }
    assert!(
        skipped > 40,
        "only {skipped} skips: the test does not exercise them"
    );
}

fn random_lights(r: &mut impl FnMut() -> f32) -> Vec<Light> {
    vec![
        Light::ambient(Vec3::splat(0.1)),
        Light::directional(Vec3::new(r(), r(), r()), Vec3::new(0.9, 0.8, 0.7)),
        Light::point(Vec3::new(r(), r(), r()) * 3.0, Vec3::ONE)
            .with_attenuation(Attenuation::InverseSquare)
            .with_intensity(4.0),
        Light::spot(
            Vec3::new(r(), r(), r()) * 3.0,
            Vec3::new(r(), r(), r()),
            Vec3::new(0.5, 1.0, 0.7),
            0.3,
            0.9,
        )
        .with_attenuation(Attenuation::Linear {
            near: 1.0,
            far: 6.0,
        }),
        Light::rect(
            Vec3::new(r(), r(), r()) * 3.0,
            Vec3::new(r(), r(), r()),
            Vec3::Y,
            Vec2::new(0.8, 0.6),
            Vec3::ONE,
        )
        .with_attenuation(Attenuation::Range(8.0)),
    ]
}

/// The lane form against the scalar one (f32 and f64) on random surfaces, lights and views.
#[test]
fn lanes_agree_with_scalar() {
    fn check() {
        let mut seed = 7u64;
        let mut r = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        };
        let mut worst = 0f32;
        for case in 0..400 {
            let lights = LightSet::new(&random_lights(&mut r));
            assert_eq!(lights.sources.len(), 4);
            let s = Surface {
                diffuse: Vec3::new(0.8, 0.5, 0.2),
                specular: if case % 5 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::splat(0.5)
                },
                ambient: Vec3::ONE,
                shininess: [1.0, 8.0, 32.0, 200.0][case % 4],
                pbr: None,
            };
            let eye = Vec3::new(r(), r(), r()) * 4.0;
            let mut p = [Vec3::ZERO; 8];
            let mut n = [Vec3::ZERO; 8];
            for i in 0..8 {
                p[i] = Vec3::new(r(), r(), r());
                n[i] = Vec3::new(r(), r(), r()).normalize_or_zero();
            }
            let lanes = |f: &dyn Fn(Vec3) -> f32, v: &[Vec3; 8]| P::from_array(v.map(f));
            let v3 =
                |v: &[Vec3; 8]| V3::new(lanes(&|v| v.x, v), lanes(&|v| v.y, v), lanes(&|v| v.z, v));
            let sl = s.at::<P>(V3::splat(s.diffuse));
            let all: Vec<u32> = (0..lights.sources.len() as u32).collect();
            for blinn in [false, true] {
                let eye8 = V3::splat(eye);
                let got = illuminate::<P>(&lights, Some(&all), &sl, v3(&p), v3(&n), eye8, blinn);
                for i in 0..8 {
                    let want = lit::<f32>(&lights, &s, p[i], n[i], eye, blinn);
                    let want64 = lit::<f64>(&lights, &s, p[i], n[i], eye, blinn);
                    let g = got.lane(i);
                    let err = (g - want).abs().max_element();
                    let err64 = (want - want64).abs().max_element();
                    worst = worst.max(err);
                    let tol = 2e-5 * (1.0 + want.max_element());
                    assert!(err < tol, "case {case}: {g} vs {want}");
                    assert!(err64 < tol, "case {case}: f32 {want} vs f64 {want64}");
                }
            }
        }
        assert!(worst < 5e-5, "worst {worst}");
    }
    check();
}

#[test]
fn non_finite_and_degenerate_lights_are_dropped_and_counted() {
    let set = LightSet::new(&[
        Light::ambient(Vec3::splat(f32::NAN)),
        Light::directional(Vec3::ZERO, Vec3::ONE),
        Light::point(Vec3::new(f32::INFINITY, 0.0, 0.0), Vec3::ONE),
        Light::spot(Vec3::ZERO, -Vec3::Z, Vec3::ONE, 0.1, 0.0),
        Light::point(Vec3::ZERO, Vec3::ONE).with_attenuation(Attenuation::Range(-1.0)),
        Light::point(Vec3::ZERO, Vec3::ONE),
    ]);
    assert_eq!(set.dropped, 5);
    assert_eq!(set.sources.len(), 1);
    assert_eq!(set.sources[0].index, 5);
    assert_eq!(set.ambient, Vec3::ZERO);
}

#[test]
fn fog_blends_towards_its_colour_between_near_and_far() {
    let fog = Fog {
        color: Vec3::new(0.5, 0.6, 0.7),
        near: 2.0,
        far: 6.0,
        distance: FogDistance::Euclidean,
    };
    let c = Vec3::ONE;
    let at = |f: &Fog, p: Vec3| f.apply::<f64>(c.as_dvec3(), p.as_dvec3(), DVec3::ZERO, -DVec3::Z);
    assert_eq!(at(&fog, Vec3::new(0.0, 0.0, -1.0)), DVec3::ONE);
    let far = at(&fog, Vec3::new(0.0, 0.0, -7.0));
    assert!((far - fog.color.as_dvec3()).abs().max_element() < 1e-9);
    // At distance 4 (Euclidean) f = 0.5; the same point has depth 4 cos 60 = 2 -> no fog.
    let p = Vec3::new(4.0 * 0.75f32.sqrt(), 0.0, -2.0);
    let half = at(&fog, p);
    assert!(
        (half - (DVec3::ONE + fog.color.as_dvec3()) * 0.5)
            .abs()
            .max_element()
            < 1e-6
    );
    let depth = Fog {
        distance: FogDistance::Depth,
        ..fog
    };
    assert!((at(&depth, p) - DVec3::ONE).abs().max_element() < 1e-6);
    // The lane form agrees.
    let pv = V3::splat(p);
    let lanes = fog.apply::<P>(V3::splat(c), pv, V3::splat(Vec3::ZERO), V3::splat(-Vec3::Z));
    assert!((lanes.x.lane(3) as f64 - half.x).abs() < 1e-6);
}
