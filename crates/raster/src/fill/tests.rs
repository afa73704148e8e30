use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::simd::kernel::__private::Portable;
use crate::simd::F8;

type P = F8<Portable>;
use crate::{
    draw, Batch, Colors, Cull, Draw, DrawState, FragmentShader, PerPixel, PixelShader, Stats,
    Target, TriInfo,
};
use realist_scene::Camera;

/// Outputs the interpolated varying (alpha 1 marks coverage).
struct Value;

impl PixelShader for Value {
    fn pixel(&self, _: TriInfo, v: &[f32]) -> Option<Vec4> {
        Some(Vec4::new(v[0], v[1], 0.0, 1.0))
    }
}

/// Outputs the varying's derivatives (dx.x, dx.y, dy.x, dy.y).
struct Derivatives;

impl FragmentShader for Derivatives {
    fn derivatives(&self, _: u32) -> Option<(usize, usize)> {
        Some((0, 2))
    }
    fn shade(&self, b: &mut Batch) {
        assert_eq!(b.derivatives, 2);
        for g in 0..b.len {
            b.out[g] = Colors {
                r: b.ddx[g][0],
                g: b.ddx[g][1],
                b: b.ddy[g][0],
                a: b.ddy[g][1],
            };
        }
    }
}

const W: u32 = 96;
const H: u32 = 72;

fn render<S: FragmentShader>(clip: &[Vec4], var: &[Vec2], shader: &S) -> (Vec<Vec4>, Stats) {
    let flat: Vec<f32> = var.iter().flat_map(|v| [v.x, v.y]).collect();
    let mut target = Target::new(W, H, Vec4::ZERO);
    let mut stats = Stats::default();
    let d = Draw {
        id: 0,
        sections: &[],
        clip,
        varyings: &flat,
        stride: 2,
        triangles: &[[0, 1, 2]],
        state: DrawState {
            cull: Cull::None,
            ..DrawState::opaque()
        },
    };
    draw(&mut target, &[d], shader, &mut stats);
    (target.resolve().color, stats)
}

/// Compares the analytic derivatives with central differences of the rendered varying
/// at every pixel whose four neighbours are covered; returns (pixels checked, worst
/// error relative to the derivative's size).
fn check(clip: &[Vec4], var: &[Vec2]) -> (usize, f32, Stats) {
    let (value, stats) = render(clip, var, &PerPixel(Value));
    let (grad, _) = render(clip, var, &Derivatives);
    let at = |x: u32, y: u32| value[(y * W + x) as usize];
    let (mut n, mut worst) = (0, 0f32);
    for y in 1..H - 1 {
        for x in 1..W - 1 {
            let nb = [at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)];
            if at(x, y).w != 1.0 || nb.iter().any(|c| c.w != 1.0) {
                continue;
            }
            let fdx = (nb[1] - nb[0]).truncate().truncate() * 0.5;
            let fdy = (nb[3] - nb[2]).truncate().truncate() * 0.5;
            let g = grad[(y * W + x) as usize];
            let (gx, gy) = (Vec2::new(g.x, g.y), Vec2::new(g.z, g.w));
            for (fd, an) in [(fdx, gx), (fdy, gy)] {
                let scale = an.length().max(1e-3);
                worst = worst.max((fd - an).length() / scale);
            }
            n += 1;
        }
    }
    (n, worst, stats)
}

fn camera_mvp() -> Mat4 {
    // Looking down at a floor, yawed and rolled: 1/w varies strongly along both x and y.
    let cam = Camera {
        eye: Vec3::new(0.0, 1.0, 0.0),
        target: Vec3::new(0.5, 0.0, -1.6),
        up: Vec3::new(0.4, 1.0, 0.0),
        yfov: 60f32.to_radians(),
        near: 0.05,
        ..Camera::default()
    };
    cam.projection(W as f32 / H as f32) * cam.view()
}

/// A non-finite vertex in a triangle that needs clipping (another vertex far outside
/// the guard band and behind the eye) is culled as degenerate, whichever vertex it is,
/// and draws nothing; so is one whose other vertices are inside.
#[test]
fn a_non_finite_vertex_culls_its_triangle_on_every_path() {
    let good = [
        Vec4::new(-0.5, -0.5, 0.5, 1.0),
        Vec4::new(0.5, -0.5, 0.5, 1.0),
    ];
    let far = Vec4::new(1e6, 0.2, 0.5, 1.0);
    let behind = Vec4::new(0.1, 0.2, 0.5, -1.0);
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let nan = Vec4::new(bad, 0.0, 0.5, 1.0);
        for tri in [
            [nan, far, behind],
            [far, nan, good[0]],
            [good[0], behind, nan],
            [good[0], good[1], nan],
        ] {
            let (image, stats) = render(&tri, &[Vec2::ZERO; 3], &PerPixel(Value));
            assert_eq!(stats.culled_degenerate, 1, "{tri:?}");
            assert_eq!((stats.drawn, stats.clipped), (0, 0), "{tri:?}");
            assert!(image.iter().all(|c| *c == Vec4::ZERO), "{tri:?}");
        }
    }
}

