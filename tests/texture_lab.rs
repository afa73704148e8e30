//! The texture-mapping experiments (the textbook's §9.5) measured against the f64 reference:
//! bump mapping from a height image and from solid noise on a plane under a grazing light,
//! procedural solid textures on a sphere, and the texture debug views against the level of
//! detail, texel density and anisotropy worked out from the camera by hand.

mod common;

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

use realist::mesh::Mesh;
use realist::quality::{compare, general, LinearImage};
use realist::render::{render, Lights, PreparedScene, Settings, Shot};
use realist::scene::{
    Camera, Light, Material, Scene, Slot, SlotOverride, SlotOverrides, TextureSource,
};
use realist::shade::texlab::{footprint_axes, level_colour, ramp};
use realist::shade::Shading;
use realist::texture::{Procedural, ProceduralTexture, Texels, Texture};

/// Supersampling of both the renders (drawn this many times larger and averaged) and the
/// reference (samples per pixel per axis).
const SS: u32 = 4;

/// Mean ΔE00 the bump-mapped renders keep from the reference: what remains is the edge
/// antialiasing of the two samplings and f32 rounding.
const BUMP_MEAN_DE: f64 = 0.5;

/// The mean ΔE00 a map must make, against an agreement of `same`, to count as shown: 10
/// times the disagreement and at least 1 (a visible difference).
fn visible(same: f64) -> f64 {
    (10.0 * same).max(1.0)
}

/// A matte white plane (2 x 2, facing +Y, UVs 0..1) under one grazing directional light
/// (10° above the horizon) and a dim ambient.
fn plane_scene() -> Scene {
    let mesh = Mesh::grid(1.0, 1.0, 4, 4).expect("grid");
    let mut scene = common::scene_of(
        mesh,
        Material {
            base_color: Vec4::ONE,
            specular: Vec3::ZERO,
            ambient: Vec3::ONE,
            ..Material::default()
        },
    );
    let elevation = 10f32.to_radians();
    let travel = -Vec3::new(
        libm::cosf(elevation) * 0.8,
        libm::sinf(elevation),
        libm::cosf(elevation) * 0.6,
    );
    scene.lights = vec![
        Light::directional(travel.normalize(), Vec3::ONE),
        Light::ambient(Vec3::splat(0.05)),
    ];
    scene
}

/// A 64 x 64 height image: smooth round bumps, 4 per side (16-bit linear).
fn bumps() -> Arc<Texture> {
    let n = 64u32;
    let texels = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f32 + 0.5, (i / n) as f32 + 0.5);
            let k = std::f32::consts::TAU * 4.0 / n as f32;
            let h = 0.5 + 0.5 * libm::sinf(k * x) * libm::sinf(k * y);
            let v = (h * 65535.0).round() as u16;
            [v, v, v, u16::MAX]
        })
        .collect();
    Arc::new(Texture::from_texels("bumps", n, n, Texels::Linear16(texels)).expect("texture"))
}

fn options(slots: SlotOverrides, shading: Shading, w: u32, h: u32) -> Shot {
    Shot {
        width: w,
        height: h,
        camera: Some(Camera {
            eye: Vec3::new(0.0, 1.6, 1.9),
            target: Vec3::new(0.0, 0.0, 0.1),
            near: 0.1,
            far: 20.0,
            ..Camera::default()
        }),
        settings: Settings {
            shading: Some(shading),
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            slots,
            lights: Lights::Auto,
            ..Settings::default()
        },
    }
}

/// The renderer's image at `SS` x the size, averaged down, in linear light.
fn rendered(scene: &Scene, opts: &Shot) -> LinearImage {
    let big = Shot {
        width: opts.width * SS,
        height: opts.height * SS,
        ..opts.clone()
    };
    let frame = render(&PreparedScene::new(scene.clone()), &big);
    LinearImage::from_framebuffer(&frame.image()).downsample(SS)
}

fn bump_slots(source: TextureSource, scale: f32) -> SlotOverrides {
    let mut slots = SlotOverrides::default();
    slots.set(Slot::Bump, Some(SlotOverride::source(source, scale)));
    slots
}

