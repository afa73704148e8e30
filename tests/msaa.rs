//! Multisampling (4 samples per pixel): coverage at exactly the standard sample positions
//! with the top-left rule, depth tested per sample, one shader call per pixel and triangle,
//! the resolve an average in linear light, and edges closer to the exact area coverage than
//! one sample per pixel. Every kernel the machine has must give the same image.

use glam::{Vec2, Vec4};
use realist::raster::{
    self, Batch, Blend, Colors, Cull, DepthTest, Draw, DrawState, FragmentShader, Stats, Target,
};
use realist::simd::KernelKind;

/// Direct3D's standard 4-sample pattern in 1/16 pixel (the specification the target follows).
const PATTERN: [[i64; 2]; 4] = [[-2, -6], [6, -2], [-6, 2], [2, 6]];

/// Writes the colour of its draw: red for draw 0, green for draw 1 (alpha 1).
struct ByDraw;

impl FragmentShader for ByDraw {
    fn discards(&self, _: u32) -> bool {
        false
    }
    fn shade(&self, b: &mut Batch) {
        let c = if b.draw == 0 { Vec4::X } else { Vec4::Y };
        for g in 0..b.len {
            b.out[g] = Colors::splat(c.with_w(1.0));
        }
    }
}

/// Renders `draws` with `samples` per pixel on every kernel, asserts they agree exactly, and
/// returns the resolved colours and the counters.
fn render(w: u32, h: u32, draws: &[Draw<'_>], samples: u32) -> (Vec<Vec4>, Stats) {
    let mut first: Option<(Vec<Vec4>, Stats)> = None;
    for kernel in KernelKind::available_kinds() {
        let mut target = Target::new(w, h, Vec4::ZERO);
        target.set_samples(samples, Vec4::ZERO);
        let mut stats = Stats::default();
        raster::draw_with_kernel(&mut target, draws, &ByDraw, &mut stats, kernel);
        let color = target.resolve().color;
        match &first {
            Some((f, _)) => assert!(*f == color, "kernel {kernel:?} differs"),
            None => first = Some((color, stats)),
        }
    }
    first.expect("at least the portable kernel")
}

fn state() -> DrawState {
    DrawState {
        cull: Cull::None,
        ..DrawState::opaque()
    }
}

/// Pixel coordinates (y down) -> NDC for a `w` x `h` target.
fn ndc(p: Vec2, w: u32, h: u32) -> Vec2 {
    Vec2::new(2.0 * p.x / w as f32 - 1.0, 1.0 - 2.0 * p.y / h as f32)
}

/// Samples of pixel (x, y) inside triangle `v` (pixel coordinates, multiples of 1/256), by
/// the top-left rule, in exact integer arithmetic on a 1/256 grid.
fn expected_samples(v: [Vec2; 3], x: u32, y: u32) -> u32 {
    let fixed = |p: Vec2| [(p.x * 256.0) as i64, (p.y * 256.0) as i64];
    let mut p = v.map(fixed);
    let area =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    if area < 0 {
        p.swap(1, 2);
    }
    let mut n = 0;
    for o in PATTERN {
        let s = [
            i64::from(x) * 256 + 128 + o[0] * 16,
            i64::from(y) * 256 + 128 + o[1] * 16,
        ];
        let inside = (0..3).all(|k| {
            let (a0, b0) = (p[(k + 1) % 3], p[(k + 2) % 3]);
            let a = a0[1] - b0[1];
            let b = b0[0] - a0[0];
            let e = a * (s[0] - a0[0]) + b * (s[1] - a0[1]);
            e > 0 || (e == 0 && (a > 0 || (a == 0 && b > 0)))
        });
        n += u32::from(inside);
    }
    n
}

#[test]
fn coverage_is_the_samples_inside_by_the_top_left_rule() {
    let (w, h) = (64u32, 48u32);
    // Vertices on the 1/16 grid too, so edges pass exactly through sample points.
    for v in [
        [
            Vec2::new(3.25, 2.5),
            Vec2::new(60.75, 9.125),
            Vec2::new(12.0, 45.3125),
        ],
        [
            Vec2::new(10.5, 4.5),
            Vec2::new(10.5, 40.375),
            Vec2::new(50.625, 22.5),
        ],
        [
            Vec2::new(0.5, 0.5),
            Vec2::new(63.5, 0.5),
            Vec2::new(0.5, 47.5),
        ],
        [
            Vec2::new(20.125, 7.0),
            Vec2::new(21.0, 30.0),
            Vec2::new(19.75, 30.5),
        ],
    ] {
        let clip: Vec<Vec4> = v
            .iter()
            .map(|&p| ndc(p, w, h).extend(0.5).extend(1.0))
            .collect();
        let d = Draw {
            id: 0,
            sections: &[],
            clip: &clip,
            varyings: &[],
            stride: 0,
            triangles: &[[0, 1, 2]],
            state: state(),
        };
        let (color, stats) = render(w, h, &[d], 4);
        let mut partial = 0;
        for y in 0..h {
            for x in 0..w {
                let want = expected_samples(v, x, y);
                let got = color[(y * w + x) as usize].x * 4.0;
                assert_eq!(got, want as f32, "{v:?}: pixel ({x}, {y})");
                partial += u32::from(want > 0 && want < 4);
            }
        }
        assert!(partial > 10, "{v:?}: only {partial} edge pixels");
        // One shader lane per pixel with any sample covered, not one per sample.
        let pixels = color.iter().filter(|c| c.x > 0.0).count() as u64;
        assert_eq!(stats.pixels_shaded, pixels, "{v:?}");
    }
}

#[test]
fn depth_is_tested_per_sample() {
    // A flat red quad at depth 0.5 and a green one whose depth rises with x, crossing it at
    // x = 20.25 px: samples right of the line see green (reversed-Z, greater is nearer).
    let (w, h) = (40u32, 8u32);
    let quad = |z: &dyn Fn(f32) -> f32| -> Vec<Vec4> {
        [
            Vec2::new(0.0, 0.0),
            Vec2::new(40.0, 0.0),
            Vec2::new(40.0, 8.0),
            Vec2::new(0.0, 8.0),
        ]
        .iter()
        .map(|&p| ndc(p, w, h).extend(z(p.x)).extend(1.0))
        .collect()
    };
    let flat = quad(&|_| 0.5);
    let slope = quad(&|x| 0.5 + 0.01 * (x - 20.25));
    let tris = [[0u32, 1, 2], [0, 2, 3]];
    let draws = [&flat, &slope].map(|clip| Draw {
        id: 0,
        sections: &[],
        clip,
        varyings: &[],
        stride: 0,
        triangles: &tris,
        state: state(),
    });
    let draws = [draws[0], Draw { id: 1, ..draws[1] }];
    let (color, _) = render(w, h, &draws, 4);
    for x in 0..w {
        let want = PATTERN
            .iter()
            .filter(|o| x as f32 + 0.5 + o[0] as f32 / 16.0 > 20.25)
            .count() as f32
            / 4.0;
        for y in 0..h {
            let c = color[(y * w + x) as usize];
            assert_eq!((c.y, c.x), (want, 1.0 - want), "pixel ({x}, {y})");
        }
    }
    // The column the line crosses is mixed (three of four samples right of 20.25).
    assert_eq!(color[20].y, 0.75);
}

/// Mean absolute error of the resolved coverage of a disc against its exact area coverage
/// (estimated with 64 x 64 samples per pixel).
fn disc_error(samples: u32) -> f64 {
    let (w, h) = (64u32, 64u32);
    let (c, r) = (Vec2::new(31.3, 32.6), 23.7f32);
    let n = 96;
    let mut clip = vec![ndc(c, w, h).extend(0.5).extend(1.0)];
    for k in 0..n {
        let a = k as f32 * std::f32::consts::TAU / n as f32;
        clip.push(
            ndc(c + Vec2::new(libm::cosf(a), libm::sinf(a)) * r, w, h)
                .extend(0.5)
                .extend(1.0),
        );
    }
    let tris: Vec<[u32; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
    let d = Draw {
        id: 0,
        sections: &[],
        clip: &clip,
        varyings: &[],
        stride: 0,
        triangles: &tris,
        state: DrawState {
            blend: Blend::Replace,
            depth_test: DepthTest::Always,
            ..state()
        },
    };
    let (color, _) = render(w, h, &[d], samples);
    // The polygon's exact coverage, point-sampled finely.
    let poly: Vec<Vec2> = (0..n)
        .map(|k| {
            let a = k as f32 * std::f32::consts::TAU / n as f32;
            c + Vec2::new(libm::cosf(a), libm::sinf(a)) * r
        })
        .collect();
    let inside = |p: Vec2| {
        (0..n as usize).all(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % n as usize]);
            (b - a).perp_dot(p - a) >= 0.0
        })
    };
    let mut err = 0.0;
    let fine = 64;
    for y in 0..h {
        for x in 0..w {
            let mut hit = 0;
            for j in 0..fine {
                for i in 0..fine {
                    let p = Vec2::new(
                        x as f32 + (i as f32 + 0.5) / fine as f32,
                        y as f32 + (j as f32 + 0.5) / fine as f32,
                    );
                    hit += u32::from(inside(p));
                }
            }
            let exact = f64::from(hit) / f64::from(fine * fine);
            err += (f64::from(color[(y * w + x) as usize].x) - exact).abs();
        }
    }
    err / f64::from(w * h)
}

