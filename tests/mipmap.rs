//! Mipmapping through the whole renderer (textured mode): a fine chequer on a plane seen at
//! a grazing angle must converge to its mean colour with trilinear filtering (and alias with
//! bilinear), and a quad drawn at exactly half the texture's size must read mip level 1.
//!
//! The scenes are lit by one white directional light along the surface normal and their
//! materials have no specular, so a pixel's linear colour is exactly the texture sample.

mod common;

use glam::{Vec2, Vec3, Vec4};
use realist::color::{delta_e_2000, xyz_to_lab, RgbSpace};
use realist::raster::Framebuffer;
use realist::render::{Settings, Shot};
use realist::scene::{Camera, Scene, TextureSlot};
use realist::shade::Shading;
use realist::texture::{Filter, Sampler, Texture, Wrap};

/// A background no texture sample can produce, marking uncovered pixels.
const BACKGROUND: Vec4 = Vec4::new(1.0, 0.0, 1.0, 1.0);

fn render(scene: &Scene, w: u32, h: u32, camera: Camera) -> Framebuffer {
    let opts = Shot {
        width: w,
        height: h,
        camera: Some(camera),
        settings: Settings {
            shading: Some(Shading::Textured),
            background: BACKGROUND,
            ..Settings::default()
        },
    };
    common::render_with(scene, &opts, 2).0
}

fn with_filter(scene: &Scene, filter: Filter) -> Scene {
    let mut scene = scene.clone();
    let slot = scene.materials[0]
        .base_color_texture
        .as_mut()
        .expect("textured");
    slot.sampler.filter = filter;
    scene
}

/// CIELAB (D65) of a linear sRGB colour.
fn lab(c: Vec4) -> [f64; 3] {
    let space = RgbSpace::srgb();
    let white = space.linear_to_xyz([1.0; 3]);
    let xyz = space.linear_to_xyz([f64::from(c.x), f64::from(c.y), f64::from(c.z)]);
    xyz_to_lab(xyz, white)
}

#[test]
fn grazing_checker_converges_to_its_mean_with_trilinear_only() {
    // A 2-texel black/white chequer (mean 0.5 in linear light) repeated every 10 units on a
    // plane 1 unit below an eye looking at the horizon. With H = 120 and a 60 degree field
    // of view (focal length 103.9 px), the row r pixels below the horizon sees the plane at
    // distance 103.9 / r, where a pixel spans 256 * 0.1 * 103.9 / r^2 texels along the view:
    // at least 11.8 texels (lod 3.6) for r <= 15, the far field checked here.
    let (w, h) = (160u32, 120u32);
    let checker = Texture::checker(256, 128, [0, 0, 0, 255], [255, 255, 255, 255]);
    let l = 3000.0;
    let scene = common::textured_quad(
        [
            Vec3::new(-l, 0.0, l),
            Vec3::new(l, 0.0, l),
            Vec3::new(l, 0.0, -l),
            Vec3::new(-l, 0.0, -l),
        ],
        [
            Vec2::new(-0.1 * l, 0.1 * l),
            Vec2::new(0.1 * l, 0.1 * l),
            Vec2::new(0.1 * l, -0.1 * l),
            Vec2::new(-0.1 * l, -0.1 * l),
        ],
        Vec3::Y,
        checker,
        Sampler::default(),
    );
    let camera = Camera {
        eye: Vec3::new(0.0, 1.0, 0.0),
        target: Vec3::new(0.0, 1.0, -10.0),
        yfov: 60f32.to_radians(),
        near: 0.1,
        far: 1e5,
        ..Camera::default()
    };
    let grey = lab(Vec4::splat(0.5));
    // Mean and largest ΔE2000 from the mean colour over the far field: rows 1..=15 below the
    // horizon (which lies between rows h/2 - 1 and h/2).
    let far_field = |fb: &Framebuffer| -> (f64, f64, usize) {
        let (mut sum, mut worst, mut n) = (0.0, 0f64, 0);
        for y in h / 2..h / 2 + 15 {
            for x in 0..w {
                let c = fb.pixel(x, y);
                assert_ne!(c, BACKGROUND, "({x}, {y}) is not on the plane");
                let d = delta_e_2000(lab(c), grey);
                sum += d;
                worst = worst.max(d);
                n += 1;
            }
        }
        (sum / n as f64, worst, n)
    };
    let trilinear = render(&scene, w, h, camera.clone());
    let slot = scene.materials[0].base_color_texture.expect("textured");
    assert_eq!(slot.sampler.filter, Filter::Trilinear);
    let (mean, worst, n) = far_field(&trilinear);
    eprintln!("trilinear: far-field ΔE2000 mean {mean:.3}, worst {worst:.3} over {n} pixels");
    assert!(
        mean < 0.1 && worst < 0.5,
        "trilinear: ΔE mean {mean}, worst {worst}"
    );

    let bilinear = render(&with_filter(&scene, Filter::Bilinear), w, h, camera);
    let (mean, worst, n) = far_field(&bilinear);
    eprintln!("bilinear: far-field ΔE2000 mean {mean:.3}, worst {worst:.3} over {n} pixels");
    // Point samples of a black/white chequer: most pixels are near black or white.
    assert!(
        mean > 15.0,
        "bilinear did not alias: ΔE mean {mean}, worst {worst}"
    );
}

