//! Procedural textures: determinism, exact filtering (tiny footprints equal point samples,
//! wide ones the mean, any one the average of a dense supersampling), solid texture
//! periodicity, robustness, baking and names.

use glam::{Vec2, Vec3, Vec4};

use super::*;
use crate::noise::tests::points;

/// Largest difference between colours that should agree (float rounding).
const EPS: f32 = 1e-5;
/// Largest difference between a filtered value and the average of a 256 x 256 supersampling
/// (each of the few edges inside the footprint is placed to within 1/256 of its width).
const SUPERSAMPLE_TOL: f32 = 0.02;

fn tex(p: Procedural) -> ProceduralTexture {
    ProceduralTexture::new(p)
}

fn all_kinds() -> Vec<ProceduralTexture> {
    [
        Procedural::checker(8),
        Procedural::grid(8),
        Procedural::wood(),
        Procedural::marble(),
        Procedural::noise(5),
    ]
    .into_iter()
    .map(tex)
    .collect()
}

/// Random UVs in [-2, 2]^2 (from the shared deterministic point generator).
fn uvs(n: usize) -> impl Iterator<Item = Vec2> {
    points(n, 2.0).map(|p| p.truncate().as_vec2())
}

/// A footprint `w` UV units wide on both axes.
fn footprint(uv: Vec2, w: f32) -> SamplePoint {
    SamplePoint::uv_grad(uv, Vec2::new(w, 0.0), Vec2::new(0.0, w))
}

#[track_caller]
fn assert_close(a: Vec4, b: Vec4, tol: f32, what: &str) {
    let d = (a - b).abs().max_element();
    assert!(
        d <= tol,
        "{what}: {a} vs {b} (difference {d}, tolerance {tol})"
    );
}

fn linear(c: [f32; 3]) -> Vec4 {
    Vec3::from_array(c.map(srgb_to_linear)).extend(1.0)
}

#[test]
fn every_kind_is_deterministic() {
    for t in all_kinds() {
        for p in points(500, 3.0) {
            let s = SamplePoint {
                uv: p.truncate().as_vec2(),
                duv_dx: Vec2::new(0.01, 0.0),
                duv_dy: Vec2::new(0.0, 0.02),
                position: p.as_vec3(),
                width: 0.01,
            };
            let (a, b) = (t.color(&s), t.clone().color(&s));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits)
            );
            assert_eq!(t.height(&s).to_bits(), t.height(&s).to_bits());
        }
    }
}

#[test]
fn checker_squares_and_designed_colours() {
    let t = tex(Procedural::checker(8));
    let (a, b) = (linear([0.9; 3]), linear([0.15; 3]));
    let at = |u: f32, v: f32| t.color(&SamplePoint::uv(Vec2::new(u, v)));
    assert_close(at(0.01, 0.01), a, EPS, "top-left square is a");
    assert_close(at(0.13, 0.01), b, EPS, "its right neighbour is b");
    assert_close(at(0.13, 0.13), a, EPS, "diagonal neighbour is a");
    assert_close(at(-0.01, 0.01), b, EPS, "repeats leftwards");
    assert_close(at(1.01, 2.01), a, EPS, "repeats per unit of UV");
}

#[test]
fn tiny_footprints_equal_point_samples() {
    for t in [tex(Procedural::checker(8)), tex(Procedural::grid(8))] {
        let n = match t.source() {
            Procedural::Checker { n, .. } => *n,
            _ => 8,
        } as f32;
        for uv in uvs(5000) {
            let point = t.color(&SamplePoint::uv(uv));
            let filtered = t.color(&footprint(uv, 1e-6));
            // Within a thousandth of a cell of an edge the footprint may straddle it.
            let f = (uv * n).fract().abs();
            let near_edge = f.min(1.0 - f).min_element() < 1e-3;
            if !near_edge {
                assert_close(
                    filtered,
                    point,
                    1e-4,
                    &format!("{} at {uv}", t.source().name()),
                );
            }
        }
    }
}

