//! Coverage properties of the fill rule: meshes that tile the plane cover every pixel (every
//! sample, multisampled) exactly once (additive count buffer), whatever the sub-pixel offset,
//! vertex order, winding, w scale, sample count or thread count.

use glam::{Vec2, Vec4};
use proptest::prelude::*;
use realist::raster::{
    self, Batch, Blend, Colors, Cull, DepthTest, Draw, DrawState, FragmentShader, Stats, Target,
};
use realist::simd::KernelKind;

/// Adds 1 to the red channel of every covered pixel.
struct Count;

impl FragmentShader for Count {
    fn discards(&self, _: u32) -> bool {
        false
    }
    fn shade(&self, b: &mut Batch) {
        for g in 0..b.len {
            b.out[g] = Colors::splat(Vec4::new(1.0, 0.0, 0.0, 0.0));
        }
    }
}

fn counting() -> DrawState {
    DrawState {
        cull: Cull::None,
        depth_test: DepthTest::Always,
        depth_write: false,
        blend: Blend::Add,
        ..DrawState::opaque()
    }
}

/// Rasterizes NDC triangles (given as 2D points plus a per-vertex w scale) with `samples`
/// per pixel and returns the per-pixel count summed over its samples.
fn count(
    width: u32,
    height: u32,
    points: &[Vec2],
    w: &[f32],
    tris: &[[u32; 3]],
    samples: u32,
) -> Vec<u32> {
    count_with(width, height, points, w, tris, counting(), samples)
}

fn count_with(
    width: u32,
    height: u32,
    points: &[Vec2],
    w: &[f32],
    tris: &[[u32; 3]],
    state: DrawState,
    samples: u32,
) -> Vec<u32> {
    count_cut(width, height, points, w, tris, state, samples, &[])
}

/// [`count_with`] with section planes (clip space).
#[allow(clippy::too_many_arguments)]
fn count_cut(
    width: u32,
    height: u32,
    points: &[Vec2],
    w: &[f32],
    tris: &[[u32; 3]],
    state: DrawState,
    samples: u32,
    sections: &[Vec4],
) -> Vec<u32> {
    let clip: Vec<Vec4> = points
        .iter()
        .zip(w)
        .map(|(p, &w)| Vec4::new(p.x * w, p.y * w, 0.5 * w, w))
        .collect();
    let draw = Draw {
        id: 0,
        sections,
        clip: &clip,
        varyings: &[],
        stride: 0,
        triangles: tris,
        state,
    };
    // Coverage is integer arithmetic: every kernel must give the identical count.
    let mut first: Option<Vec<u32>> = None;
    for kernel in KernelKind::available_kinds() {
        let mut target = Target::new(width, height, Vec4::ZERO);
        target.set_samples(samples, Vec4::ZERO);
        assert_eq!(target.samples(), samples);
        let mut stats = Stats::default();
        raster::draw_with_kernel(&mut target, &[draw], &Count, &mut stats, kernel);
        // The resolve averages the samples: multiples of 1/samples, exact in f32.
        let counts: Vec<u32> = target
            .resolve()
            .color
            .iter()
            .map(|c| (c.x * samples as f32).round() as u32)
            .collect();
        match &first {
            Some(f) => assert!(*f == counts, "kernel {kernel:?} covers differently"),
            None => first = Some(counts),
        }
    }
    first.unwrap_or_default()
}

