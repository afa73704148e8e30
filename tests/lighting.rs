//! The lighting model against its formulas, measured on rendered frames: each light type and
//! attenuation mode on a lit plane (the brightness at every sampled pixel against the
//! formula evaluated independently here, in f64, at the world point the pixel shows), fog on
//! and off with both distance kinds, alpha blending and masking, two-sided lighting, and
//! shadow coverage of a square occluder against its analytic outline; and the shared teapot
//! under every light type and fog against the f64 reference of `quality::general`.

use std::sync::Arc;

use glam::{DVec3, Mat4, Vec2, Vec3, Vec4};
use realist::mesh::Mesh;
use realist::render::{Lights, PreparedScene, Renderer, Settings, View};
use realist::scene::{AlphaMode, Attenuation, Camera, Instance, Light, Material, Scene, Style};
use realist::shade::{Fog, FogDistance, Shading};

/// Linear-light tolerance of a lit pixel against its formula: f32 shading, the depth
/// buffer's reconstruction of the point, and the pixel-centre sampling of steep profiles
/// (a spot's falloff) stay well below it; a wrong formula (a missing square, a wrong ramp
/// end, a linear instead of a smooth cone edge) is off by far more.
const TOL: f64 = 4e-3;
/// Plane albedo.
const KD: f32 = 0.5;
const SIZE: u32 = 128;

fn matte(kd: f32) -> Material {
    Material {
        name: "matte".into(),
        base_color: Vec4::new(kd, kd, kd, 1.0),
        specular: Vec3::ZERO,
        ambient: Vec3::ONE,
        ..Material::default()
    }
}

