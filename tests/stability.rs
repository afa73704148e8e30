//! The stability suite: random and extreme triangles against an f64 reference, with the
//! number of cases each test tried printed (`cargo test --release --test stability --
//! --nocapture` shows them). Deterministic: a fixed-seed generator, no proptest shrinking.
//!
//! The reference decides coverage in homogeneous coordinates, so it holds for triangles
//! crossing w = 0 as well: a pixel centre (x, y) in NDC is covered iff the clip-space
//! barycentrics b (sum 1) with sum b_i (X_i - x W_i) = sum b_i (Y_i - y W_i) = 0 are all
//! non-negative and the point is in front (w = sum b_i W_i > 0; every vertex has z = w / 2, so that
//! is also the near-plane test); see [`edge_functions`]. The same b are the
//! perspective-correct interpolation weights. Pixels within [`AMBIGUOUS_PX`] of an edge line
//! are not judged (vertices snap to 1/256 px and NDC is f32).

use glam::Vec4;
use realist::mesh::{Mesh, MeshData, NormalOptions, NormalPolicy};
use realist::raster::{
    self, Blend, Cull, DepthTest, Draw, DrawState, PerPixel, PixelShader, Stats, Target, TriInfo,
};
use realist::simd::KernelKind;

/// Distance from a pixel centre within which the reference decision is not enforced.
const AMBIGUOUS_PX: f64 = 0.02;