#[test]
fn four_samples_halve_the_edge_error_at_least() {
    let one = disc_error(1);
    let four = disc_error(4);
    eprintln!("disc coverage error: 1 sample {one:.5}, 4 samples {four:.5}");
    assert!(four < 0.5 * one, "1 sample {one}, 4 samples {four}");
}

#[test]
fn sample_count_round_trips_and_changing_it_clears() {
    let mut t = Target::new(70, 65, Vec4::ONE);
    assert_eq!(t.samples(), 1);
    t.set_samples(4, Vec4::splat(0.25));
    assert_eq!(t.samples(), 4);
    assert_eq!(t.resolve().pixel(69, 64), Vec4::splat(0.25));
    t.reshape(130, 70, Vec4::ZERO);
    assert_eq!(t.samples(), 4);
    let (ti, o) = t.locate(129, 69);
    t.tiles[ti].materialize();
    t.tiles[ti].set_color(o, Vec4::new(0.5, 0.0, 1.0, 1.0));
    assert_eq!(t.resolve().pixel(129, 69), Vec4::new(0.5, 0.0, 1.0, 1.0));
    t.set_samples(1, Vec4::ZERO);
    assert_eq!(t.resolve().pixel(129, 69), Vec4::ZERO);
}

#[test]
fn every_readout_averages_the_samples() {
    let (w, h) = (70u32, 65u32);
    let v = [
        Vec2::new(3.3, 2.6),
        Vec2::new(66.7, 20.2),
        Vec2::new(20.1, 63.9),
    ];
    let clip: Vec<Vec4> = v
        .iter()
        .map(|&p| ndc(p, w, h).extend(0.5).extend(1.0))
        .collect();
    let d = Draw {
        id: 1,
        sections: &[],
        clip: &clip,
        varyings: &[],
        stride: 0,
        triangles: &[[0, 1, 2]],
        state: state(),
    };
    let mut target = Target::new(w, h, Vec4::new(0.2, 0.0, 0.6, 1.0));
    target.set_samples(4, Vec4::new(0.2, 0.0, 0.6, 1.0));
    raster::draw(&mut target, &[d], &ByDraw, &mut Stats::default());
    let mut rgba = vec![[0u8; 4]; (w * h) as usize];
    target.write_rgba8(&mut rgba);
    let rgb = target.to_srgb8();
    assert!(rgba.iter().zip(rgb.chunks(3)).all(|(a, b)| a[..3] == *b));
    // Edge pixels are mixtures: some green from the triangle, some blue from the clear.
    let mixed = rgba.iter().filter(|p| p[1] > 0 && p[2] > 0).count();
    assert!(mixed > 50, "{mixed} mixed pixels");
    let fb = target.resolve();
    let mut depth = vec![0.0; (w * h) as usize];
    target.write_depth(&mut depth);
    assert_eq!(depth, fb.depth);
}
