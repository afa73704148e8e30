//! One criterion benchmark per pipeline stage on fixed fixtures (no files needed):
//! a 256 x 128 latitude/longitude sphere (~65,000 triangles) at 1280 x 720 under the
//! standard accuracy camera, and a 128 x 128 floor grid (32,768 triangles) that crosses the
//! near plane and the guard band, for clipping. `cargo bench --bench stages`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::{Mat4, Vec3, Vec4};

use realist::mesh::Mesh;
use realist::quality::sphere::SphereSetup;
use realist::raster::{
    self, stages, Cull, Draw, DrawState, FragmentShader, Stats, Target, TriInfo,
};

const W: u32 = 1280;
const H: u32 = 720;

struct Fixture {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    mvp: Mat4,
}

fn sphere() -> Fixture {
    let setup = SphereSetup::standard(W, H);
    let tri = Mesh::sphere(1.0, 256, 128).expect("sphere").triangulate();
    let mvp = setup.camera.projection(W as f32 / H as f32) * setup.camera.view();
    Fixture {
        positions: tri.positions,
        normals: tri.normals,
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
        positions,
        normals,
        triangles,
        mvp,
    }
}

/// Lambert against a fixed light: the cost of a light per-pixel shader.
struct Lambert;

impl FragmentShader for Lambert {
    type Varying = Vec3;
    fn fragment(&self, _: TriInfo, n: &Vec3) -> Option<Vec4> {
        let l = Vec3::new(0.4, 0.8, 0.45).normalize();
        let d = n.normalize_or_zero().dot(l).max(0.0);
        Some(Vec4::new(d, d, d, 1.0))
    }
}

fn draw_of<'a>(f: &'a Fixture, clip: &'a [Vec4]) -> Draw<'a, Vec3> {
    Draw {
        id: 0,
        clip,
        varyings: &f.normals,
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
    let batch = stages::setup_all(&draw_of(&sphere, &clip), W, H);
    c.bench_function("bin/sphere", |b| {
        b.iter(|| stages::bin_all(&target, &batch))
    });
    c.bench_function("fill_shade/sphere lambert", |b| {
        b.iter_batched(
            || {
                let batch = stages::setup_all(&draw_of(&sphere, &clip), W, H);
                let target = Target::new(W, H, Vec4::ZERO);
                let bins = stages::bin_all(&target, &batch);
                (target, batch, bins)
            },
            |(mut target, mut batch, bins)| {
                let mut stats = Stats::default();
                stages::fill_all(&mut target, &mut batch, bins, &Lambert, &mut stats);
                target
            },
            criterion::BatchSize::LargeInput,
        )
    });
    let mut drawn = Target::new(W, H, Vec4::ZERO);
    raster::draw(
        &mut drawn,
        &[draw_of(&sphere, &clip)],
        &Lambert,
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