#[test]
fn a_quad_at_half_size_reads_mip_level_1() {
    // yfov 90 degrees at distance 1: the 1 x 1 quad covers 32 x 32 pixels of a 64 x 64
    // image, pixels (16..48, 16..48), so a 64 x 64 texture has 2 texels a pixel: lod 1.
    // The UVs are shifted by half a base texel, so a pixel centre is a base texel's centre
    // (what level 0 would return) but lies a quarter of the way between level 1's texel
    // centres: the expected colour is level 1's bilinear blend with weights 3/4, 1/4.
    let n = 64u32;
    let mut state = 0x1234_5678u32;
    let texels = (0..n * n)
        .map(|_| {
            let mut c = [255u8; 4];
            for v in &mut c[..3] {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                *v = (state >> 24) as u8;
            }
            c
        })
        .collect();
    let texture = Texture::new("noise", n, n, texels, true).unwrap();
    let sampler = Sampler {
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Trilinear,
    };
    let s = 0.5 / n as f32;
    let mut scene = common::textured_quad(
        [
            Vec3::new(-0.5, 0.5, 0.0),
            Vec3::new(-0.5, -0.5, 0.0),
            Vec3::new(0.5, -0.5, 0.0),
            Vec3::new(0.5, 0.5, 0.0),
        ],
        [
            Vec2::new(s, s),
            Vec2::new(s, 1.0 + s),
            Vec2::new(1.0 + s, 1.0 + s),
            Vec2::new(1.0 + s, s),
        ],
        Vec3::Z,
        texture,
        Sampler::default(),
    );
    scene.materials[0].base_color_texture = Some(TextureSlot {
        sampler,
        ..TextureSlot::new(0)
    });
    let camera = Camera {
        eye: Vec3::new(0.0, 0.0, 1.0),
        target: Vec3::ZERO,
        yfov: 90f32.to_radians(),
        ..Camera::default()
    };
    let fb = render(&scene, n, n, camera);
    let t = &scene.textures[0];
    assert_eq!(t.level_size(1), (32, 32));
    let l1 = |x: u32, y: u32| t.fetch_level(1, x % 32, y % 32);
    let (mut worst, mut off_level0) = (0f32, 0f32);
    for j in 0..32 {
        for i in 0..32 {
            let got = fb.pixel(16 + i, 16 + j);
            assert_ne!(got, BACKGROUND, "pixel ({i}, {j}) of the quad not covered");
            let row = |y| l1(i, y).lerp(l1(i + 1, y), 0.25);
            let want = row(j).lerp(row(j + 1), 0.25);
            worst = worst.max((got - want).abs().max_element());
            let level0 = t.fetch_level(0, 2 * i + 1, 2 * j + 1);
            off_level0 += (got - level0).abs().max_element() / (32.0 * 32.0);
        }
    }
    assert!(worst < 1e-3, "level 1 expected, worst difference {worst}");
    // Level 0 (or bilinear) would read the base texel at each pixel centre: far off.
    assert!(off_level0 > 0.05, "{off_level0}");
    // The quad's border pixels are outside.
    assert_eq!(fb.pixel(15, 30), BACKGROUND);
    assert_eq!(fb.pixel(48, 30), BACKGROUND);
}