/// An (n+1) x (m+1) grid of points spanning beyond the viewport, interior points jittered by
/// up to 0.45 of a cell, two triangles per cell with the given diagonal and windings.
fn grid(
    n: usize,
    m: usize,
    jitter: &[(f32, f32)],
    offset: Vec2,
    flips: &[bool],
) -> (Vec<Vec2>, Vec<[u32; 3]>) {
    let mut pts = Vec::new();
    for j in 0..=m {
        for i in 0..=n {
            let mut p = Vec2::new(
                -1.3 + 2.6 * i as f32 / n as f32,
                -1.3 + 2.6 * j as f32 / m as f32,
            );
            if i > 0 && i < n && j > 0 && j < m {
                let (jx, jy) = jitter[(j * (n + 1) + i) % jitter.len()];
                p += Vec2::new(jx * 2.6 / n as f32, jy * 2.6 / m as f32) * 0.45;
            }
            pts.push(p + offset);
        }
    }
    let mut tris = Vec::new();
    let idx = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..m {
        for i in 0..n {
            let k = tris.len();
            let mut a = [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)];
            let mut b = [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)];
            if flips[k % flips.len()] {
                a.swap(1, 2);
            }
            if flips[(k + 1) % flips.len()] {
                b.swap(0, 1);
            }
            tris.push(a);
            tris.push(b);
        }
    }
    (pts, tris)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn jittered_grid_covers_every_pixel_once(
        n in 2usize..14,
        m in 2usize..14,
        width in 1u32..150,
        height in 1u32..150,
        jitter in prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0), 16..64),
        flips in prop::collection::vec(any::<bool>(), 1..16),
        offset in (-0.05f32..0.05, -0.05f32..0.05),
        wscale in prop::collection::vec(0.01f32..50.0, 4..8),
        samples in prop::sample::select(vec![1u32, 4]),
    ) {
        let (pts, tris) = grid(n, m, &jitter, Vec2::new(offset.0, offset.1), &[false]);
        // Large jitter can fold a cell over; such a mesh does not tile the plane.
        prop_assume!(tris.iter().all(|t| {
            let [a, b, c] = t.map(|k| pts[k as usize]);
            (b - a).perp_dot(c - a) > 0.0
        }));
        let (_, tris) = grid(n, m, &jitter, Vec2::new(offset.0, offset.1), &flips);
        let w: Vec<f32> = (0..pts.len()).map(|k| wscale[k % wscale.len()]).collect();
        let counts = count(width, height, &pts, &w, &tris, samples);
        for (k, c) in counts.iter().enumerate() {
            prop_assert_eq!(*c, samples, "pixel ({}, {}) of {}x{}", k as u32 % width, k as u32 / width, width, height);
        }
    }

    #[test]
    fn closed_fan_covers_every_pixel_once(
        spokes in 3usize..40,
        center in (-0.9f32..0.9, -0.9f32..0.9),
        rotation in 0.0f32..6.3,
        width in 1u32..200,
        height in 1u32..200,
        reverse in any::<bool>(),
        subpixel_bits in 0u8..=8,
        samples in prop::sample::select(vec![1u32, 4]),
    ) {
        // A fan around an interior point whose rim lies outside the viewport.
        let mut pts = vec![Vec2::new(center.0, center.1)];
        for k in 0..spokes {
            let a = rotation + k as f32 * std::f32::consts::TAU / spokes as f32;
            pts.push(Vec2::new(libm::cosf(a), libm::sinf(a)) * 6.0);
        }
        let mut tris: Vec<[u32; 3]> =
            (0..spokes).map(|k| [0, 1 + k as u32, 1 + ((k + 1) % spokes) as u32]).collect();
        if reverse {
            for t in &mut tris {
                t.rotate_left(1);
            }
            tris.reverse();
        }
        // Watertight at every snap precision: shared vertices snap alike.
        let state = DrawState { subpixel_bits, ..counting() };
        let counts = count_with(width, height, &pts, &vec![1.0; pts.len()], &tris, state, samples);
        prop_assert!(counts.iter().all(|&c| c == samples), "counts {:?}", counts.iter().filter(|&&c| c != samples).count());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// A jittered grid cut by one or two section planes (lines across the image): every
    /// pixel centre clearly on the kept side is covered exactly once, every one clearly on
    /// the removed side not at all, and none twice along the cuts (the pieces of triangles
    /// that share an edge meet the plane at the identical vertex).
    #[test]
    fn a_section_plane_cuts_a_grid_without_gaps_or_overlaps(
        n in 2usize..10,
        m in 2usize..10,
        width in 8u32..120,
        height in 8u32..120,
        jitter in prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0), 16..64),
        wscale in prop::collection::vec(0.05f32..20.0, 4..8),
        planes in prop::collection::vec((0.0f32..6.3, -0.8f32..0.8), 1..=2),
        samples in prop::sample::select(vec![1u32, 4]),
    ) {
        let (pts, tris) = grid(n, m, &jitter, Vec2::ZERO, &[false]);
        prop_assume!(tris.iter().all(|t| {
            let [a, b, c] = t.map(|k| pts[k as usize]);
            (b - a).perp_dot(c - a) > 0.0
        }));
        let w: Vec<f32> = (0..pts.len()).map(|k| wscale[k % wscale.len()]).collect();
        // Keep cos(a) x + sin(a) y + c >= 0 in NDC: (cos a, sin a, 0, c) in clip space.
        let sections: Vec<Vec4> =
            planes.iter().map(|&(a, c)| Vec4::new(libm::cosf(a), libm::sinf(a), 0.0, c)).collect();
        let counts = count_cut(width, height, &pts, &w, &tris, counting(), samples, &sections);
        // Half a pixel in NDC, along the planes' unit normals: a pixel's samples all lie
        // within 0.5 px of its centre in each axis.
        let px = 2.0 / width.min(height) as f32;
        for (k, &c) in counts.iter().enumerate() {
            let (x, y) = (k as u32 % width, k as u32 / width);
            let ndc = Vec2::new(
                2.0 * (x as f32 + 0.5) / width as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / height as f32,
            );
            let d: Vec<f32> = sections.iter().map(|p| p.x * ndc.x + p.y * ndc.y + p.w).collect();
            prop_assert!(c <= samples, "pixel ({}, {}) covered {} times", x, y, c);
            if d.iter().all(|&d| d > px) {
                prop_assert_eq!(c, samples, "kept pixel ({}, {})", x, y);
            }
            if d.iter().any(|&d| d < -px) {
                prop_assert_eq!(c, 0, "removed pixel ({}, {})", x, y);
            }
        }
    }
}