/// Renders `slots` on the plane and checks it against the reference within
/// [`BUMP_MEAN_DE`], and that the bump changed the image well beyond that (so the
/// agreement is not that of two flat planes).
fn bump_agrees(what: &str, slots: SlotOverrides) {
    let scene = plane_scene();
    let (w, h) = (96, 72);
    let opts = options(slots, Shading::Textured, w, h);
    let ras = rendered(&scene, &opts);
    let reference = general::reference(&scene, &opts, SS, true).expect("reference");
    let same = compare(&ras, &reference, 1.0);
    let flat = options(SlotOverrides::default(), Shading::Textured, w, h);
    let flat = compare(&rendered(&scene, &flat), &reference, 1.0);
    agrees_and_shows(what, "the reference", &same, "without the bump", &flat);
}

/// Asserts that an image agrees with `against` within [`BUMP_MEAN_DE`] (`same`) and that
/// what it shows changes the image well beyond that (`shown`: against the image without it).
fn agrees_and_shows(
    what: &str,
    against: &str,
    same: &realist::quality::Metrics,
    without: &str,
    shown: &realist::quality::Metrics,
) {
    eprintln!(
        "{what}: mean ΔE00 {:.3} (p95 {:.3}) against {against}, {:.2} {without}",
        same.mean_de2000, same.p95_de2000, shown.mean_de2000
    );
    assert!(
        same.mean_de2000 < BUMP_MEAN_DE,
        "{what}: mean ΔE00 {} against {against}",
        same.mean_de2000
    );
    assert!(
        shown.mean_de2000 > visible(same.mean_de2000),
        "{what}: it barely shows (ΔE00 {} {without})",
        shown.mean_de2000
    );
}

#[test]
fn a_bump_image_under_a_grazing_light_agrees_with_the_f64_reference() {
    bump_agrees(
        "height image",
        bump_slots(TextureSource::Image(bumps()), 1.5),
    );
}

#[test]
fn solid_noise_bumps_under_a_grazing_light_agree_with_the_f64_reference() {
    let (noise, scale) =
        TextureSource::bump_from_spec("noise:0.1", |_, _| Err::<Arc<Texture>, _>("no image"))
            .expect("noise");
    assert_eq!(scale, 0.1);
    bump_agrees("solid noise", bump_slots(noise, scale));
}

/// The glTF normal-map test planes (`models/texture/normal-plane.glb`: tangent-space bumps
/// with the normal scale 1 and 0.5, the file's MikkTSpace tangents) under the same grazing
/// light, against the reference, which perturbs the normal with the same texels in f64.
#[test]
fn normal_maps_under_a_grazing_light_agree_with_the_f64_reference() {
    normal_planes_agree("normal maps", false);
}

/// The same planes with their tangents taken away (as an OBJ, or an image put in the
/// normal slot of a mesh that has none): the frame comes from the screen-space derivatives
/// of position and UV (the reference: from each triangle's edges), and the image is the
/// one the file's MikkTSpace tangents give.
#[test]
fn normal_maps_on_a_mesh_without_tangents_take_their_frame_from_the_uvs() {
    let with = normal_planes_agree("normal maps without tangents", true);
    let (scene, opts) = normal_planes(false);
    let same = compare(&with, &rendered(&scene, &opts), 1.0);
    eprintln!(
        "normal maps without tangents: mean ΔE00 {:.3} (p95 {:.3}) against the file's tangents",
        same.mean_de2000, same.p95_de2000
    );
    assert!(
        same.mean_de2000 < BUMP_MEAN_DE,
        "mean ΔE00 {}",
        same.mean_de2000
    );
}