/// The exact box-filtered checker differs from the mean by at most `0.5 / w^2` (w in
/// squares): each axis by at most `0.5 / w`, and the checker is their product.
#[test]
fn filtered_checker_tends_to_the_mean() {
    let t = tex(Procedural::checker(8));
    let (a, b) = (linear([0.9; 3]), linear([0.15; 3]));
    let mean = 0.5 * (a + b);
    for squares in [1.5f32, 3.7, 10.3, 64.9, 1000.1] {
        let w = squares / 8.0;
        for uv in uvs(300) {
            let c = t.color(&footprint(uv, w));
            let bound = 0.5 / (squares * squares) * (a - b).abs().max_element();
            assert_close(c, mean, bound + EPS, &format!("{squares} squares at {uv}"));
        }
    }
    for w in [f32::INFINITY, 1e30] {
        assert_close(
            t.color(&footprint(Vec2::splat(0.3), w)),
            mean,
            EPS,
            "huge footprint",
        );
    }
}

/// The mean of `t` over the footprint box by dense point sampling.
fn supersampled(t: &ProceduralTexture, uv: Vec2, w: Vec2) -> Vec4 {
    const K: usize = 256;
    let mut sum = Vec4::ZERO;
    for j in 0..K {
        for i in 0..K {
            let o = (Vec2::new(i as f32, j as f32) + 0.5) / K as f32 - 0.5;
            sum += t.color(&SamplePoint::uv(uv + o * w));
        }
    }
    sum / (K * K) as f32
}

#[test]
fn box_filter_matches_supersampling() {
    for t in [tex(Procedural::checker(4)), tex(Procedural::grid(8))] {
        for (k, uv) in uvs(12).enumerate() {
            let w = Vec2::new(0.02 + 0.09 * k as f32, 0.03 + 0.05 * (11 - k) as f32);
            let s = SamplePoint::uv_grad(uv, Vec2::new(w.x, 0.0), Vec2::new(0.0, w.y));
            let (exact, brute) = (t.color(&s), supersampled(&t, uv, w));
            assert_close(
                exact,
                brute,
                SUPERSAMPLE_TOL,
                &format!("{} {uv} {w}", t.source().name()),
            );
        }
    }
}

#[test]
fn grid_shows_columns_rows_lines_and_an_f() {
    let t = tex(Procedural::grid(4));
    let at = |u: f32, v: f32| t.color(&SamplePoint::uv(Vec2::new(u, v) / 4.0));
    // Cell (0, 0) and (1, 0): different hues; (0, 0) and (0, 1): same hue, darker below.
    let (c00, c10, c01) = (at(0.1, 0.9), at(1.1, 0.9), at(0.1, 1.9));
    assert!((c00 - c10).abs().max_element() > 0.1, "{c00} {c10}");
    let ratio = c01.truncate() / c00.truncate();
    assert!(
        ratio.max_element() - ratio.min_element() < 1e-3,
        "same hue: {ratio}"
    );
    assert!(ratio.x < 0.9, "lower rows are darker: {ratio}");
    // Lines on cell edges are dark; the F's stem, top bar and middle bar are white.
    assert!(at(1.0, 0.5).truncate().max_element() < 0.01, "line");
    let white = Vec4::ONE;
    for (u, v) in [(0.36, 0.5), (0.6, 0.28), (0.5, 0.5)] {
        assert_close(at(u, v), white, EPS, &format!("F at {u}, {v}"));
    }
    // The F is not symmetric: its mirror images and turns are cell colour.
    for (u, v) in [(0.64, 0.5), (0.28, 0.6), (0.5, 0.64), (0.6, 0.72)] {
        assert!(at(u, v).truncate().min_element() < 0.9, "no F at {u}, {v}");
    }
    assert_eq!(t.height(&SamplePoint::uv(Vec2::new(0.1, 0.9) / 4.0)), 1.0);
    assert_eq!(t.height(&SamplePoint::uv(Vec2::new(0.36, 0.5) / 4.0)), 0.0);
}