/// Pixel centres exactly on shared edges and vertices (a grid aligned to pixel centres).
#[test]
fn edges_through_pixel_centres_are_covered_once() {
    let (w, h) = (32u32, 32u32);
    // Grid lines at pixel centres: NDC x = (2 * (px + 0.5) / w) - 1.
    let ndc = |p: f32, n: u32| 2.0 * (p + 0.5) / n as f32 - 1.0;
    let mut pts = Vec::new();
    let xs: Vec<f32> = [-10.0, 3.0, 7.0, 15.0, 16.0, 31.0, 50.0]
        .iter()
        .map(|&p| ndc(p, w))
        .collect();
    let ys: Vec<f32> = [-10.0, 0.0, 5.0, 9.0, 20.0, 50.0]
        .iter()
        .map(|&p| -ndc(p, h))
        .collect();
    for y in &ys {
        for x in &xs {
            pts.push(Vec2::new(*x, *y));
        }
    }
    let nx = xs.len();
    let mut tris = Vec::new();
    for j in 0..ys.len() - 1 {
        for i in 0..nx - 1 {
            let q = |a: usize, b: usize| (b * nx + a) as u32;
            tris.push([q(i, j), q(i + 1, j), q(i + 1, j + 1)]);
            tris.push([q(i, j), q(i + 1, j + 1), q(i, j + 1)]);
        }
    }
    for samples in [1, 4] {
        let counts = count(w, h, &pts, &vec![1.0; pts.len()], &tris, samples);
        assert!(
            counts.iter().all(|&c| c == samples),
            "{samples} samples: {} pixels not covered exactly once",
            counts.iter().filter(|&&c| c != samples).count()
        );
    }
}

/// Translating a triangle by whole pixels translates its coverage exactly.
#[test]
fn integer_translation_moves_coverage_exactly() {
    let (w, h) = (96u32, 80u32);
    let to_ndc = |x: f32, y: f32| Vec2::new(2.0 * x / w as f32 - 1.0, 1.0 - 2.0 * y / h as f32);
    let base = [(10.3f32, 7.7f32), (40.1, 12.5), (22.9, 35.0)];
    let at = |dx: f32, dy: f32| {
        base.iter()
            .map(|&(x, y)| to_ndc(x + dx, y + dy))
            .collect::<Vec<_>>()
    };
    for samples in [1, 4] {
        let a = count(w, h, &at(0.0, 0.0), &[1.0; 3], &[[0, 1, 2]], samples);
        let b = count(w, h, &at(17.0, 29.0), &[1.0; 3], &[[0, 1, 2]], samples);
        let covered: usize = a.iter().map(|&c| c as usize).sum();
        assert!(covered > 100 * samples as usize);
        for y in 0..h - 29 {
            for x in 0..w - 17 {
                assert_eq!(
                    a[(y * w + x) as usize],
                    b[((y + 29) * w + x + 17) as usize],
                    "{samples} samples, pixel ({x}, {y})"
                );
            }
        }
    }
}