#[test]
fn analytic_derivatives_match_central_differences() {
    let mvp = camera_mvp();
    let world = [
        Vec3::new(-3.0, 0.0, -1.0),
        Vec3::new(2.5, 0.0, -0.6),
        Vec3::new(0.3, 0.0, -9.0),
    ];
    let clip: Vec<Vec4> = world.iter().map(|p| mvp * p.extend(1.0)).collect();
    let var: Vec<Vec2> = world
        .iter()
        .map(|p| Vec2::new(p.x * 3.0, p.z * 2.0))
        .collect();
    let (n, worst, stats) = check(&clip, &var);
    eprintln!("unclipped: {n} pixels, worst relative error {worst}");
    assert_eq!(stats.clipped, 0);
    assert!(n > 1000, "{n} pixels");
    // Central differences of the rational varying are exact to second order; the
    // affine (not perspective-correct) derivative is off by far more.
    assert!(worst < 0.02, "worst relative error {worst} over {n} pixels");
}

#[test]
fn clipped_pieces_get_the_derivatives_of_the_whole_triangle() {
    // The floor triangle reaches behind the eye: near-plane clipping cuts it into
    // pieces, each set up with its own (clip-space interpolated) vertices.
    let mvp = camera_mvp();
    let world = [
        Vec3::new(-1.0, 0.0, 3.0),
        Vec3::new(4.0, 0.0, -1.2),
        Vec3::new(-2.5, 0.0, -7.0),
    ];
    let clip: Vec<Vec4> = world.iter().map(|p| mvp * p.extend(1.0)).collect();
    assert!(
        clip[0].w < 0.0 && clip[1].w > 0.0 && clip[2].w > 0.0,
        "{clip:?}"
    );
    let var: Vec<Vec2> = world
        .iter()
        .map(|p| Vec2::new(p.x * 3.0, p.z * 2.0))
        .collect();
    let (n, worst, stats) = check(&clip, &var);
    eprintln!("clipped: {n} pixels, worst relative error {worst}, {stats:?}");
    assert_eq!(stats.clipped, 1);
    assert!(stats.drawn >= 2, "{stats:?}");
    assert!(n > 1000, "{n} pixels");
    assert!(worst < 0.02, "worst relative error {worst} over {n} pixels");
}

/// A lane shader with a nonlinear colour of its varyings, their derivatives and the
/// facing, deferred or not.
struct Wavy {
    pack: bool,
}

impl FragmentShader for Wavy {
    fn derivatives(&self, _: u32) -> Option<(usize, usize)> {
        Some((0, 2))
    }
    fn defers(&self, _: u32) -> bool {
        self.pack
    }
    fn discards(&self, _: u32) -> bool {
        false
    }
    fn shade(&self, b: &mut Batch) {
        let side = if b.front { 1.0 } else { 0.5 };
        for g in 0..b.len {
            let (u, v): (P, P) = (b.var[g][0].get(), b.var[g][1].get());
            let (dx, dy): (P, P) = (b.ddx[g][0].get(), b.ddy[g][1].get());
            b.out[g] = Colors::of(
                (u * P::splat(7.0) + v).map(libm::sinf),
                (dx * P::splat(31.0)).map(libm::cosf) * side,
                dy * P::splat(13.0) + P::splat(b.draw as f32),
                (u * v).sqrt(),
            );
        }
    }
}

