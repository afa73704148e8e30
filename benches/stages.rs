//! One criterion benchmark per pipeline stage on fixed fixtures (no files needed):
//! a 256 x 128 latitude/longitude sphere (~65,000 triangles) at 1280 x 720 under the
//! standard accuracy camera, and a 128 x 128 floor grid (32,768 triangles) that crosses the
//! near plane and the guard band, for clipping. `cargo bench --bench stages`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::{Mat4, Vec3, Vec4};

use realist::mesh::Mesh;
use realist::quality::sphere::SphereSetup;
use realist::raster::{
    self, stages, Batch, Colors, Cull, Draw, DrawState, FragmentShader, Stats, Target,
};
use realist::scene::{AlphaMode, Light};
use realist::shade::stages::Program;
use realist::shade::{DrawParams, LightSet, LitLayout, LitShader, Surface, TexView};
use realist::simd::{KernelKind, F8, V3};

const W: u32 = 1280;
const H: u32 = 720;

struct Fixture {
    positions: Vec<Vec3>,
    /// World position and normal per vertex (the lit layout without UV or colour).
    varyings: Vec<f32>,
    triangles: Vec<[u32; 3]>,
    mvp: Mat4,
}

fn sphere() -> Fixture {
    let setup = SphereSetup::standard(W, H);
    let tri = Mesh::sphere(1.0, 256, 128).expect("sphere").triangulate();
    let mvp = setup.camera.projection(W as f32 / H as f32) * setup.camera.view();
    Fixture {
        varyings: lit_varyings(&tri.positions, &tri.normals),
        positions: tri.positions,
        triangles: tri.triangles,
        mvp,
    }
}

fn floor() -> Fixture {
    let n = 128u32;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(Vec3::new(
                i as f32 / n as f32 * 200.0 - 100.0,
                -1.0,
                j as f32 / n as f32 * 200.0 - 100.0,
            ));
        }
    }
    let mut triangles = Vec::new();
    let idx = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            triangles.push([idx(i, j), idx(i, j + 1), idx(i + 1, j)]);
            triangles.push([idx(i + 1, j), idx(i, j + 1), idx(i + 1, j + 1)]);
        }
    }
    let cam =
        realist::scene::Camera::orbit(Vec3::ZERO, 10.0, 5.0, 3.0, realist::scene::DEFAULT_YFOV);
    let mvp = cam.projection(W as f32 / H as f32) * cam.view();
    let normals = vec![Vec3::Y; positions.len()];
    Fixture {
        varyings: lit_varyings(&positions, &normals),
        positions,
        triangles,
        mvp,
    }
}

fn lit_varyings(positions: &[Vec3], normals: &[Vec3]) -> Vec<f32> {
    let layout = LitLayout::default();
    let mut out = vec![0.0; positions.len() * layout.stride()];
    for ((o, p), n) in out.chunks_mut(layout.stride()).zip(positions).zip(normals) {
        layout.write(
            o,
            *p,
            *n,
            |_| glam::Vec2::ZERO,
            || Vec3::ZERO,
            Vec4::ONE,
            Vec4::X,
        );
    }
    out
}

/// Lambert against a fixed light: the cost of the simplest lit shader.
struct Lambert(KernelKind);

realist::simd::per_kernel! {
    /// Lambert on the groups of a batch.
    fn lambert<L>(b: &mut Batch) {
        let l = V3::<L>::splat(Vec3::new(0.4, 0.8, 0.45).normalize());
        for g in 0..b.len {
            let v = &b.var[g];
            let n = V3::<L>::new(v[3].get(), v[4].get(), v[5].get()).normalize_or_zero();
            let d = n.dot(l).max(F8::ZERO);
            b.out[g] = Colors::of(d, d, d, F8::ONE);
        }
    }
}

impl FragmentShader for Lambert {
    fn defers(&self, _: u32) -> bool {
        true
    }
    fn discards(&self, _: u32) -> bool {
        false
    }
    fn shade(&self, b: &mut Batch) {
        lambert::pick(self.0)(b);
    }
}

fn draw_of<'a>(f: &'a Fixture, clip: &'a [Vec4]) -> Draw<'a> {
    Draw {
        id: 0,
        sections: &[],
        clip,
        varyings: &f.varyings,
        stride: LitLayout::default().stride(),
        triangles: &f.triangles,
        state: DrawState {
            cull: Cull::Back,
            ..DrawState::opaque()
        },
    }
}