fn place(scene: &mut Scene, mut mesh: Mesh, material: Material, world: Mat4) {
    mesh.material = Some(scene.materials.len());
    scene.materials.push(material);
    scene.instances.push(Instance {
        mesh: scene.meshes.len(),
        world,
        name: mesh.name.clone(),
        style: Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    scene.meshes.push(mesh);
}

/// An 8 x 8 plane at y = 0 facing +Y, finely cut.
fn plane_scene() -> Scene {
    let mut scene = Scene::default();
    place(
        &mut scene,
        Mesh::grid(4.0, 4.0, 64, 64).unwrap(),
        matte(KD),
        Mat4::IDENTITY,
    );
    scene
}

/// Looking straight down at the plane from 6 units up (60 degree field of view: the whole
/// image shows plane).
fn top_view() -> View {
    View {
        camera: Camera {
            name: "top".into(),
            eye: Vec3::new(0.0, 6.0, 0.0),
            target: Vec3::ZERO,
            up: -Vec3::Z,
            yfov: 60f32.to_radians(),
            near: 0.5,
            far: 50.0,
            ..Camera::default()
        },
        width: SIZE,
        height: SIZE,
    }
}

fn settings(lights: Vec<Light>, shading: Shading) -> Settings {
    Settings {
        shading: Some(shading),
        lights: Lights::Custom {
            lights,
            follow_camera: false,
        },
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        ..Settings::default()
    }
}

/// Renders and returns, for every fourth pixel in each direction that shows a surface, the
/// world point (from the depth buffer) and the linear colour.
fn samples(scene: &Scene, settings: &Settings, view: &View) -> Vec<(Vec3, Vec4)> {
    let prepared = PreparedScene::new(scene.clone());
    let mut r = Renderer::new();
    r.render(&prepared, settings, view);
    let target = r.target().expect("a frame");
    let mut out = Vec::new();
    for y in (1..view.height).step_by(4) {
        for x in (1..view.width).step_by(4) {
            if let (Some(p), Some((c, _))) = (r.pick(x, y), target.pixel(x, y)) {
                out.push((p, c));
            }
        }
    }
    out
}

/// Checks every sample against `want(point) -> linear grey level`; returns how many were
/// checked.
fn check(what: &str, got: &[(Vec3, Vec4)], want: impl Fn(DVec3) -> f64) -> usize {
    let mut worst = 0f64;
    for &(p, c) in got {
        let w = want(p.as_dvec3());
        let e = (f64::from(c.x) - w).abs();
        worst = worst.max(e);
        assert!(e < TOL, "{what}: at {p} got {} want {w} (error {e})", c.x);
    }
    assert!(got.len() > 500, "{what}: only {} samples", got.len());
    eprintln!("{what}: {} samples, worst error {worst:.2e}", got.len());
    got.len()
}

/// Lambert factor at a plane point for a light at `pos`.
fn ndl(p: DVec3, pos: DVec3) -> (f64, f64) {
    let to = pos - p;
    let d = to.length();
    ((to.y / d).max(0.0), d)
}

#[test]
fn directional_and_ambient_light_a_plane_evenly() {
    let scene = plane_scene();
    let dir = Vec3::new(0.3, -1.0, 0.5);
    let cos = f64::from(-dir.normalize().y);
    for mode in [Shading::Phong, Shading::Gouraud, Shading::Blinn] {
        let s = settings(
            vec![
                Light::ambient(Vec3::splat(0.2)).with_attenuation(Attenuation::InverseSquare),
                Light::directional(dir, Vec3::ONE)
                    .with_intensity(0.8)
                    .with_attenuation(Attenuation::Linear {
                        near: 0.0,
                        far: 0.1,
                    }),
            ],
            mode,
        );
        let got = samples(&scene, &s, &top_view());
        // Ambient and directional lights never attenuate.
        check(&format!("directional {mode}"), &got, |_| {
            f64::from(KD) * (0.2 + 0.8 * cos)
        });
    }
}

#[test]
fn point_light_attenuation_modes_follow_their_formulas() {
    let scene = plane_scene();
    let pos = DVec3::new(0.5, 2.0, -0.3);
    // Each mode with the light's intensity and the factor it should give at distance d.
    type Falloff = Box<dyn Fn(f64) -> f64>;
    let modes: [(Attenuation, f32, Falloff); 4] = [
        (Attenuation::None, 1.0, Box::new(|_| 1.0)),
        (
            Attenuation::Linear {
                near: 2.5,
                far: 4.5,
            },
            1.0,
            // Full strength within d_min, linear to zero at d_max.
            Box::new(|d: f64| ((4.5 - d) / 2.0).clamp(0.0, 1.0)),
        ),
        (
            Attenuation::InverseSquare,
            4.0,
            Box::new(|d: f64| 1.0 / (d * d)),
        ),
        (
            Attenuation::Range(4.0),
            4.0,
            Box::new(|d: f64| (1.0 - (d / 4.0).powi(4)).clamp(0.0, 1.0) / (d * d)),
        ),
    ];
    for (att, intensity, f) in &modes {
        let light = Light::point(pos.as_vec3(), Vec3::ONE)
            .with_intensity(*intensity)
            .with_attenuation(*att);
        let got = samples(&scene, &settings(vec![light], Shading::Phong), &top_view());
        check(&format!("point {}", att.name()), &got, |p| {
            let (c, d) = ndl(p, pos);
            f64::from(KD) * f64::from(*intensity) * c * f(d)
        });
    }
}

/// Smoothstep in cos between the falloff and hotspot angles.
fn spot_factor(cos_axis: f64, inner: f64, outer: f64) -> f64 {
    let t = ((cos_axis - libm::cos(outer)) / (libm::cos(inner) - libm::cos(outer))).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[test]
fn spot_light_has_a_hotspot_and_a_smooth_falloff() {
    let scene = plane_scene();
    let pos = DVec3::new(-0.4, 3.0, 0.2);
    let axis = DVec3::new(0.3, -1.0, 0.1).normalize();
    let (inner, outer) = (20f64.to_radians(), 35f64.to_radians());
    let light = Light::spot(
        pos.as_vec3(),
        axis.as_vec3(),
        Vec3::ONE,
        inner as f32,
        outer as f32,
    )
    .with_attenuation(Attenuation::Linear {
        near: 3.0,
        far: 6.0,
    });
    let got = samples(&scene, &settings(vec![light], Shading::Phong), &top_view());
    let cone = |p: DVec3| spot_factor((p - pos).normalize().dot(axis), inner, outer);
    check("spot", &got, |p| {
        let (c, d) = ndl(p, pos);
        f64::from(KD) * c * ((6.0 - d) / 3.0).clamp(0.0, 1.0) * cone(p)
    });
    let count = |f: &dyn Fn(f64) -> bool| got.iter().filter(|(p, _)| f(cone(p.as_dvec3()))).count();
    let inside = count(&|s| s >= 1.0);
    let edge = count(&|s| s > 0.0 && s < 1.0);
    let outside = count(&|s| s <= 0.0);
    assert!(
        inside > 50 && edge > 100 && outside > 100,
        "{inside} {edge} {outside}"
    );
}

#[test]
fn rectangular_spot_lights_its_pyramid_and_projects_its_image() {
    let scene = plane_scene();
    // 4 units up, looking down, image up = -Z (so right = +X): on the plane the pyramid is
    // |x| <= 2, |z| <= 1.
    let (tx, tz) = (0.5f32, 0.25f32);
    let plain = Light::rect(
        Vec3::new(0.0, 4.0, 0.0),
        -Vec3::Y,
        -Vec3::Z,
        Vec2::new(libm::atanf(tx), libm::atanf(tz)),
        Vec3::ONE,
    );
    let got = samples(
        &scene,
        &settings(vec![plain.clone()], Shading::Phong),
        &top_view(),
    );
    // Half a pixel (0.027 units) of margin around the pyramid's edge.
    let near_edge = |p: DVec3| (p.x.abs() - 2.0).abs() < 0.04 || (p.z.abs() - 1.0).abs() < 0.04;
    let interior: Vec<_> = got
        .iter()
        .copied()
        .filter(|(p, _)| !near_edge(p.as_dvec3()))
        .collect();
    check("rect", &interior, |p| {
        if p.x.abs() <= 2.0 && p.z.abs() <= 1.0 {
            let (c, _) = ndl(p, DVec3::new(0.0, 4.0, 0.0));
            f64::from(KD) * c
        } else {
            0.0
        }
    });
    // A 2 x 2 slide: red top-left, green top-right, blue bottom-left, white bottom-right.
    let px = vec![
        [255, 0, 0, 255],
        [0, 255, 0, 255],
        [0, 0, 255, 255],
        [255, 255, 255, 255],
    ];
    let slide = realist::texture::Texture::new("slide", 2, 2, px, true).unwrap();
    let projector = plain.with_image(Arc::new(slide));
    let got = samples(
        &scene,
        &settings(vec![projector], Shading::Phong),
        &top_view(),
    );
    let mut seen = [0; 4];
    for (p, c) in got {
        // Away from the edges, and outside the texel centres (u, v beyond 1/4 from the
        // middle), where the bilinear filter blends neighbouring texels.
        let (ax, az) = (p.x.abs(), p.z.abs());
        if !(1.1..1.9).contains(&ax) || !(0.55..0.95).contains(&az) {
            continue;
        }
        let want = match (p.x < 0.0, p.z < 0.0) {
            (true, true) => (Vec3::X, 0),
            (false, true) => (Vec3::Y, 1),
            (true, false) => (Vec3::Z, 2),
            (false, false) => (Vec3::ONE, 3),
        };
        let lit = c.truncate() / c.truncate().max_element().max(1e-6);
        assert!(
            (lit - want.0).abs().max_element() < 0.02,
            "slide at {p}: {c} want {}",
            want.0
        );
        seen[want.1] += 1;
    }
    assert!(seen.iter().all(|&n| n >= 6), "{seen:?}");
}

#[test]
fn fog_blends_with_both_distance_kinds_per_pixel_and_per_vertex() {
    let scene = plane_scene();
    let view = View {
        camera: Camera {
            name: "oblique".into(),
            eye: Vec3::new(0.0, 2.0, 4.5),
            target: Vec3::new(0.0, 0.0, -2.0),
            up: Vec3::Y,
            yfov: 50f32.to_radians(),
            near: 0.1,
            far: 50.0,
            ..Camera::default()
        },
        width: SIZE,
        height: SIZE,
    };
    let eye = view.camera.eye.as_dvec3();
    let forward = view.camera.forward().as_dvec3();
    let lights = vec![Light::ambient(Vec3::ONE)];
    // Fog off: the plane's albedo everywhere.
    let off = samples(&scene, &settings(lights.clone(), Shading::Phong), &view);
    check("fog off", &off, |_| f64::from(KD));
    for distance in [FogDistance::Euclidean, FogDistance::Depth] {
        let fog = Fog {
            color: Vec3::new(1.0, 0.2, 0.2),
            near: 3.0,
            far: 9.0,
            distance,
        };
        let d = move |p: DVec3| match distance {
            FogDistance::Euclidean => (p - eye).length(),
            FogDistance::Depth => (p - eye).dot(forward),
        };
        let f = move |p: DVec3| ((d(p) - 3.0) / 6.0).clamp(0.0, 1.0);
        let kd = f64::from(KD);
        let mut s = settings(lights.clone(), Shading::Phong);
        s.fog = Some(fog);
        let got = samples(&scene, &s, &view);
        check(&format!("fog {} phong", distance.name()), &got, |p| {
            kd + f(p) * (1.0 - kd)
        });
        // The green channel goes towards 0.2.
        for (p, c) in &got {
            let want = kd + f(p.as_dvec3()) * (0.2 - kd);
            assert!((f64::from(c.y) - want).abs() < TOL, "green at {p}");
        }
        // Gouraud fogs the vertices and interpolates: close on this fine grid, exact where
        // f is linear across a triangle (never off by more than the curvature of f over a
        // cell of 1/8 unit).
        s.shading = Some(Shading::Gouraud);
        let got = samples(&scene, &s, &view);
        let worst = got
            .iter()
            .map(|(p, c)| (f64::from(c.x) - (kd + f(p.as_dvec3()) * (1.0 - kd))).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 0.01,
            "gouraud fog {}: worst {worst}",
            distance.name()
        );
    }
    // The two kinds differ off the view axis.
    let mut a = settings(lights.clone(), Shading::Phong);
    a.fog = Some(Fog {
        color: Vec3::new(1.0, 0.2, 0.2),
        near: 3.0,
        far: 9.0,
        distance: FogDistance::Euclidean,
    });
    let mut b = a.clone();
    b.fog = a.fog.map(|f| Fog {
        distance: FogDistance::Depth,
        ..f
    });
    let (ga, gb) = (samples(&scene, &a, &view), samples(&scene, &b, &view));
    let differ = ga
        .iter()
        .zip(&gb)
        .filter(|(x, y)| (x.1 - y.1).abs().max_element() > 0.01)
        .count();
    assert!(
        differ > 100,
        "euclidean and depth fog differ at {differ} samples"
    );
}

/// A horizontal square of half-size `h` at height `y`.
fn square(h: f32, y: f32) -> (Mesh, Mat4) {
    let mut m = Mesh::grid(h, h, 1, 1).unwrap();
    m.name = "square".into();
    (m, Mat4::from_translation(Vec3::new(0.0, y, 0.0)))
}

#[test]
fn alpha_blend_and_mask() {
    let blue = Material {
        base_color: Vec4::new(0.1, 0.2, 0.9, 1.0),
        ..matte(0.0)
    };
    let red = |alpha: f32, mode: AlphaMode| Material {
        base_color: Vec4::new(0.9, 0.1, 0.1, alpha),
        alpha_mode: mode,
        ..matte(0.0)
    };
    let cases = [
        // t = 1 - alpha of the front surface: I = t I_b + (1 - t) I_a.
        (0.25, AlphaMode::Blend, Some(0.25)),
        (0.8, AlphaMode::Blend, Some(0.8)),
        (0.4, AlphaMode::Mask(0.5), None),
        (0.6, AlphaMode::Mask(0.5), Some(1.0)),
    ];
    for (alpha, mode, shown) in cases {
        let mut scene = Scene::default();
        place(
            &mut scene,
            Mesh::grid(4.0, 4.0, 4, 4).unwrap(),
            blue.clone(),
            Mat4::IDENTITY,
        );
        let (m, w) = square(1.0, 0.5);
        place(&mut scene, m, red(alpha, mode), w);
        let got = samples(
            &scene,
            &settings(vec![Light::ambient(Vec3::ONE)], Shading::Phong),
            &top_view(),
        );
        let mut front = 0;
        for (p, c) in got {
            if p.y > 0.25 {
                front += 1;
            }
            // Pixels well inside the square's image (it is 0.5 units nearer the camera).
            let s = 6.0 / 5.5;
            if p.x.abs() > 0.9 * s || p.z.abs() > 0.9 * s {
                continue;
            }
            let (ia, ib) = (Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.2, 0.9));
            let want = match shown {
                None => ib,
                Some(a) => ia * a + ib * (1.0 - a),
            };
            assert!(
                (c.truncate() - want).abs().max_element() < 2e-3,
                "{mode:?} alpha {alpha}: {c} want {want} at {p}"
            );
        }
        // A blended or discarded square writes no depth: the plane is what the depth
        // buffer shows; a kept masked square does.
        assert_eq!(front > 0, shown == Some(1.0), "{mode:?} alpha {alpha}");
    }
}

#[test]
fn two_sided_lighting_lights_the_side_that_is_seen() {
    let scene = plane_scene();
    let below = View {
        camera: Camera {
            eye: Vec3::new(0.0, -6.0, 0.0),
            up: Vec3::Z,
            ..top_view().camera
        },
        ..top_view()
    };
    let from_below = Light::directional(Vec3::Y, Vec3::ONE);
    let from_above = Light::directional(-Vec3::Y, Vec3::ONE);
    for mode in [Shading::Phong, Shading::Gouraud, Shading::Flat] {
        // One-sided: the back face is culled, nothing is seen.
        let s = settings(vec![from_below.clone()], mode);
        assert!(samples(&scene, &s, &below).is_empty(), "{mode}");
        // Two-sided: the underside is lit by the light below, not by the light above.
        let mut s = settings(vec![from_below.clone()], mode);
        s.double_sided = true;
        check(
            &format!("two-sided {mode}"),
            &samples(&scene, &s, &below),
            |_| f64::from(KD),
        );
        let mut s = settings(vec![from_above.clone()], mode);
        s.double_sided = true;
        check(
            &format!("two-sided {mode} lit behind"),
            &samples(&scene, &s, &below),
            |_| 0.0,
        );
    }
}

/// Shadow coverage of a horizontal square occluder of half-size 0.5 at height 1 on the
/// plane, against the analytic outline: `shadowed(p)` says whether plane point `p` is in
/// the exact shadow. Pixels farther than `margin` from the outline must agree exactly; the
/// shadowed area must match within the band the margin allows.
fn check_shadow(
    what: &str,
    light: Light,
    shadowed: impl Fn(DVec3) -> bool,
    lit: impl Fn(DVec3) -> bool,
    margin: f64,
) {
    let mut scene = plane_scene();
    let (m, w) = square(0.5, 1.0);
    place(&mut scene, m, matte(KD), w);
    let mut s = settings(vec![light.with_shadow(true)], Shading::Phong);
    s.double_sided = true;
    let view = View {
        width: 256,
        height: 256,
        ..top_view()
    };
    let prepared = PreparedScene::new(scene);
    let mut r = Renderer::new();
    let report = r.render(&prepared, &s, &view).clone();
    assert_eq!(report.stats.shadow_maps, 1, "{what}");
    let target = r.target().unwrap();
    let (mut agree, mut band, mut dark, mut want_dark) = (0, 0, 0, 0);
    // The exact outline, sampled finely, for the distance test.
    let pixel = 2.0 * 6.0 * (libm::tan(30f64.to_radians())) / 256.0;
    for y in 0..256 {
        for x in 0..256 {
            let Some(p) = r.pick(x, y) else { continue };
            if p.y > 0.5 {
                continue; // the occluder itself
            }
            let p = p.as_dvec3();
            if !lit(p) {
                continue; // outside the light's reach
            }
            let c = f64::from(target.pixel(x, y).unwrap().0.x);
            let is_dark = c < 0.02;
            let want = shadowed(p);
            // Distance to the outline: does the classification change within `margin`?
            let near = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)]
                .iter()
                .any(|(dx, dz)| shadowed(p + DVec3::new(dx * margin, 0.0, dz * margin)) != want);
            if near {
                band += 1;
                continue;
            }
            assert_eq!(is_dark, want, "{what}: at {p} value {c}");
            agree += 1;
            dark += usize::from(is_dark);
            want_dark += usize::from(want);
        }
    }
    assert!(
        want_dark > 200,
        "{what}: the shadow covers only {want_dark} pixels"
    );
    assert!(
        agree > 20000,
        "{what}: {agree} pixels compared, {band} in the band"
    );
    eprintln!("{what}: {agree} pixels agree ({dark} in shadow), {band} within {margin} of the outline (pixel {pixel:.3})");
}