/// Deferring fragments to the tile's end and packing them across rows, triangles and
/// draws changes no pixel: thousands of small triangles of two draws, both facings, in
/// perspective and overlapping in depth, render bit for bit as shaded in order, with
/// each covered pixel shaded once and far fewer shader calls.
#[test]
fn deferred_shading_gives_the_forward_image() {
    let mut seed = 0x2545_f491_u32;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f32 / u32::MAX as f32
    };
    let (mut clip, mut var) = (Vec::new(), Vec::new());
    for t in 0..6000 {
        let (cx, cy, w) = (rnd() * 2.2 - 1.1, rnd() * 2.2 - 1.1, 0.5 + rnd() * 3.0);
        let z = rnd() * 0.8 + 0.1;
        // Counter-clockwise around the centre (front-facing), one in ten clockwise.
        let turn = if t % 10 == 0 { -1.0 } else { 1.0 };
        for k in 0..3 {
            let a = turn * (k as f32 + rnd() * 0.5) * std::f32::consts::TAU / 3.0;
            // Mostly small (rows with a lane or two), some large (full rows, shaded
            // as they are unless a packed fragment shares their pixels).
            let r = if t % 7 == 0 {
                0.1 + rnd() * 0.3
            } else {
                0.02 + rnd() * 0.05
            };
            let (x, y) = (cx + r * libm::cosf(a), cy + r * libm::sinf(a));
            clip.push(Vec4::new(x * w, y * w, z * w, w));
            var.extend([rnd() * 4.0, rnd() * 4.0]);
        }
    }
    let tris: Vec<[u32; 3]> = (0..clip.len() as u32 / 3)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    let (a, b) = tris.split_at(tris.len() / 2);
    let state = DrawState {
        cull: Cull::None,
        ..DrawState::opaque()
    };
    let draw_with = |shader: &Wavy| {
        let mut target = Target::new(W, H, Vec4::ZERO);
        let mut stats = Stats::default();
        let draws = [a, b, a].map(|t| Draw {
            id: if std::ptr::eq(t, b) { 1 } else { 0 },
            sections: &[],
            clip: &clip,
            varyings: &var,
            stride: 2,
            triangles: t,
            state,
        });
        draw(&mut target, &draws, shader, &mut stats);
        (target.resolve().color, stats)
    };
    let (packed, ps) = draw_with(&Wavy { pack: true });
    let (plain, us) = draw_with(&Wavy { pack: false });
    let bits = |c: &[Vec4]| -> Vec<[u32; 4]> {
        c.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
    };
    let covered = plain.iter().filter(|c| c.w != 0.0).count();
    assert!(covered > (W * H / 2) as usize, "{covered} pixels covered");
    assert!(
        bits(&packed) == bits(&plain),
        "deferred and forward images differ"
    );
    // Every covered pixel once (no lane of this shader's alpha is 0 where drawn), where
    // the forward fill shaded every fragment that passed the depth test.
    assert_eq!(ps.pixels_shaded, covered as u64);
    assert!(us.pixels_shaded > ps.pixels_shaded * 5 / 4, "{ps:?} {us:?}");
    eprintln!(
        "{} pixels shaded in {} deferred calls; forward {} in {}",
        ps.pixels_shaded, ps.shader_calls, us.pixels_shaded, us.shader_calls
    );
    // Groups are aligned rows of eight pixels, filled with every visible fragment of
    // one draw and facing that lies in them (not compacted across rows): on these tiny
    // triangles 0.56 of their lanes are in use, against 0.38 when each triangle's rows
    // are shaded on their own (the forward run here).
    let lanes = ps.pixels_shaded as f64 / (8 * ps.shader_calls) as f64;
    assert!(lanes > 0.5, "lanes in use: {lanes}, {ps:?}");
    assert!(ps.shader_calls * 2 < us.shader_calls, "{ps:?} {us:?}");
}

/// `facing_varyings`: set-up keeps the front half of the varyings for a front-facing
/// triangle and the back half for a back-facing one.
#[test]
fn facing_varyings_keep_the_side_shown() {
    struct Rgba;
    impl PixelShader for Rgba {
        fn pixel(&self, _: TriInfo, v: &[f32]) -> Option<Vec4> {
            assert_eq!(v.len(), 4);
            Some(Vec4::new(v[0], v[1], v[2], v[3]))
        }
    }
    let front = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0];
    let var: Vec<f32> = (0..3).flat_map(|_| front).collect();
    let ccw = [
        Vec4::new(-0.8, -0.8, 0.5, 1.0),
        Vec4::new(0.8, -0.8, 0.5, 1.0),
        Vec4::new(0.0, 0.8, 0.5, 1.0),
    ];
    for (tris, want) in [
        ([[0u32, 1, 2]], Vec4::X.with_w(1.0)),
        ([[0, 2, 1]], Vec4::Z.with_w(1.0)),
    ] {
        let mut target = Target::new(W, H, Vec4::ZERO);
        let d = Draw {
            id: 0,
            sections: &[],
            clip: &ccw,
            varyings: &var,
            stride: 8,
            triangles: &tris,
            state: DrawState {
                cull: Cull::None,
                facing_varyings: true,
                ..DrawState::opaque()
            },
        };
        draw(&mut target, &[d], &PerPixel(Rgba), &mut Stats::default());
        let c = target.resolve().pixel(W / 2, H / 2);
        assert_eq!(c, want, "{tris:?}");
    }
}
