//! Texture slots as glTF defines them, on the files of `models/texture/` (written by
//! independent tools: obj2gltf, gltfpack, glTF-Transform; see `models/README.md` for their
//! exact contents): `KHR_texture_transform` (offset, rotation, scale, the `texCoord`
//! override), a second UV set, gltfpack's quantised UVs brought back by a transform, and
//! tangents generated with MikkTSpace against the file's own.
//!
//! Where a test reads colours off the frame, the scene is lit by an ambient light of 1 on
//! white, non-specular materials, so a pixel is its texel (plus any emitted light).

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2, Vec3, Vec4};

use realist::load::{load, LoadOptions};
use realist::render::{render, Lights, PreparedScene, Settings, Shot};
use realist::scene::{Camera, Light, Scene};
use realist::shade::Shading;

fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models/texture")
        .join(name)
}

fn load_model(name: &str) -> Scene {
    load(&model(name), &LoadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Every material white, matte and not metallic (Phong materials, so the models open
/// textured rather than `pbr`), under one ambient light of 1: the lit colour is the
/// base-colour texel (and what the material emits).
fn unlit(mut scene: Scene) -> (Scene, Lights) {
    for m in &mut scene.materials {
        m.pbr = None;
        m.base_color = Vec4::ONE;
        m.specular = Vec3::ZERO;
        m.ambient = Vec3::ONE;
    }
    let lights = Lights::Custom {
        lights: vec![Light::ambient(Vec3::ONE)],
        follow_camera: false,
    };
    (scene, lights)
}

/// An orthographic camera looking down -Z at the row of quads (x from -4.5 to 4.5).
fn front_camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        ortho: Some(0.75),
        near: 0.1,
        far: 20.0,
        ..Camera::default()
    }
}

/// Pixel coordinates (x right, y down) of world point `p` in a `w` x `h` frame of `camera`.
fn pixel_of(camera: &Camera, w: u32, h: u32, p: Vec3) -> (u32, u32) {
    let vp: Mat4 = camera.projection(w as f32 / h as f32) * camera.view();
    let c = vp.project_point3(p);
    let x = (c.x + 1.0) * 0.5 * w as f32;
    let y = (1.0 - c.y) * 0.5 * h as f32;
    (x as u32, y as u32)
}

/// The affine map of a quad from UV set `set` to the world, as (origin, d/du, d/dv), for a
/// quad whose corners carry the UVs (0,0), (1,0) and (0,1) among others.
fn quad_frame(scene: &Scene, inst: usize, set: usize) -> (Vec3, Vec3, Vec3) {
    let i = &scene.instances[inst];
    let m = &scene.meshes[i.mesh];
    let uvs = &m.uvs[set];
    let corner = |want: Vec2| {
        let (_, &v) = m
            .corners
            .iter()
            .enumerate()
            .find(|&(c, &v)| (uvs.at(c, v) - want).length() < 1e-4)
            .unwrap_or_else(|| panic!("no corner with UV {want}"));
        i.world.transform_point3(m.positions[v as usize])
    };
    let p00 = corner(Vec2::ZERO);
    (p00, corner(Vec2::X) - p00, corner(Vec2::Y) - p00)
}

fn point_at_uv(scene: &Scene, inst: usize, set: usize, uv: Vec2) -> Vec3 {
    let (o, du, dv) = quad_frame(scene, inst, set);
    o + du * uv.x + dv * uv.y
}

/// The UV (of set `set`) of the point of quad `inst` that pixel (x, y)'s centre sees, for a
/// camera looking down -Z at a quad in a plane z = constant.
#[allow(clippy::too_many_arguments)]
fn uv_at_pixel(
    scene: &Scene,
    inst: usize,
    set: usize,
    cam: &Camera,
    w: u32,
    h: u32,
    x: u32,
    y: u32,
) -> Vec2 {
    let vp: Mat4 = cam.projection(w as f32 / h as f32) * cam.view();
    let ndc = Vec3::new(
        (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
        0.5,
    );
    let p = vp.inverse().project_point3(ndc);
    let (o, du, dv) = quad_frame(scene, inst, set);
    // Solve (p - o).xy = u du.xy + v dv.xy.
    let m = glam::Mat2::from_cols(du.truncate(), dv.truncate());
    m.inverse() * (p - o).truncate()
}

/// The worked values of `models/README.md`: for each quad of `transform-quads.glb`, the
/// texel of `uv-grid.png` (256 x 256) that UV (0.3, 0.4) and UV (0.7, 0.85) read.
const TRANSFORM_TEXELS: [(&str, [(u32, u32); 2]); 7] = [
    ("0-none", [(76, 102), (179, 217)]),
    ("1-offset", [(204, 166), (51, 25)]),
    ("2-scale", [(153, 51), (102, 108)]),
    ("3-rotation", [(102, 179), (217, 76)]),
    ("4-readme-example", [(51, 217), (108, 166)]),
    ("5-combined", [(202, 200), (122, 198)]),
    ("6-texcoord-override", [(166, 179), (217, 236)]),
];

#[test]
fn texture_transforms_read_the_texels_the_worked_values_name() {
    let scene = load_model("transform-quads.glb");
    assert!(
        !scene
            .report
            .skipped
            .iter()
            .any(|s| s.contains("KHR_texture_transform")),
        "the extension is supported: {:?}",
        scene.report.skipped
    );
    let grid = scene.textures[0].clone();
    assert_eq!((grid.width, grid.height), (256, 256));
    let (scene, lights) = unlit(scene);
    let (w, h) = (1200, 200);
    let camera = front_camera();
    let opts = Shot {
        width: w,
        height: h,
        camera: Some(camera.clone()),
        settings: Settings {
            lights,
            shading: Some(Shading::Textured),
            ..Settings::default()
        },
    };
    let image = render(&PreparedScene::new(scene.clone()), &opts).image();
    let mut checked = 0;
    for (name, texels) in TRANSFORM_TEXELS {
        let inst = scene
            .instances
            .iter()
            .position(|i| scene.meshes[i.mesh].name == name || i.name == name)
            .unwrap_or_else(|| panic!("no quad {name}"));
        let mesh = &scene.meshes[scene.instances[inst].mesh];
        // The override quad's "usual" UVs are its second set.
        let set = if name.starts_with('6') { 1 } else { 0 };
        assert!(mesh.uvs.len() > set, "{name}: UV sets");
        let slot = scene.materials[mesh.material.expect("a material")]
            .base_color_texture
            .expect("a base-colour texture");
        let texel_of = |uv: Vec2| {
            let t = slot.transform.apply(uv);
            let f = |c: f32| ((c - c.floor()) * 256.0).floor() as u32;
            (f(t.x), f(t.y))
        };
        for (uv, worked) in [Vec2::new(0.3, 0.4), Vec2::new(0.7, 0.85)]
            .into_iter()
            .zip(texels)
        {
            // The loaded transform gives the README's texel...
            assert_eq!(texel_of(uv), worked, "{name} at UV {uv}");
            // ...and the pixel there shows the texel of its own centre's UV.
            let (x, y) = pixel_of(&camera, w, h, point_at_uv(&scene, inst, set, uv));
            let at = uv_at_pixel(&scene, inst, set, &camera, w, h, x, y);
            let (tx, ty) = texel_of(at);
            let got = image.pixel(x, y);
            let want = grid.fetch(tx, ty);
            assert!(
                (got - want).abs().truncate().max_element() < 2e-3,
                "{name} at UV {uv}: pixel ({x}, {y}) (UV {at}) is {got}, texel ({tx}, {ty}) is {want}"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 14);
}

#[test]
fn a_second_uv_set_feeds_the_slot_that_names_it() {
    // Base colour on TEXCOORD_1 = (2 v0, 2 (1 - u0)); emissive on TEXCOORD_0.
    let scene = load_model("multi-uv.glb");
    let m = &scene.materials[0];
    let base = m.base_color_texture.expect("base colour texture");
    let emissive = m.emissive_texture.expect("emissive texture");
    assert_eq!((base.uv_set, emissive.uv_set), (1, 0));
    let grid = scene.textures[base.texture].clone();
    let glow = scene.textures[emissive.texture].clone();
    let (scene, lights) = unlit(scene);
    let (w, h) = (400, 400);
    let camera = Camera {
        ortho: Some(1.2),
        ..front_camera()
    };
    let opts = Shot {
        width: w,
        height: h,
        camera: Some(camera.clone()),
        settings: Settings {
            lights,
            ..Settings::default()
        },
    };
    let image = render(&PreparedScene::new(scene.clone()), &opts).image();
    // (u0, v0) = (0.3, 0.4): emissive texel (19, 25), black; (0.05, 0.55): the emissive
    // texel (3, 35), cyan. The grid's texel follows from the pixel's own TEXCOORD_1.
    let texel = |uv: Vec2, n: f32| {
        let f = |c: f32| ((c - c.floor()) * n).floor() as u32;
        (f(uv.x), f(uv.y))
    };
    for (uv0, glow_texel) in [
        (Vec2::new(0.3, 0.4), (19, 25)),
        (Vec2::new(0.05, 0.55), (3, 35)),
    ] {
        let (x, y) = pixel_of(&camera, w, h, point_at_uv(&scene, 0, 0, uv0));
        let at = uv_at_pixel(&scene, 0, 0, &camera, w, h, x, y);
        assert_eq!(texel(at, 64.0), glow_texel, "the README's emissive texel");
        let uv1 = Vec2::new(2.0 * at.y, 2.0 * (1.0 - at.x));
        let t = texel(uv1, 256.0);
        let want = grid.fetch(t.0, t.1) + glow.fetch(glow_texel.0, glow_texel.1);
        let got = image.pixel(x, y);
        assert!(
            (got - want).abs().truncate().max_element() < 2e-3,
            "UV0 {uv0}: pixel ({x}, {y}) is {got}, want {want}"
        );
    }
}

/// Mean absolute difference of two 8-bit RGB images, in levels.
fn mean_levels(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let sum: u64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum();
    sum as f64 / a.len() as f64
}

#[test]
fn gltfpack_quantised_uvs_render_like_the_original() {
    // gltfpack stores the UVs as 12-bit integers and folds the inverse into each slot's
    // KHR_texture_transform (offset [-1, 0], scale [48.01, 16.00]), and the positions'
    // into the node's matrix.
    let original = load_model("grid-torus.glb");
    let packed = load_model("grid-torus-gltfpack.glb");
    let t = packed.materials[0]
        .base_color_texture
        .expect("texture")
        .transform;
    assert!(
        !t.is_identity(),
        "the quantisation's transform is kept: {t:?}"
    );
    let camera = Camera {
        eye: Vec3::new(0.0, 2.6, 2.6),
        target: Vec3::ZERO,
        ..Camera::default()
    };
    let opts = Shot {
        width: 480,
        height: 360,
        camera: Some(camera),
        settings: Settings {
            shading: Some(Shading::Textured),
            ..Settings::default()
        },
    };
    let frame = |s: &Scene| render(&PreparedScene::new(s.clone()), &opts).srgb8();
    let (a, b) = (frame(&original), frame(&packed));
    let d = mean_levels(&a, &b);
    eprintln!("gltfpack vs original: mean difference {d:.3} levels");
    assert!(d < 1.0, "mean difference {d} levels");
    // Teeth: without the transform the packed UVs read one corner of one cell.
    let mut broken = packed.clone();
    for m in &mut broken.materials {
        if let Some(s) = &mut m.base_color_texture {
            s.transform = realist::scene::UvTransform::IDENTITY;
        }
    }
    let wrong = mean_levels(&a, &frame(&broken));
    assert!(
        wrong > 10.0,
        "ignoring the transform changes little: {wrong}"
    );
}

#[test]
fn generated_tangents_agree_with_the_files_mikktspace_tangents() {
    // normal-sphere.glb carries TANGENT written by glTF-Transform with the mikktspace
    // package (the reference C code compiled to WebAssembly); MikkTSpace again, here, on
    // the same positions, normals and UVs must give the same frames.
    let scene = load_model("normal-sphere.glb");
    let mut mesh = scene.meshes[0].clone();
    let file = mesh.tangents.clone().expect("the file's tangents");
    assert!(
        scene
            .report
            .generated
            .iter()
            .all(|g| !g.contains("tangents")),
        "the file's own tangents are used: {:?}",
        scene.report.generated
    );
    mesh.generate_tangents(0).expect("UV set 0");
    let ours = mesh.tangents.as_ref().unwrap();
    let (mut worst, mut flipped) = (0f32, 0);
    for (c, &v) in mesh.corners.iter().enumerate() {
        let (a, b) = (file.at(c, v), ours.at(c, v));
        worst = worst.max(a.truncate().angle_between(b.truncate()));
        flipped += usize::from(a.w != b.w);
    }
    eprintln!(
        "largest angle {:.4} degrees, {flipped} handedness differences",
        worst.to_degrees()
    );
    assert_eq!(flipped, 0);
    assert!(worst.to_degrees() < 0.5, "{} degrees", worst.to_degrees());

    // Loaded without its tangents, the file gets them generated (and says so).
    let mut stripped = scene.clone();
    stripped.meshes[0].tangents = None;
    stripped.report.generated.clear();
    stripped.check_texture_slots();
    assert!(
        stripped
            .report
            .generated
            .iter()
            .any(|g| g.contains("MikkTSpace")),
        "{:?}",
        stripped.report.generated
    );
    assert_eq!(stripped.meshes[0].tangents.as_ref(), Some(ours));
}