#[test]
fn directional_shadow_matches_the_analytic_outline() {
    // Light travelling along (1, -1, 0.3): the shadow is the square moved by (1, 0, 0.3).
    let dir = DVec3::new(1.0, -1.0, 0.3);
    let light = Light::directional(dir.as_vec3(), Vec3::ONE);
    let shadowed = move |p: DVec3| {
        // Back along the ray to y = 1.
        let q = p - dir * (1.0 / -dir.y);
        q.x.abs() <= 0.5 && q.z.abs() <= 0.5
    };
    // Shadow map texel 0.011 units, PCF over 3 texels, one screen pixel of 0.027.
    check_shadow("directional", light, shadowed, |_| true, 0.06);
}

#[test]
fn spot_shadow_matches_the_analytic_outline() {
    let pos = DVec3::new(1.5, 4.0, -0.5);
    let axis = DVec3::new(-0.3, -1.0, 0.1).normalize();
    let (inner, outer) = (50f64.to_radians(), 60f64.to_radians());
    let light = Light::spot(
        pos.as_vec3(),
        axis.as_vec3(),
        Vec3::ONE,
        inner as f32,
        outer as f32,
    );
    let in_hotspot = move |p: DVec3| (p - pos).normalize().dot(axis) > libm::cos(inner);
    let shadowed = move |p: DVec3| {
        // The ray from p to the light crosses y = 1 inside the square.
        let t = (1.0 - p.y) / (pos.y - p.y);
        let q = p + (pos - p) * t;
        q.x.abs() <= 0.5 && q.z.abs() <= 0.5
    };
    // Texels of about 0.02 units at the plane (a 124 degree cone over 1024 texels).
    check_shadow("spot", light, shadowed, in_hotspot, 0.08);
}