fn benches(c: &mut Criterion) {
    let sphere = sphere();
    let floor = floor();
    let clip = raster::transform_positions(sphere.mvp, &sphere.positions);
    let floor_clip = raster::transform_positions(floor.mvp, &floor.positions);

    c.bench_function("transform/sphere", |b| {
        b.iter(|| raster::transform_positions(black_box(sphere.mvp), black_box(&sphere.positions)))
    });
    c.bench_function("clip_cull/sphere", |b| {
        b.iter(|| stages::clip_cull(&draw_of(&sphere, &clip), W, H))
    });
    c.bench_function("clip_cull/floor crossing the near plane", |b| {
        b.iter(|| stages::clip_cull(&draw_of(&floor, &floor_clip), W, H))
    });
    c.bench_function("setup/sphere", |b| {
        b.iter(|| stages::setup_all(&draw_of(&sphere, &clip), W, H))
    });
    let target = Target::new(W, H, Vec4::ZERO);
    c.bench_function("bin/sphere", |b| {
        b.iter_batched(
            || stages::setup_all(&draw_of(&sphere, &clip), W, H),
            |mut batch| {
                stages::bin_all(&target, &mut batch);
                batch
            },
            criterion::BatchSize::LargeInput,
        )
    });
    let mut batch = stages::setup_all(&draw_of(&sphere, &clip), W, H);
    stages::bin_all(&target, &mut batch);
    let params = [DrawParams {
        base: Vec4::new(0.8, 0.7, 0.6, 1.0),
        surface: Surface {
            diffuse: Vec3::ONE,
            specular: Vec3::splat(0.4),
            ambient: Vec3::ONE,
            shininess: 32.0,
            pbr: None,
        },
        emissive: Vec3::ZERO,
        base_map: None,
        gloss: None,
        normal_map: None,
        occlusion: None,
        emissive_map: None,
        bump: None,
        metal_rough: None,
        layer_maps: Default::default(),
        model_scale: glam::Vec3::ONE,
        unlit: false,
        view: TexView::Lit,
        measure: None,
        layout: LitLayout::default(),
        mapped: false,
        blinn: true,
        provoking_vertex: false,
        alpha: AlphaMode::Opaque,
        double_sided: false,
        lights: (0, 1),
    }];
    let lights = LightSet::new(&[
        Light::ambient(Vec3::splat(0.1)),
        Light::directional(-Vec3::new(0.5, 1.0, 0.8), Vec3::splat(0.9)),
    ]);
    // One fill benchmark per kernel this machine has, with the simplest and the real shader.
    for kernel in KernelKind::available_kinds() {
        let name = kernel.name();
        let mut program = Program::default();
        program.build(&params[0], &[0], false, kernel);
        let programs = [program];
        let blinn = LitShader {
            draws: &params,
            programs: &programs,
            lights: &lights,
            active: &[0],
            eye: Vec3::new(0.0, 0.0, 4.0),
            forward: -Vec3::Z,
            fog: None,
            lod_scale: 1.0,
            backdrop: None,
        };
        c.bench_function(&format!("fill_shade/sphere lambert/{name}"), |b| {
            let mut target = Target::new(W, H, Vec4::ZERO);
            b.iter(|| {
                target.clear(Vec4::ZERO);
                stages::fill_all(
                    &mut target,
                    &batch,
                    &Lambert(kernel),
                    &mut Stats::default(),
                    kernel,
                );
            })
        });
        c.bench_function(&format!("fill_shade/sphere blinn-phong/{name}"), |b| {
            let mut target = Target::new(W, H, Vec4::ZERO);
            b.iter(|| {
                target.clear(Vec4::ZERO);
                stages::fill_all(&mut target, &batch, &blinn, &mut Stats::default(), kernel);
            })
        });
    }
    let mut drawn = Target::new(W, H, Vec4::ZERO);
    raster::draw(
        &mut drawn,
        &[draw_of(&sphere, &clip)],
        &Lambert(KernelKind::best()),
        &mut Stats::default(),
    );
    c.bench_function("encode/srgb8 1280x720", |b| b.iter(|| drawn.to_srgb8()));
    let rgb = drawn.to_srgb8();
    c.bench_function("encode/png 1280x720", |b| {
        b.iter(|| {
            let mut out = Vec::new();
            image::RgbImage::from_raw(W, H, rgb.clone())
                .expect("size")
                .write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
                .expect("png");
            out
        })
    });
}

criterion_group! {
    name = stages_group;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = benches
}
criterion_main!(stages_group);