/// splitmix64 ([`realist_testkit::SplitMix`]) with ranges.
struct Rng(realist_testkit::SplitMix);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    fn unit(&mut self) -> f64 {
        self.0.unit_f64()
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// Outputs the interpolated attribute in red and 1 in green (the count).
struct Attr;

impl PixelShader for Attr {
    fn pixel(&self, _: TriInfo, v: &[f32]) -> Option<Vec4> {
        Some(Vec4::new(v[0], 1.0, 0.0, 0.0))
    }
}

fn state() -> DrawState {
    DrawState {
        cull: Cull::None,
        depth_test: DepthTest::Always,
        depth_write: true,
        blend: Blend::Add,
        ..DrawState::opaque()
    }
}

/// One triangle in clip space with one f32 attribute per vertex.
#[derive(Clone, Copy, Debug)]
struct Tri {
    clip: [[f64; 4]; 3],
    attr: [f32; 3],
}

/// Draws `tri` into a fresh `w` x `h` target with every kernel the machine has; checks
/// every buffer is finite, that the kernels cover identical pixels and interpolate the
/// attribute to the same bits (no fused multiply-add in any kernel), and returns the
/// portable kernel's (attribute sum, count) per pixel.
fn draw(tri: &Tri, w: u32, h: u32) -> Vec<(f32, f32)> {
    let mut first: Option<Vec<(f32, f32)>> = None;
    for kernel in KernelKind::available_kinds() {
        let got = draw_with(tri, w, h, kernel);
        match &first {
            None => first = Some(got),
            Some(f) => {
                for (a, b) in f.iter().zip(&got) {
                    assert_eq!(a.1, b.1, "{kernel:?} covers differently: {tri:?}");
                    assert_eq!(
                        a.0.to_bits(),
                        b.0.to_bits(),
                        "{kernel:?} attribute {} vs {}: {tri:?}",
                        b.0,
                        a.0
                    );
                }
            }
        }
    }
    first.unwrap_or_default()
}

fn draw_with(tri: &Tri, w: u32, h: u32, kernel: KernelKind) -> Vec<(f32, f32)> {
    let clip: Vec<Vec4> = tri
        .clip
        .iter()
        .map(|c| Vec4::new(c[0] as f32, c[1] as f32, c[2] as f32, c[3] as f32))
        .collect();
    let mut target = Target::new(w, h, Vec4::ZERO);
    let d = Draw {
        id: 0,
        sections: &[],
        clip: &clip,
        varyings: &tri.attr,
        stride: 1,
        triangles: &[[0, 1, 2]],
        state: state(),
    };
    let mut stats = Stats::default();
    raster::draw_with_kernel(&mut target, &[d], &PerPixel(Attr), &mut stats, kernel);
    let fb = target.resolve();
    assert!(
        fb.color.iter().all(|c| c.is_finite()),
        "non-finite colour for {tri:?}"
    );
    assert!(
        fb.depth
            .iter()
            .all(|d| d.is_finite() && (0.0..=1.0).contains(d)),
        "bad depth for {tri:?}"
    );
    fb.color.iter().map(|c| (c.x, c.y)).collect()
}

/// The three homogeneous edge functions at NDC point (x, y): n_k is linear in (x, y) (the
/// xy terms cancel), n_k / sum(n) are the clip-space (perspective-correct) barycentrics, and
/// sum(n_k W_k) is the constant det[X; Y; W] of the triangle, so the point is covered iff
/// every n_k has the sign of that determinant (which also puts it in front, w > 0).
fn edge_functions(t: &Tri, x: f64, y: f64) -> [f64; 3] {
    let a: Vec<[f64; 2]> = t
        .clip
        .iter()
        .map(|c| [c[0] - x * c[3], c[1] - y * c[3]])
        .collect();
    let cross = |i: usize, j: usize| a[i][0] * a[j][1] - a[j][0] * a[i][1];
    [cross(1, 2), cross(2, 0), cross(0, 1)]
}

fn orientation(t: &Tri) -> f64 {
    let [p, q, r] = t.clip;
    // det of rows X, Y, W over the vertices.
    p[0] * (q[1] * r[3] - r[1] * q[3]) - q[0] * (p[1] * r[3] - r[1] * p[3])
        + r[0] * (p[1] * q[3] - q[1] * p[3])
}

/// Clip-space barycentrics of NDC point (x, y), or None if degenerate there.
fn bary(t: &Tri, x: f64, y: f64) -> Option<[f64; 3]> {
    let n = edge_functions(t, x, y);
    let sum = n[0] + n[1] + n[2];
    (sum != 0.0 && sum.is_finite()).then(|| n.map(|v| v / sum))
}

/// The reference decision at pixel-space point (sx, sy) of a `w` x `h` image: `Some(true)`
/// or `Some(false)` if it holds for every point within [`AMBIGUOUS_PX`], `None` otherwise
/// (or for a degenerate triangle).
fn reference(t: &Tri, w: u32, h: u32, sx: f64, sy: f64) -> Option<bool> {
    let d = orientation(t);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let ndc = |sx: f64, sy: f64| (2.0 * sx / f64::from(w) - 1.0, 1.0 - 2.0 * sy / f64::from(h));
    let (x, y) = ndc(sx, sy);
    let n = edge_functions(t, x, y);
    let (x1, _) = ndc(sx + 1.0, sy);
    let (_, y1) = ndc(sx, sy + 1.0);
    let (nx, ny) = (edge_functions(t, x1, y), edge_functions(t, x, y1));
    // Signed distance in pixels to each edge line, positive inside.
    let dist: Vec<f64> = (0..3)
        .map(|k| {
            let g = libm::hypot(nx[k] - n[k], ny[k] - n[k]);
            if g > 0.0 {
                n[k] * d.signum() / g
            } else if n[k] * d.signum() >= 0.0 {
                f64::INFINITY
            } else {
                f64::NEG_INFINITY
            }
        })
        .collect();
    if dist.iter().any(|&v| v < -AMBIGUOUS_PX) {
        Some(false)
    } else if dist.iter().all(|&v| v > AMBIGUOUS_PX) {
        Some(true)
    } else {
        None
    }
}

/// Compares the rasterizer with the reference on every pixel; returns how many pixels were
/// judged. Attributes are checked where `check_attr` (to `attr_tol`).
fn check(t: &Tri, w: u32, h: u32, check_attr: bool, attr_tol: f32) -> usize {
    let got = draw(t, w, h);
    let mut judged = 0;
    for py in 0..h {
        for px in 0..w {
            let (c, n) = got[(py * w + px) as usize];
            assert!(
                n == 0.0 || n == 1.0,
                "pixel ({px}, {py}) written {n} times by one triangle {t:?}"
            );
            let (cx, cy) = (f64::from(px) + 0.5, f64::from(py) + 0.5);
            let Some(inside) = reference(t, w, h, cx, cy) else {
                continue;
            };
            judged += 1;
            assert_eq!(
                n == 1.0,
                inside,
                "pixel ({px}, {py}) of {w}x{h}: reference says covered={inside} for {t:?}"
            );
            if inside && check_attr {
                let (x, y) = (2.0 * cx / f64::from(w) - 1.0, 1.0 - 2.0 * cy / f64::from(h));
                let b = bary(t, x, y).unwrap();
                let want: f64 = (0..3).map(|i| b[i] * f64::from(t.attr[i])).sum();
                assert!(
                    (f64::from(c) - want).abs() <= f64::from(attr_tol),
                    "pixel ({px}, {py}): attribute {c} vs {want} for {t:?}"
                );
            }
        }
    }
    judged
}

/// A random triangle in pixel space (position, size from 0.1 to 3000 px), random w per
/// vertex, as clip coordinates for a `w` x `h` image.
fn random_tri(rng: &mut Rng, w: u32, h: u32) -> (Tri, f64) {
    let (fw, fh) = (f64::from(w), f64::from(h));
    let size = libm::pow(10f64, rng.range(-1.0, 3.5));
    let (cx, cy) = (
        rng.range(-0.3 * fw, 1.3 * fw),
        rng.range(-0.3 * fh, 1.3 * fh),
    );
    let pts: Vec<(f64, f64)> = (0..3)
        .map(|_| {
            (
                cx + size * rng.range(-1.0, 1.0),
                cy + size * rng.range(-1.0, 1.0),
            )
        })
        .collect();
    let mut clip = [[0.0; 4]; 3];
    for (i, &(x, y)) in pts.iter().enumerate() {
        let wv = rng.range(0.2, 5.0);
        let (nx, ny) = (2.0 * x / fw - 1.0, 1.0 - 2.0 * y / fh);
        clip[i] = [nx * wv, ny * wv, 0.5 * wv, wv];
    }
    let area = ((pts[1].0 - pts[0].0) * (pts[2].1 - pts[0].1)
        - (pts[2].0 - pts[0].0) * (pts[1].1 - pts[0].1))
        .abs()
        / 2.0;
    let longest = (0..3)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % 3]);
            libm::hypot(a.0 - b.0, a.1 - b.1)
        })
        .fold(0.0, f64::max);
    let min_altitude = if longest > 0.0 {
        2.0 * area / longest
    } else {
        0.0
    };
    let attr = [rng.unit() as f32, rng.unit() as f32, rng.unit() as f32];
    (Tri { clip, attr }, min_altitude)
}