#[test]
fn shadows_off_cost_nothing_and_change_nothing_where_nothing_occludes() {
    let scene = plane_scene();
    let light = Light::directional(Vec3::new(0.2, -1.0, 0.1), Vec3::ONE);
    let prepared = PreparedScene::new(scene);
    let mut r = Renderer::new();
    let off = settings(vec![light.clone()], Shading::Phong);
    assert_eq!(r.render(&prepared, &off, &top_view()).stats.shadow_maps, 0);
    let a = r.take_target().unwrap().resolve();
    let on = settings(vec![light.with_shadow(true)], Shading::Phong);
    assert_eq!(r.render(&prepared, &on, &top_view()).stats.shadow_maps, 1);
    let b = r.take_target().unwrap().resolve();
    // A lone plane shadows nothing: no acne anywhere (the slope-scaled bias at work).
    let worst = a
        .color
        .iter()
        .zip(&b.color)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .fold(0f32, f32::max);
    assert!(
        worst < 1e-6,
        "shadow map changed an unoccluded plane by {worst}"
    );
}

#[test]
fn lights_that_cannot_reach_an_object_are_skipped_and_counted() {
    let mut scene = plane_scene();
    let (m, w) = square(0.5, 1.0);
    place(&mut scene, m, matte(KD), w);
    // A spot far off to the side aiming away, and a short-range point light far away.
    let lights = vec![
        Light::spot(Vec3::new(30.0, 1.0, 0.0), Vec3::X, Vec3::ONE, 0.2, 0.3),
        Light::point(Vec3::new(0.0, 1.0, 40.0), Vec3::ONE).with_attenuation(Attenuation::Linear {
            near: 1.0,
            far: 5.0,
        }),
        Light::ambient(Vec3::splat(0.3)),
    ];
    let prepared = PreparedScene::new(scene.clone());
    let mut r = Renderer::new();
    let stats = r
        .render(&prepared, &settings(lights, Shading::Phong), &top_view())
        .stats;
    // Two objects, two unreachable lights each.
    assert_eq!(stats.lights_skipped, 4);
    let got = samples(
        &scene,
        &settings(vec![Light::ambient(Vec3::splat(0.3))], Shading::Phong),
        &top_view(),
    );
    check("skipped lights add nothing", &got, |_| 0.3 * f64::from(KD));
}