#[test]
fn filtered_grid_tends_to_its_mean() {
    let t = tex(Procedural::grid(8));
    let mean = supersampled(&t, Vec2::splat(0.5), Vec2::ONE);
    for w in [8.0, 64.0, f32::INFINITY] {
        for uv in uvs(50) {
            assert_close(
                t.color(&footprint(uv, w)),
                mean,
                0.5 / w + SUPERSAMPLE_TOL,
                "grid",
            );
        }
    }
}

#[test]
fn wood_rings_are_radially_periodic() {
    let rings = 8.0;
    let t = tex(Procedural::Wood {
        rings,
        wobble: 0.0,
        light: [0.9; 3],
        dark: [0.1; 3],
    });
    let h = |p: Vec3| t.height(&SamplePoint::position(p, 0.0));
    for p in points(500, 2.0) {
        let p = p.as_vec3();
        let radial = Vec3::new(p.x, 0.0, p.z).normalize_or(Vec3::X);
        let next = p + radial / rings;
        assert!(
            (h(p) - h(next)).abs() < 1e-4,
            "{p}: {} vs {}",
            h(p),
            h(next)
        );
        // The pattern does not depend on height along the axis.
        assert!((h(p) - h(p + 3.0 * Vec3::Y)).abs() < 1e-5);
    }
    assert!(h(Vec3::ZERO) < EPS, "light at the centre");
    assert!(
        (h(Vec3::new(0.5 / rings, 0.0, 0.0)) - 1.0).abs() < EPS,
        "dark half a ring out"
    );
    // The gradient points along the radius.
    // A quarter ring out, where the rings are steepest.
    let g = t.height_gradient(&SamplePoint::position(
        Vec3::new(0.15, 0.7, 0.2) / rings,
        0.0,
    ));
    assert!(g.y.abs() < 1e-3 && (g.x / g.z - 0.75).abs() < 1e-2, "{g}");
}

#[test]
fn marble_bands_repeat_along_x() {
    let t = tex(Procedural::Marble {
        frequency: 2.0,
        turbulence: 0.0,
        base: [0.9; 3],
        vein: [0.1; 3],
    });
    let h = |p: Vec3| t.height(&SamplePoint::position(p, 0.0));
    for p in points(300, 2.0) {
        let p = p.as_vec3();
        assert!((h(p) - h(p + Vec3::X * 0.5)).abs() < 1e-4);
        assert!((h(p) - h(p + Vec3::new(0.0, 1.3, -0.7))).abs() < 1e-5);
    }
}

#[test]
fn solid_textures_fade_to_their_mean_when_minified() {
    for t in all_kinds()
        .into_iter()
        .filter(|t| t.domain() == Domain::Object)
    {
        let mean = t.color(&SamplePoint::position(Vec3::NAN, 0.0));
        for p in points(100, 2.0) {
            let s = SamplePoint::position(p.as_vec3(), 50.0);
            assert_close(t.color(&s), mean, 1e-3, t.source().name());
            let mean_height = t.height(&SamplePoint::position(Vec3::NAN, 0.0));
            assert!((t.height(&s) - mean_height).abs() < 1e-3);
        }
        // Contrast drops monotonically with the footprint.
        let spread = |w: f32| {
            let hs: Vec<f32> = points(2000, 1.0)
                .map(|p| t.height(&SamplePoint::position(p.as_vec3(), w)))
                .collect();
            let m = hs.iter().sum::<f32>() / hs.len() as f32;
            hs.iter().map(|h| (h - m).powi(2)).sum::<f32>() / hs.len() as f32
        };
        let (v0, v1, v2) = (spread(0.0), spread(0.05), spread(0.3));
        assert!(v0 > v1 && v1 > v2, "{}: {v0} {v1} {v2}", t.source().name());
    }
}