/// `models/texture/normal-plane.glb` (tangent-space bumps with the normal scale 1 and 0.5,
/// the file's MikkTSpace tangents, or none if `strip`), matte, under a light 10° above
/// the planes, and the options that render it.
fn normal_planes(strip: bool) -> (Scene, Shot) {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/texture/normal-plane.glb");
    let mut scene = realist::load::load(&path, &realist::load::LoadOptions::default())
        .expect("normal-plane.glb");
    for m in &mut scene.materials {
        m.specular = Vec3::ZERO;
        m.ambient = Vec3::ONE;
    }
    if strip {
        for m in &mut scene.meshes {
            assert!(m.tangents.is_some(), "the file has tangents");
            m.tangents = None;
        }
    }
    let elevation = 10f32.to_radians();
    // The planes face +Z: the light skims them from the upper right.
    let travel = -Vec3::new(
        libm::cosf(elevation) * 0.8,
        libm::cosf(elevation) * 0.6,
        libm::sinf(elevation),
    );
    scene.lights = vec![
        Light::directional(travel.normalize(), Vec3::ONE),
        Light::ambient(Vec3::splat(0.05)),
    ];
    let opts = Shot {
        camera: None,
        ..options(SlotOverrides::default(), Shading::Textured, 128, 64)
    };
    (scene, opts)
}

/// The normal-map planes ([`normal_planes`]) against the f64 reference, which perturbs the
/// normal with the same texels in f64; the normal maps must show. Returns the render.
fn normal_planes_agree(what: &str, strip: bool) -> LinearImage {
    let (scene, opts) = normal_planes(strip);
    let ras = rendered(&scene, &opts);
    let reference = general::reference(&scene, &opts, SS, true).expect("reference");
    let same = compare(&ras, &reference, 1.0);
    let mut off = SlotOverrides::default();
    off.set(Slot::Normal, Some(SlotOverride::Off));
    let without = Shot {
        settings: Settings {
            slots: off,
            ..opts.clone().settings
        },
        ..opts.clone()
    };
    let flat = compare(&rendered(&scene, &without), &reference, 1.0);
    agrees_and_shows(what, "the reference", &same, "without them", &flat);
    ras
}

/// Solid wood and marble on a sphere (no UVs needed) against the reference, which evaluates
/// the same procedural at every sample point.
#[test]
fn solid_textures_on_a_sphere_agree_with_the_f64_reference() {
    let mut mesh = Mesh::sphere(1.0, 48, 24).expect("sphere");
    mesh.uvs.clear();
    let scene = common::scene_of(
        mesh,
        Material {
            base_color: Vec4::ONE,
            specular: Vec3::splat(0.2),
            ..Material::default()
        },
    );
    for name in ["wood", "marble"] {
        let p: Procedural = name.parse().expect("procedural");
        let mut slots = SlotOverrides::default();
        slots.set(
            Slot::BaseColor,
            Some(SlotOverride::source(
                TextureSource::Procedural(Arc::new(ProceduralTexture::new(p))),
                1.0,
            )),
        );
        let opts = Shot {
            camera: None,
            ..options(slots, Shading::Textured, 80, 60)
        };
        let ras = rendered(&scene, &opts);
        let reference = general::reference(&scene, &opts, SS, true).expect("reference");
        let m = compare(&ras, &reference, 1.0);
        let plain = compare(
            &rendered(
                &scene,
                &options(SlotOverrides::default(), Shading::Blinn, 80, 60),
            ),
            &reference,
            1.0,
        );
        eprintln!(
            "{name}: mean ΔE00 {:.3} (p95 {:.3}); untextured {:.2}",
            m.mean_de2000, m.p95_de2000, plain.mean_de2000
        );
        assert!(m.mean_de2000 < 1.0, "{name}: mean ΔE00 {}", m.mean_de2000);
        assert!(plain.mean_de2000 > 4.0, "{name}: the texture barely shows");
    }
}