/// The shared teapot under every light type with attenuation and Euclidean fog, drawn in
/// Phong by the renderer (4 x 4 supersampled) and by the f64 reference of `quality::general`
/// at the same sample positions: only the arithmetic differs. Needs `REALIST_SHARED`.
#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn shared_model_under_every_light_type_and_fog_agrees_with_the_f64_reference() {
    use realist::quality::{compare, general, LinearImage};
    use realist::render::{default_camera, render, Shot};
    let dir = realist_testkit::shared("the shared-model reference test");
    let path = dir.join("models/obj/teapot.obj");
    let scene = realist::load::load(&path, &realist::load::LoadOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (lo, hi) = scene.bounds().expect("bounds");
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    let lights = vec![
        Light::ambient(Vec3::splat(0.05)),
        Light::spot(
            c + Vec3::new(0.6, 1.4, 0.9) * r,
            -Vec3::new(0.6, 1.4, 0.9),
            Vec3::new(1.0, 0.9, 0.8),
            12f32.to_radians(),
            24f32.to_radians(),
        )
        .with_attenuation(Attenuation::Linear {
            near: 1.2 * r,
            far: 3.0 * r,
        }),
        Light::point(c + Vec3::new(-1.5, 0.5, 1.0) * r, Vec3::new(0.3, 0.4, 0.9))
            .with_intensity(4.0 * r * r)
            .with_attenuation(Attenuation::InverseSquare),
        Light::rect(
            c + Vec3::new(0.0, 0.3, 2.0) * r,
            -Vec3::new(0.0, 0.3, 2.0),
            Vec3::Y,
            Vec2::new(0.35, 0.2),
            Vec3::new(0.5, 0.8, 0.4),
        )
        .with_intensity(4.0 * r * r)
        .with_attenuation(Attenuation::Range(3.0 * r)),
    ];
    let (w, h, ss) = (160, 120, 4);
    let camera = default_camera(&scene, w as f32 / h as f32);
    let fog = Fog {
        color: Vec3::new(0.5, 0.55, 0.6),
        near: (camera.eye - c).length() - 0.5 * r,
        far: (camera.eye - c).length() + 1.5 * r,
        distance: FogDistance::Euclidean,
    };
    let opts = Shot {
        width: w,
        height: h,
        camera: Some(camera),
        settings: Settings {
            shading: Some(Shading::Phong),
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            lights: Lights::Custom {
                lights,
                follow_camera: false,
            },
            fog: Some(fog),
            ..Settings::default()
        },
    };
    let big = Shot {
        width: w * ss,
        height: h * ss,
        ..opts.clone()
    };
    let frame = render(&PreparedScene::new(scene.clone()), &big);
    let ras = LinearImage::from_framebuffer(&frame.image()).downsample(ss);
    let reference = general::reference(&scene, &opts, ss, false).expect("reference");
    let same = compare(&ras, &reference, 1.0);
    let unfogged = Shot {
        settings: Settings {
            fog: None,
            ..opts.clone().settings
        },
        ..opts.clone()
    };
    let no_fog = compare(
        &ras,
        &general::reference(&scene, &unfogged, ss, false).unwrap(),
        1.0,
    );
    let blinn = compare(
        &ras,
        &general::reference(&scene, &opts, ss, true).unwrap(),
        1.0,
    );
    eprintln!("teapot, every light and fog: {same:?}\nwithout fog: {no_fog:?}\nBlinn: {blinn:?}");
    // As the demo scene in quality::general: f32 against f64, and samples within 1e-3
    // pixel of a silhouette that vertex snapping moves across.
    assert!(
        same.mean_de2000 < 2e-3 && same.over_threshold < 30,
        "{same:?}"
    );
    // Measured mean 3e-4, 2 pixels above 1. Teeth: the reference without the fog
    // (measured 0.56), or with Blinn highlights (0.13), or without any one light (0.55 to
    // 1.6).
    assert!(no_fog.mean_de2000 > 0.25, "{no_fog:?}");
    assert!(blinn.mean_de2000 > 0.05, "{blinn:?}");
    // Every light shows: the reference without it differs.
    let Lights::Custom { lights, .. } = &opts.settings.lights else {
        unreachable!()
    };
    for k in 1..lights.len() {
        let mut fewer = lights.clone();
        let gone = fewer.remove(k);
        let without = Shot {
            settings: Settings {
                lights: Lights::Custom {
                    lights: fewer,
                    follow_camera: false,
                },
                ..opts.clone().settings
            },
            ..opts.clone()
        };
        let m = compare(
            &ras,
            &general::reference(&scene, &without, ss, false).unwrap(),
            1.0,
        );
        eprintln!("without the {:?} light: {m:?}", gone.kind);
        assert!(
            m.mean_de2000 > 0.2,
            "without the {:?} light: {m:?}",
            gone.kind
        );
    }
}