#[test]
fn no_nan_or_inf_from_any_input() {
    let weird = [
        0.0,
        -0.0,
        1e-30,
        1e30,
        -1e30,
        f32::MAX,
        f32::MIN,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ];
    let mut kinds = all_kinds();
    kinds.push(tex(Procedural::Checker {
        n: 0,
        a: [f32::NAN; 3],
        b: [2.0, -1.0, 0.5],
    }));
    kinds.push(tex(Procedural::Grid { cells: 1000 }));
    kinds.push(tex(Procedural::Wood {
        rings: f32::NAN,
        wobble: f32::INFINITY,
        light: [0.5; 3],
        dark: [0.5; 3],
    }));
    kinds.push(tex(Procedural::Marble {
        frequency: -1.0,
        turbulence: f32::NAN,
        base: [1.0; 3],
        vein: [0.0; 3],
    }));
    kinds.push(tex(Procedural::Noise {
        frequency: f32::INFINITY,
        octaves: 0,
        low: [0.0; 3],
        high: [1.0; 3],
    }));
    for t in &kinds {
        for &a in &weird {
            for &w in &weird {
                let s = SamplePoint {
                    uv: Vec2::new(a, 0.3),
                    duv_dx: Vec2::new(w, 0.0),
                    duv_dy: Vec2::new(0.0, w),
                    position: Vec3::new(0.2, a, -0.4),
                    width: w,
                };
                let c = t.color(&s);
                assert!(
                    c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0,
                    "{t:?} {s:?}: {c}"
                );
                let h = t.height(&s);
                assert!((0.0..=1.0).contains(&h), "{s:?}: {h}");
                assert!(t.height_gradient(&s).is_finite(), "{s:?}");
            }
        }
    }
}

#[test]
fn bake_encodes_srgb_and_antialiases() {
    let t = tex(Procedural::checker(8));
    let img = t.bake(64, 32);
    assert_eq!((img.width, img.height, img.texels.len()), (64, 32, 64 * 32));
    // Texel (2, 1) lies inside square (0, 0): the designed sRGB 0.9.
    let [r, g, b, a] = img.texels[64 + 2];
    assert!((f32::from(r) - 0.9 * 255.0).abs() <= 1.0 && r == g && g == b && a == 255);
    assert_eq!(t.bake(0, 10).texels.len(), 0);
    assert_eq!(t.bake(MAX_BAKE + 5, 1).width, MAX_BAKE);
    // Minified: 512 squares across 64 texels, every texel the linear mean.
    let fine = tex(Procedural::checker(512)).bake(64, 64);
    let mean = linear_to_srgb(0.5 * (srgb_to_linear(0.9) + srgb_to_linear(0.15)));
    for texel in &fine.texels {
        assert!(
            (f32::from(texel[0]) - mean * 255.0).abs() <= 1.0,
            "{texel:?}"
        );
    }
    for t in all_kinds() {
        assert_eq!(t.bake(16, 8), t.bake(16, 8), "{}", t.source().name());
    }
}

#[test]
fn names_parse_with_defaults_and_errors_list_options() {
    for name in PROCEDURAL_NAMES {
        let p: Procedural = name.parse().unwrap();
        assert_eq!(p.name(), name);
    }
    assert_eq!("Checker:16".parse(), Ok(Procedural::checker(16)));
    assert_eq!(" grid:4 ".parse(), Ok(Procedural::grid(4)));
    assert_eq!("noise:3".parse(), Ok(Procedural::noise(3)));
    let err = "brick".parse::<Procedural>().unwrap_err().to_string();
    assert!(
        err.contains("checker[:N]") && err.contains("marble"),
        "{err}"
    );
    for bad in ["grid:0", "grid:99", "checker:x", "noise:-1"] {
        let err = bad.parse::<Procedural>().unwrap_err();
        assert!(
            matches!(err, ParseProceduralError::Count { .. }),
            "{bad}: {err}"
        );
    }
    assert!("wood:3".parse::<Procedural>().is_err());
    // Domains.
    let domains: Vec<Domain> = all_kinds().iter().map(ProceduralTexture::domain).collect();
    assert_eq!(
        domains,
        [
            Domain::Uv,
            Domain::Uv,
            Domain::Object,
            Domain::Object,
            Domain::Object
        ]
    );
}