/// A face-on square of `side` pixels showing a `texels`-wide image through an orthographic
/// camera: every pixel spans `texels / side` texels on both axes.
fn face_on(side: u32, texels: u32, shading: Shading) -> (Vec4, Vec4) {
    let data = vec![[128u8, 128, 128, 255]; (texels * texels) as usize];
    let image = Arc::new(Texture::new("flat", texels, texels, data, true).expect("texture"));
    let mesh = Mesh::grid(1.0, 1.0, 1, 1).expect("grid");
    let scene = common::scene_of(mesh, Material::default());
    let mut slots = SlotOverrides::default();
    slots.set(
        Slot::BaseColor,
        Some(SlotOverride::source(TextureSource::Image(image), 1.0)),
    );
    let opts = Shot {
        width: side * 2,
        height: side * 2,
        camera: Some(Camera {
            eye: Vec3::new(0.0, 5.0, 0.0),
            target: Vec3::ZERO,
            up: Vec3::NEG_Z,
            ortho: Some(2.0),
            near: 0.1,
            far: 20.0,
            ..Camera::default()
        }),
        settings: Settings {
            shading: Some(shading),
            slots,
            ..Settings::default()
        },
    };
    let fb = render(&PreparedScene::new(scene), &opts).image();
    let at = |x: u32, y: u32| fb.color[(y * fb.width + x) as usize];
    // The centre pixel, and one the plane does not cover (its corner is at 1/4 .. 3/4).
    (at(side, side), at(1, 1))
}

fn display(c: Vec3) -> Vec4 {
    let f = |v: f32| realist::texture::srgb_to_linear(v.clamp(0.0, 1.0));
    Vec4::new(f(c.x), f(c.y), f(c.z), 1.0)
}

fn close(a: Vec4, b: Vec4) -> bool {
    (a - b).truncate().abs().max_element() < 2e-3
}

#[test]
fn the_mip_level_view_shows_the_level_the_camera_asks_for() {
    // Ortho half-height 2 on a 2 x 2 plane: the plane is half the frame, `side` pixels.
    for (side, texels, level) in [(64, 256, 2.0), (64, 1024, 4.0), (128, 128, 0.0)] {
        let (centre, outside) = face_on(side, texels, Shading::MipLevel);
        let want = display(level_colour(level));
        assert!(
            close(centre, want),
            "{texels} texels on {side} pixels: {centre} is not level {level}'s {want}"
        );
        assert!(!close(outside, want), "the background is not a mip level");
    }
}

#[test]
fn the_texel_density_and_anisotropy_views_read_the_footprint() {
    let (centre, _) = face_on(64, 512, Shading::TexelDensity);
    // 8 texels per pixel: log2 8 = 3 at the top of the ramp (1/8 .. 8).
    assert!(close(centre, display(ramp(1.0))), "{centre}");
    let (centre, _) = face_on(64, 64, Shading::TexelDensity);
    assert!(
        close(centre, display(ramp(0.5))),
        "1:1 is the ramp's middle: {centre}"
    );
    let (centre, _) = face_on(64, 512, Shading::Anisotropy);
    assert!(
        close(centre, display(ramp(0.5))),
        "face on is isotropic: {centre}"
    );
    // The footprint's axes: a 4:1 stretch along u and a shear keep their singular values.
    let (major, minor) = footprint_axes(Vec2::new(4.0, 0.0), Vec2::new(0.0, 1.0));
    assert!((major - 4.0).abs() < 1e-5 && (minor - 1.0).abs() < 1e-5);
    let r = std::f32::consts::FRAC_PI_6;
    let rot = |v: Vec2| {
        Vec2::new(
            libm::cosf(r) * v.x - libm::sinf(r) * v.y,
            libm::sinf(r) * v.x + libm::cosf(r) * v.y,
        )
    };
    let (major, minor) = footprint_axes(rot(Vec2::new(4.0, 0.0)), rot(Vec2::new(0.0, 1.0)));
    assert!((major - 4.0).abs() < 1e-4 && (minor - 1.0).abs() < 1e-4);
}