#[test]
fn random_triangles_match_the_reference_coverage_and_interpolation() {
    let mut rng = Rng(realist_testkit::SplitMix(0x5EED_0001));
    let (mut tris, mut judged, mut attr_checked) = (0usize, 0usize, 0usize);
    // Odd sizes that straddle the 64 px tile border, and one full-HD-plus-one.
    for &(w, h, n) in &[
        (67u32, 45u32, 100_000usize),
        (131, 67, 8_000),
        (1921, 1081, 300),
    ] {
        for _ in 0..n {
            let (t, alt) = random_tri(&mut rng, w, h);
            // Interpolation is judged where snapping (1/512 px) moves weights by < 1e-3.
            let attr = alt >= 8.0;
            judged += check(&t, w, h, attr, 2e-3);
            attr_checked += usize::from(attr);
            tris += 1;
        }
    }
    println!("stability: {tris} random triangles, {judged} pixels judged against the f64 reference, attributes checked on {attr_checked} triangles");
    assert!(tris >= 100_000);
}

#[test]
fn triangles_crossing_w_zero_and_the_near_plane() {
    let mut rng = Rng(realist_testkit::SplitMix(0x5EED_0002));
    let (w, h) = (97u32, 61u32);
    let mut n = 0;
    for k in 0..4000 {
        let (mut t, _) = random_tri(&mut rng, w, h);
        // Push one or two vertices behind the eye (w <= 0), some exactly to w = 0, and some
        // to grazing: just behind the near plane.
        let behind = 1 + (k % 2);
        for v in t.clip.iter_mut().take(behind) {
            let wv = match k % 4 {
                0 => 0.0,
                1 => -rng.range(0.01, 10.0),
                2 => -1e-6,
                _ => rng.range(-1.0, 1.0),
            };
            let (nx, ny) = (v[0] / v[3], v[1] / v[3]);
            *v = [
                nx * wv.abs().max(1e-3) * if wv < 0.0 { -1.0 } else { 1.0 },
                ny * wv.abs().max(1e-3),
                0.5 * wv,
                wv,
            ];
        }
        check(&t, w, h, false, 0.0);
        n += 1;
    }
    println!("stability: {n} triangles crossing w = 0 (exactly, grazing at -1e-6, or behind) and the near plane: coverage matched the homogeneous reference");
}