/// Gouraud and flat shading with the textbook's formulas (Phong's `R·V` at the vertices,
/// flat facets lit at their centroids) and with OpenGL's (`VertexLighting::GL`: Blinn's
/// `N·H`, each triangle lit at its last vertex), against those formulas evaluated here in
/// f64: a shiny plane of eight triangles under a near point light, seen from the top (so the
/// interpolation in screen space is affine in the plane).
#[test]
fn vertex_lighting_follows_the_textbook_or_the_gl_formulas() {
    use realist::mesh::{MeshData, NormalPolicy};
    use realist::render::VertexLighting;
    let (kd, ks, shininess) = (0.3f64, 0.5f64, 8.0f64);
    let light = DVec3::new(0.6, 1.2, -0.5);
    let eye = DVec3::new(0.0, 6.0, 0.0);
    // A 2 x 2 grid of quads over [-2, 2]^2, each cut into two triangles facing +Y.
    let at = |i: u32, j: u32| Vec3::new(-2.0 + 2.0 * i as f32, 0.0, -2.0 + 2.0 * j as f32);
    let mut positions = Vec::new();
    for j in 0..3 {
        for i in 0..3 {
            positions.push(at(i, j));
        }
    }
    let mut corners = Vec::new();
    for j in 0..2 {
        for i in 0..2 {
            let k = |di: u32, dj: u32| (j + dj) * 3 + i + di;
            corners.extend([k(0, 0), k(0, 1), k(1, 0)]);
            corners.extend([k(1, 1), k(1, 0), k(0, 1)]);
        }
    }
    let mesh = Mesh::new(
        MeshData {
            name: "plane".into(),
            positions: positions.clone(),
            corners: corners.clone(),
            ..MeshData::default()
        },
        NormalPolicy::default(),
    )
    .expect("mesh");
    let mut scene = Scene::default();
    let material = Material {
        name: "shiny".into(),
        base_color: Vec4::new(kd as f32, kd as f32, kd as f32, 1.0),
        specular: Vec3::splat(ks as f32),
        shininess: shininess as f32,
        ambient: Vec3::ONE,
        ..Material::default()
    };
    place(&mut scene, mesh, material, Mat4::IDENTITY);

    // The lighting equation at `q` with normal +Y.
    let lighting = |q: DVec3, blinn: bool| {
        let l = (light - q).normalize();
        let v = (eye - q).normalize();
        let ndl = l.y;
        let base = if blinn {
            (l + v).normalize().y
        } else {
            (DVec3::Y * (2.0 * ndl) - l).dot(v)
        };
        let spec = if ndl > 0.0 && base > 0.0 {
            libm::pow(base, shininess)
        } else {
            0.0
        };
        kd * ndl.max(0.0) + ks * spec
    };
    let tris: Vec<[DVec3; 3]> = corners
        .chunks(3)
        .map(|c| [0, 1, 2].map(|k| positions[c[k] as usize].as_dvec3()))
        .collect();
    // The triangle under `p` and its barycentric coordinates, unless `p` is near an edge.
    let locate = |p: DVec3| {
        tris.iter().find_map(|t| {
            let (a, b, c) = (t[0], t[1], t[2]);
            let area = (b.x - a.x) * (c.z - a.z) - (c.x - a.x) * (b.z - a.z);
            let w =
                |u: DVec3, v: DVec3| ((v.x - u.x) * (p.z - u.z) - (p.x - u.x) * (v.z - u.z)) / area;
            let bary = DVec3::new(w(b, c), w(c, a), w(a, b));
            (bary.min_element() > 0.03).then_some((*t, bary))
        })
    };
    let light_list =
        || vec![Light::point(light.as_vec3(), Vec3::ONE).with_attenuation(Attenuation::None)];
    let mut images = Vec::new();
    for (mode, vl) in [
        (Shading::Gouraud, VertexLighting::default()),
        (Shading::Gouraud, VertexLighting::GL),
        (Shading::Flat, VertexLighting::default()),
        (Shading::Flat, VertexLighting::GL),
    ] {
        let s = Settings {
            vertex_lighting: vl,
            ..settings(light_list(), mode)
        };
        let got = samples(&scene, &s, &top_view());
        let mut checked = 0;
        let mut worst = 0f64;
        for &(p, c) in &got {
            let Some((t, bary)) = locate(p.as_dvec3()) else {
                continue;
            };
            let want = match mode {
                Shading::Gouraud => {
                    bary.x * lighting(t[0], vl.blinn)
                        + bary.y * lighting(t[1], vl.blinn)
                        + bary.z * lighting(t[2], vl.blinn)
                }
                _ if vl.provoking_vertex => lighting(t[2], true),
                _ => lighting((t[0] + t[1] + t[2]) / 3.0, false),
            };
            let e = (f64::from(c.x) - want).abs();
            worst = worst.max(e);
            assert!(
                e < TOL,
                "{mode} {vl:?}: at {p} got {} want {want} (error {e})",
                c.x
            );
            checked += 1;
        }
        assert!(checked > 200, "{mode} {vl:?}: only {checked} samples");
        eprintln!("{mode} {vl:?}: {checked} samples, worst error {worst:.2e}");
        images.push(got);
    }
    // The two formulas differ visibly on this plane, so each check above tells them apart.
    for (a, b) in [(0, 1), (2, 3)] {
        let most = images[a]
            .iter()
            .zip(&images[b])
            .map(|(x, y)| (x.1.x - y.1.x).abs())
            .fold(0f32, f32::max);
        assert!(most > 0.05, "textbook and GL images differ by only {most}");
    }
}