/// Without tangents the tangent-normals view takes its frame from the UVs (the screen-space
/// derivatives of the position and of UV set 0): the bumps of a height image on the plane
/// show as they do with MikkTSpace tangents generated for it, not as a flat colour.
#[test]
fn the_tangent_normals_view_takes_its_frame_from_the_uvs_without_tangents() {
    let bare = plane_scene();
    assert!(bare.meshes.iter().all(|m| m.tangents.is_none()));
    let mut with_tangents = bare.clone();
    for m in &mut with_tangents.meshes {
        m.generate_tangents(0).expect("tangents");
    }
    let (w, h) = (96, 72);
    let bumped = options(
        bump_slots(TextureSource::Image(bumps()), 1.0),
        Shading::TangentNormals,
        w,
        h,
    );
    let derived = rendered(&bare, &bumped);
    let generated = rendered(&with_tangents, &bumped);
    let flat = rendered(
        &bare,
        &options(SlotOverrides::default(), Shading::TangentNormals, w, h),
    );
    let same = compare(&derived, &generated, 1.0);
    let shown = compare(&derived, &flat, 1.0);
    agrees_and_shows(
        "tangent-normals without tangents",
        "MikkTSpace tangents",
        &same,
        "against the unbumped view",
        &shown,
    );
}

/// A 64 x 64 height image rising linearly, `du` per texel along u (columns) and `dv` per
/// texel along v (rows), from 0.25 at the first texel (16-bit linear).
fn ramp_height(du: f32, dv: f32) -> Arc<Texture> {
    let n = 64u32;
    let texels = (0..n * n)
        .map(|i| {
            let h = 0.25 + du * (i % n) as f32 + dv * (i / n) as f32;
            let v = (h * 65535.0).round() as u16;
            [v, v, v, u16::MAX]
        })
        .collect();
    Arc::new(Texture::from_texels("ramp", n, n, Texels::Linear16(texels)).expect("texture"))
}

/// Bump mapping against the geometry of a height field, computed here and not by the
/// renderer's functions: on the plane (facing +Y, u along +X, v along +Z), a height image
/// rising `du`, `dv` per texel and scaled by `s` (heights in texel widths: 1 over one
/// texel is 45°) is the surface y = H(x, z) with slopes H_x = s du, H_z = s dv, whose
/// normal is (-H_x, 1, -H_z) normalised: it leans away from where the surface rises. The
/// probe's shading normal must be that normal, and the rasterizer's pixel the Lambert
/// term with it; a wrong sign or scale of the gradient fails both.
#[test]
fn a_height_ramp_tilts_the_normal_as_the_slope_of_its_surface() {
    let (du, dv, s) = (0.004f32, 0.002f32, 10.0f32);
    let want = Vec3::new(-s * du, 1.0, -s * dv).normalize();
    let scene = plane_scene();
    let (w, h) = (96, 72);
    let slots = bump_slots(TextureSource::Image(ramp_height(du, dv)), s);
    let shot = options(slots, Shading::Textured, w, h);
    let prepared = PreparedScene::new(scene.clone());
    let view = shot.view(&scene);
    let (px, py) = (w / 2, h / 2);
    let p = realist::render::probe(&prepared, &shot.settings, &view, px, py).expect("the plane");
    let uv = p.uv.expect("uv");
    assert!(
        (0.2..0.8).contains(&uv.x) && (0.2..0.8).contains(&uv.y),
        "probed inside the plane: {uv}"
    );
    assert!(
        (p.normal - want).length() < 2e-3,
        "shading normal {} against the height field's {want}",
        p.normal
    );
    // The rasterizer's own pixel: ambient 0.05 plus the Lambert term of the light (white,
    // intensity 1) with that normal; without the bump, with the normal (0, 1, 0).
    let l = -match scene.lights[0].kind {
        realist::scene::LightKind::Directional => scene.lights[0].direction.normalize(),
        k => panic!("the plane's first light is directional, not {k:?}"),
    };
    let lit = |n: Vec3| 0.05 + n.dot(l).max(0.0);
    let frame = render(&prepared, &shot).image();
    let got = frame.pixel(px, py).x;
    let (bumped, flat) = (lit(want), lit(Vec3::Y));
    assert!(
        (got - bumped).abs() < 0.01 * bumped,
        "pixel {got}, the height field's normal gives {bumped} (flat {flat})"
    );
    assert!((flat - bumped).abs() > 0.1 * bumped, "the bump shows");
}