#[test]
fn extreme_coordinates_never_panic_or_poison_buffers() {
    let mut rng = Rng(realist_testkit::SplitMix(0x5EED_0003));
    let (w, h) = (129u32, 67u32);
    let specials = [
        0.0,
        -0.0,
        1e-30,
        1e6,
        -1e6,
        1e30,
        -1e30,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        f64::MAX,
        f64::MIN_POSITIVE,
    ];
    let mut n = 0;
    for k in 0..20_000 {
        let (mut t, _) = random_tri(&mut rng, w, h);
        let v = (rng.next() % 3) as usize;
        let c = (rng.next() % 4) as usize;
        t.clip[v][c] = specials[k % specials.len()];
        if k % 7 == 0 {
            // A 16k-pixel needle, or a sliver that snaps to zero area.
            let len = if k % 2 == 0 { 16_384.0 } else { 1e-4 };
            t.clip[1] = [
                t.clip[0][0] + len / f64::from(w),
                t.clip[0][1] + 1e-7,
                t.clip[0][2],
                t.clip[0][3],
            ];
        }
        let got = draw(&t, w, h);
        assert!(got.iter().all(|&(_, n)| n == 0.0 || n == 1.0), "{t:?}");
        // Where the reference is defined (finite input, and z = w / 2 still holds, which
        // is what the reference's near-plane test assumes), coverage must match it.
        let defined = t
            .clip
            .iter()
            .all(|c| c.iter().all(|v| v.is_finite() && v.abs() <= 1e6) && c[2] == 0.5 * c[3]);
        if defined {
            check(&t, w, h, false, 0.0);
        }
        n += 1;
    }
    println!("stability: {n} triangles with extreme coordinates (0, 1e-30, 1e6, 1e30, inf, NaN, MAX, needles, slivers): no panic, finite buffers");
}

#[test]
fn coplanar_triangles_resolve_depth_deterministically() {
    // Two triangles in the same plane, drawn twice with GreaterEqual (reversed-Z) depth: the second pass
    // writes exactly where the first did (equal depths compare equal), 1 and 2 threads alike.
    let mut rng = Rng(realist_testkit::SplitMix(0x5EED_0004));
    let (w, h) = (83u32, 59u32);
    for _ in 0..500 {
        let (t, _) = random_tri(&mut rng, w, h);
        let clip: Vec<Vec4> = t
            .clip
            .iter()
            .map(|c| Vec4::new(c[0] as f32, c[1] as f32, c[2] as f32, c[3] as f32))
            .collect();
        let st = DrawState {
            depth_test: DepthTest::GreaterEqual,
            blend: Blend::Add,
            ..state()
        };
        let mut target = Target::new(w, h, Vec4::ZERO);
        let tris = [[0, 1, 2], [0, 1, 2]];
        let d = Draw {
            id: 0,
            sections: &[],
            clip: &clip,
            varyings: &t.attr,
            stride: 1,
            triangles: &tris,
            state: st,
        };
        raster::draw(&mut target, &[d], &PerPixel(Attr), &mut Stats::default());
        let fb = target.resolve();
        assert!(
            fb.color.iter().all(|c| c.y == 0.0 || c.y == 2.0),
            "coplanar duplicate not drawn twice everywhere: {t:?}"
        );
    }
    println!("stability: 500 coplanar duplicate pairs");
}

#[test]
fn averaged_normals_are_finite_and_unit_for_degenerate_meshes() {
    let mut rng = Rng(realist_testkit::SplitMix(0x5EED_0005));
    let mut cases = 0;
    for _ in 0..2_000 {
        let nv = 3 + (rng.next() % 12) as usize;
        let mut positions: Vec<glam::Vec3> = (0..nv)
            .map(|_| {
                glam::Vec3::new(
                    rng.range(-1.0, 1.0) as f32,
                    rng.range(-1.0, 1.0) as f32,
                    rng.range(-1.0, 1.0) as f32,
                )
            })
            .collect();
        // Duplicate positions and collinear points.
        positions[1] = positions[0];
        positions[2] = (positions[0] + positions[3 % nv]) * 0.5;
        let mut corners = Vec::new();
        for _ in 0..(2 + rng.next() % 20) {
            let mut f = [
                (rng.next() % nv as u64) as u32,
                (rng.next() % nv as u64) as u32,
                (rng.next() % nv as u64) as u32,
            ];
            if rng.next().is_multiple_of(3) {
                f.swap(1, 2); // inverted
            }
            corners.extend_from_slice(&f);
            if rng.next().is_multiple_of(4) {
                corners.extend_from_slice(&f); // duplicate facet
            }
        }
        let data = MeshData {
            name: "random".into(),
            positions,
            corners,
            ..MeshData::default()
        };
        for crease in [None, Some(30.0)] {
            let opts = NormalOptions {
                crease_degrees: crease,
                ..NormalOptions::default()
            };
            let mesh = Mesh::new(data.clone(), NormalPolicy::Average(opts)).unwrap();
            for n in &mesh.normals.values {
                assert!(
                    n.is_finite() && (n.length() - 1.0).abs() < 1e-4,
                    "normal {n} of {data:?}"
                );
            }
            cases += 1;
        }
    }
    println!("stability: {cases} random meshes with zero-area, duplicate and inverted facets: every normal finite and unit");
}
