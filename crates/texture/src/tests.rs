use super::*;

#[test]
fn srgb_round_trip() {
    for i in 0..=255 {
        let c = i as f32 / 255.0;
        assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-5);
    }
}

#[test]
fn wrap_modes() {
    assert_eq!(wrap_index(-1.0, 4, Wrap::Repeat), 3);
    assert_eq!(wrap_index(5.0, 4, Wrap::Repeat), 1);
    assert_eq!(wrap_index(-1.0, 4, Wrap::ClampToEdge), 0);
    assert_eq!(wrap_index(4.0, 4, Wrap::MirroredRepeat), 3);
    assert_eq!(wrap_index(-1.0, 4, Wrap::MirroredRepeat), 0);
    assert_eq!(wrap_index(1e30, 4, Wrap::Repeat), 0);
}

#[test]
fn huge_uvs_sample_finite_colours() {
    let t = Texture::checker(256, 8, [255, 0, 0, 255], [0, 0, 255, 255]);
    for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
        for filter in [Filter::Nearest, Filter::Bilinear] {
            let s = Sampler {
                wrap_u: wrap,
                wrap_v: wrap,
                filter,
            };
            for uv in [
                Vec2::new(1.0, -1.7e38),
                Vec2::new(3e38, 0.5),
                Vec2::new(-1e20, 1e20),
                Vec2::new(f32::NAN, 0.0),
            ] {
                assert!(t.sample_with(uv, s).is_finite(), "{wrap:?} {filter:?} {uv}");
            }
        }
    }
    // Reduction keeps what a wrap mode samples.
    let s = Sampler {
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Nearest,
    };
    assert_eq!(
        t.sample_with(Vec2::new(0.3, 0.7), s),
        t.sample_with(Vec2::new(5.3, -2.3), s)
    );
}

#[test]
fn uvs_near_1e5_keep_their_texel() {
    // f32 spacing at 1e5 is 1/128, so a UV there is known to 1/256; a texel centre of a
    // 100-texel map (texels 1/100 wide) is still resolved. Nearest sampling at
    // u = 1e5 + centre must give the texel of the centre itself: folding the UV before
    // scaling keeps it (scaling first puts u * 100 = 1e7 where f32 spacing is 1).
    let n = 100;
    let texels: Vec<[u8; 4]> = (0..n * n)
        .map(|i| [(i % n) as u8, (i / n) as u8, 0, 255])
        .collect();
    let t = Texture::new("ramp", n, n, texels, false).unwrap();
    let mut tried = 0;
    for wrap in [Wrap::Repeat, Wrap::MirroredRepeat] {
        let s = Sampler {
            wrap_u: wrap,
            wrap_v: wrap,
            filter: Filter::Nearest,
        };
        for k in 0..n {
            let f = (k as f32 + 0.5) / n as f32;
            let near = t.sample_with(Vec2::new(f, f), s);
            // 1e5 is even, so mirrored repeat also maps it back onto [0, 1).
            let far = t.sample_with(Vec2::new(1e5 + f, 1e5 + f), s);
            assert_eq!(near, far, "{wrap:?} texel {k}");
            tried += 1;
        }
    }
    assert_eq!(tried, 200);
}

#[test]
fn bilinear_between_texels() {
    let t = Texture::new("t", 2, 1, vec![[0, 0, 0, 255], [255, 255, 255, 255]], false).unwrap();
    let s = Sampler {
        wrap_u: Wrap::ClampToEdge,
        wrap_v: Wrap::ClampToEdge,
        filter: Filter::Bilinear,
    };
    let mid = t.sample_with(Vec2::new(0.5, 0.5), s);
    assert!((mid.x - 0.5).abs() < 1e-6, "{mid}");
}

/// Deterministic pseudo-random texels (splitmix64).
fn noise(name: &str, w: u32, h: u32, srgb: bool, seed: u64) -> Texture {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as u8
    };
    let texels = (0..w * h)
        .map(|_| [next(), next(), next(), next()])
        .collect();
    Texture::new(name, w, h, texels, srgb).unwrap()
}

fn level_mean(t: &Texture, level: usize) -> glam::DVec4 {
    let (w, h) = t.level_size(level);
    let mut sum = glam::DVec4::ZERO;
    for y in 0..h {
        for x in 0..w {
            sum += t.fetch_level(level, x, y).as_dvec4();
        }
    }
    sum / f64::from(w * h)
}

#[test]
fn every_mip_level_keeps_the_mean_in_linear_light() {
    let mut checked = 0;
    for (w, h) in [
        (64, 64),
        (37, 20),
        (20, 37),
        (1, 37),
        (37, 1),
        (5, 3),
        (2, 1),
    ] {
        for srgb in [true, false] {
            let t = noise("noise", w, h, srgb, u64::from(w * 1000 + h));
            let base = level_mean(&t, 0);
            let (mut lw, mut lh) = (w, h);
            for level in 1..t.levels() {
                (lw, lh) = ((lw / 2).max(1), (lh / 2).max(1));
                assert_eq!(t.level_size(level), (lw, lh), "{w}x{h} level {level}");
                let m = level_mean(&t, level);
                // 16-bit levels: a rounding of at most 2^-17 per level.
                let err = (m - base).abs().max_element();
                assert!(
                    err < 2e-5,
                    "{w}x{h} srgb {srgb} level {level}: {m} vs {base}"
                );
                checked += 1;
            }
            assert_eq!(t.level_size(t.levels() - 1), (1, 1), "{w}x{h}");
        }
    }
    assert_eq!(checked, 2 * (6 + 5 + 5 + 5 + 5 + 2 + 1));
}

#[test]
fn odd_sizes_weigh_every_texel_by_its_area() {
    // 3 -> 1: the mean of the three texels (a 2-tap filter would drop one).
    let t = Texture::new(
        "t",
        3,
        1,
        vec![[0, 0, 0, 0], [30, 60, 90, 120], [255, 255, 255, 255]],
        false,
    )
    .unwrap();
    let want = Vec4::new(285.0, 315.0, 345.0, 375.0) / (3.0 * 255.0);
    let got = t.fetch_level(1, 0, 0);
    assert!((got - want).abs().max_element() < 1e-4, "{got} vs {want}");
    // 5 -> 2: weights (2, 2, 1) / 5 and (1, 2, 2) / 5.
    let v = [0u8, 50, 100, 150, 250];
    let t = Texture::new(
        "t",
        5,
        1,
        v.iter().map(|&c| [c, c, c, 255]).collect(),
        false,
    )
    .unwrap();
    let l = |x| t.fetch_level(1, x, 0).x * 255.0;
    assert!((l(0) - 40.0).abs() < 0.01, "{}", l(0));
    assert!((l(1) - 180.0).abs() < 0.01, "{}", l(1));
}

#[test]
fn levels_are_filtered_in_linear_light() {
    // Black and white sRGB texels average to 0.5 in linear light (sRGB 188, not 128).
    let t = Texture::checker(2, 2, [0, 0, 0, 255], [255, 255, 255, 255]);
    let m = t.fetch_level(1, 0, 0);
    assert!(
        (m - Vec4::new(0.5, 0.5, 0.5, 1.0)).abs().max_element() < 1e-4,
        "{m}"
    );
    // sRGB 0 and 128: linear 0 and 0.2158, mean 0.1079 (averaging the codes would give
    // 0.0513 decoded, or 0.251 taken as linear).
    let t = Texture::checker(2, 2, [0, 0, 0, 255], [128, 128, 128, 255]);
    let want = srgb_to_linear(128.0 / 255.0) / 2.0;
    let m = t.fetch_level(1, 0, 0);
    assert!(
        (m.x - want).abs() < 1e-4 && (want - 0.1079).abs() < 1e-4,
        "{m}"
    );
    // Linear data is averaged as stored.
    let t = t.as_slot_wants(false).expect("re-labelled as linear"); // without a chain
    assert!((t.fetch_level(1, 0, 0).x - 64.0 / 255.0).abs() < 1e-4);
}

#[test]
fn lod_is_log2_of_the_longer_derivative_in_texels() {
    let t = Texture::checker(64, 8, [0; 4], [255; 4]); // 7 levels
    let texel = 1.0 / 64.0;
    let lod = |dx: Vec2, dy: Vec2| t.lod(dx, dy);
    assert_eq!(
        lod(Vec2::new(2.0 * texel, 0.0), Vec2::new(0.0, 2.0 * texel)),
        1.0
    );
    assert_eq!(
        lod(Vec2::new(0.5 * texel, 0.0), Vec2::new(0.0, 4.0 * texel)),
        2.0
    );
    assert!(
        (lod(Vec2::new(3.0 * texel, 4.0 * texel), Vec2::ZERO) - libm::log2f(5f32)).abs() < 1e-6
    );
    // Magnification and zero derivatives: the base level; far minification: the last.
    assert_eq!(lod(Vec2::new(0.25 * texel, 0.0), Vec2::ZERO), 0.0);
    assert_eq!(lod(Vec2::ZERO, Vec2::ZERO), 0.0);
    assert_eq!(lod(Vec2::new(1e3, 0.0), Vec2::ZERO), 6.0);
    assert_eq!(lod(Vec2::new(f32::MAX, f32::MAX), Vec2::ZERO), 6.0);
    // Non-finite derivatives: the base level.
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(lod(Vec2::new(bad, 0.0), Vec2::new(1.0, 1.0)), 0.0);
        assert_eq!(lod(Vec2::ZERO, Vec2::new(0.0, bad)), 0.0);
    }
    // Non-square: texels are counted per axis.
    let t = noise("wide", 256, 4, true, 1);
    assert_eq!(
        t.lod(Vec2::new(4.0 / 256.0, 0.0), Vec2::new(0.0, 1.0 / 4.0)),
        2.0
    );
}

#[test]
fn integer_lod_reads_that_level_and_fractions_blend() {
    let t = noise("n", 40, 24, true, 7);
    let s = Sampler {
        wrap_u: Wrap::Repeat,
        wrap_v: Wrap::Repeat,
        filter: Filter::Trilinear,
    };
    for level in 0..t.levels() {
        let (w, h) = t.level_size(level);
        for (x, y) in [(0, 0), (w - 1, h - 1), (w / 2, h / 3)] {
            let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let got = t.sample_lod_with(uv, level as f32, s);
            let want = t.fetch_level(level, x, y);
            assert!(
                (got - want).abs().max_element() < 1e-5,
                "level {level} ({x}, {y})"
            );
        }
    }
    let uv = Vec2::new(0.3, 0.6);
    let (a, b) = (t.sample_lod_with(uv, 1.0, s), t.sample_lod_with(uv, 2.0, s));
    let mid = t.sample_lod_with(uv, 1.25, s);
    assert!((mid - a.lerp(b, 0.25)).abs().max_element() < 1e-6);
}

#[test]
fn derivatives_change_only_trilinear() {
    let t = noise("n", 32, 32, true, 3);
    let (dx, dy) = (Vec2::new(0.3, 0.0), Vec2::new(0.0, 0.2));
    for filter in [Filter::Nearest, Filter::Bilinear] {
        let s = Sampler {
            filter,
            ..Sampler::default()
        };
        for uv in [Vec2::new(0.1, 0.7), Vec2::new(-3.3, 2.1)] {
            // Bit-identical to sampling without derivatives.
            assert_eq!(t.sample_grad_with(uv, dx, dy, s), t.sample_with(uv, s));
        }
    }
    let tri = Sampler::default();
    let bi = Sampler {
        filter: Filter::Bilinear,
        ..tri
    };
    assert_eq!(tri.filter, Filter::Trilinear, "the default");
    let uv = Vec2::new(0.37, 0.61);
    // Magnified: exactly the bilinear sample.
    let small = Vec2::new(0.5 / 32.0, 0.0);
    assert_eq!(
        t.sample_grad_with(uv, small, small.perp(), tri),
        t.sample_with(uv, bi)
    );
    assert_eq!(t.sample_with(uv, tri), t.sample_with(uv, bi));
    // Minified: not the bilinear sample of the noise.
    assert_ne!(t.sample_grad_with(uv, dx, dy, tri), t.sample_with(uv, bi));
}

#[test]
fn no_nan_from_degenerate_derivatives_or_uvs() {
    let specials = [
        0.0,
        -0.0,
        1e-30,
        1.0,
        -7.5,
        1e30,
        -1e30,
        f32::MAX,
        f32::MIN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
    ];
    let mut tried = 0;
    for (w, h) in [(1, 1), (1, 9), (9, 1), (16, 16)] {
        let t = noise("n", w, h, true, 11);
        for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
            let s = Sampler {
                wrap_u: wrap,
                wrap_v: wrap,
                filter: Filter::Trilinear,
            };
            for &a in &specials {
                for &b in &specials {
                    let d = Vec2::new(a, b);
                    for uv in [Vec2::new(0.4, 0.6), Vec2::new(b, a), Vec2::new(a, 0.5)] {
                        let c = t.sample_grad_with(uv, d, d.perp(), s);
                        assert!(c.is_finite(), "{w}x{h} {wrap:?} uv {uv} d {d}: {c}");
                        for n in [2, 16] {
                            let an = Sampler {
                                filter: Filter::Anisotropic(n),
                                ..s
                            };
                            for e in [d.perp(), Vec2::new(b, 0.01)] {
                                let c = t.sample_grad_with(uv, d, e, an);
                                assert!(c.is_finite(), "aniso {n} uv {uv} d {d} {e}: {c}");
                                let taps = t.aniso(d, e, n).taps;
                                assert!((1..=u32::from(n)).contains(&taps));
                            }
                        }
                        let lod = t.lod(d, Vec2::new(b, 0.1));
                        assert!((0.0..=(t.levels() - 1) as f32).contains(&lod));
                        tried += 1;
                    }
                }
            }
            for lod in specials {
                assert!(t.sample_lod_with(Vec2::new(0.2, 0.9), lod, s).is_finite());
            }
        }
    }
    assert_eq!(tried, 4 * 3 * 12 * 12 * 3);
}

#[test]
fn filter_names_parse_and_round_trip() {
    for f in Filter::COMMON {
        assert_eq!(f.name().parse::<Filter>(), Ok(f));
        assert_eq!(f.to_string(), f.name());
    }
    for n in MIN_ANISO..=MAX_ANISO {
        let f = Filter::Anisotropic(n);
        assert_eq!(f.name(), format!("aniso:{n}"));
        assert_eq!(f.name().parse::<Filter>(), Ok(f));
    }
    assert_eq!(" Aniso:08 ".parse::<Filter>(), Ok(Filter::Anisotropic(8)));
    assert_eq!("TRILINEAR".parse::<Filter>(), Ok(Filter::Trilinear));
    // Out-of-range ratios are named (and sampled) clamped.
    assert_eq!(Filter::Anisotropic(0).name(), "aniso:2");
    assert_eq!(Filter::Anisotropic(200).name(), "aniso:16");
    for bad in [
        "",
        "aniso",
        "aniso:",
        "aniso:1",
        "aniso:17",
        "aniso:+4",
        "aniso:-4",
        "aniso:4x",
        "aniso:256",
        "aniso:999",
        "aniso4",
        "linear",
        "tri",
        "aniso:٣",
    ] {
        let e = bad.parse::<Filter>().expect_err(bad).to_string();
        for form in ["nearest", "bilinear", "trilinear", "aniso:N", "2", "16"] {
            assert!(e.contains(form), "{bad}: {e}");
        }
    }
}

fn aniso_sampler(n: u8) -> Sampler {
    Sampler {
        filter: Filter::Anisotropic(n),
        ..Sampler::default()
    }
}

#[test]
fn aniso_taps_follow_the_footprint() {
    let t = noise("n", 64, 64, true, 9); // 7 levels
    let texel = 1.0 / 64.0;
    let taps = |dx: Vec2, dy: Vec2, max| {
        let a = t.aniso(dx * texel, dy * texel, max);
        (a.taps, a.lod)
    };
    // 8 x 1 texels: 8 taps at the base level; along y, the same.
    assert_eq!(taps(Vec2::new(8.0, 0.0), Vec2::new(0.0, 1.0), 16), (8, 0.0));
    assert_eq!(taps(Vec2::new(0.0, 1.0), Vec2::new(0.0, 8.0), 16), (8, 0.0));
    // 64 x 2: ratio 32 capped at 16 taps, each covering 4 texels: lod 2.
    assert_eq!(
        taps(Vec2::new(64.0, 0.0), Vec2::new(0.0, 2.0), 16),
        (16, 2.0)
    );
    assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::new(0.0, 2.0), 4), (4, 4.0));
    // Ratio 2.5 -> 3 taps; lod log2(10 / 3).
    let (n, lod) = taps(Vec2::new(0.0, 4.0), Vec2::new(10.0, 0.0), 16);
    assert_eq!(n, 3);
    assert!((lod - libm::log2f(10f32 / 3.0)).abs() < 1e-6);
    // A thinner-than-a-texel minor axis counts as one texel.
    assert_eq!(
        taps(Vec2::new(6.0, 0.0), Vec2::ZERO, 16),
        (6, libm::log2f(6f32 / 6.0))
    );
    // Out-of-range ratios clamp: 0 and 1 mean 2, 200 means 16.
    assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::ZERO, 0).0, 2);
    assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::ZERO, 1).0, 2);
    assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::ZERO, 200).0, 16);
    // Isotropic, magnified, zero or non-finite: one tap.
    for (dx, dy) in [
        (Vec2::new(4.0, 0.0), Vec2::new(0.0, 4.0)),
        (Vec2::new(3.0, 4.0), Vec2::new(-4.0, 3.0)),
        (Vec2::new(0.9, 0.0), Vec2::ZERO),
        (Vec2::ZERO, Vec2::ZERO),
        (Vec2::new(f32::NAN, 0.0), Vec2::new(0.0, 1e3)),
        (Vec2::new(f32::INFINITY, 0.0), Vec2::ZERO),
    ] {
        assert_eq!(taps(dx, dy, 16).0, 1, "{dx} {dy}");
    }
    // Derivatives whose length overflows: 16 taps on the last level.
    let a = t.aniso(Vec2::new(f32::MAX, f32::MAX), Vec2::ZERO, 16);
    assert_eq!((a.taps, a.lod), (16, 6.0));
    let a = t.aniso(Vec2::splat(f32::MAX), Vec2::splat(-f32::MAX), 16);
    assert_eq!((a.taps, a.lod), (16, 6.0));
}

#[test]
fn one_tap_aniso_is_exactly_trilinear() {
    let t = noise("n", 40, 24, true, 4);
    let texel = Vec2::new(1.0 / 40.0, 1.0 / 24.0);
    let mut checked = 0;
    for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
        for (dx, dy) in [
            (Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.3)),
            (Vec2::new(3.0, 0.0), Vec2::new(0.0, 3.0)),
            (Vec2::new(5.0, 1.0), Vec2::new(-1.0, 5.0)),
            (Vec2::ZERO, Vec2::ZERO),
            (Vec2::new(f32::NAN, 1.0), Vec2::new(1.0, 0.0)),
        ] {
            let (dx, dy) = (dx * texel, dy * texel);
            for uv in [Vec2::new(0.31, 0.77), Vec2::new(-2.2, 5.01)] {
                let tri = Sampler {
                    wrap_u: wrap,
                    wrap_v: wrap,
                    filter: Filter::Trilinear,
                };
                for n in [2, 16] {
                    let an = Sampler {
                        filter: Filter::Anisotropic(n),
                        ..tri
                    };
                    assert_eq!(
                        t.sample_grad_with(uv, dx, dy, an),
                        t.sample_grad_with(uv, dx, dy, tri),
                        "{wrap:?} {dx} {dy} {uv}"
                    );
                    checked += 1;
                }
            }
            // Without derivatives: the base level, as trilinear.
            let uv = Vec2::new(0.4, 0.1);
            assert_eq!(
                t.sample_with(uv, aniso_sampler(8)),
                t.sample_with(uv, Sampler::default())
            );
        }
    }
    assert_eq!(checked, 3 * 5 * 2 * 2);
}

#[test]
fn aniso_averages_along_the_long_axis_and_keeps_the_short_one_sharp() {
    // Linear texels: green alternates per column (mean 0.5), red is a ramp down the
    // rows (smooth along v). A footprint 8 texels along u and 1 along v: anisotropic
    // filtering averages green to its mean and reads red as sharp as bilinear does;
    // trilinear (level 3) blurs red across 8 rows.
    let (w, h) = (64u32, 64u32);
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let g = if x % 2 == 0 { 0 } else { 255 };
            let r = ((y % 32) * 8) as u8;
            [r, g, 0, 255]
        })
        .collect();
    let t = Texture::new("stripes", w, h, texels, false).unwrap();
    let (dx, dy) = (Vec2::new(8.0 / 64.0, 0.0), Vec2::new(0.0, 1.0 / 64.0));
    let bi = Sampler {
        filter: Filter::Bilinear,
        ..Sampler::default()
    };
    let (mut tri_err, mut checked) = (0f32, 0);
    for k in 0..32 {
        // Rows 4..28 of the ramp (away from its wrap from 248 to 0).
        let uv = Vec2::new(0.37 + 0.011 * k as f32, (4.5 + 0.77 * k as f32) / 64.0);
        let a = t.sample_grad_with(uv, dx, dy, aniso_sampler(16));
        let sharp = t.sample_with(uv, bi);
        assert!((a.y - 0.5).abs() < 1e-5, "{uv}: green {a}");
        assert!((a.x - sharp.x).abs() < 1e-5, "{uv}: red {a} vs {sharp}");
        let tri = t.sample_grad_with(uv, dx, dy, Sampler::default());
        assert!((tri.y - 0.5).abs() < 1e-3, "{uv}: trilinear green {tri}");
        tri_err = tri_err.max((tri.x - sharp.x).abs());
        checked += 1;
    }
    assert_eq!(checked, 32);
    // Level 3 averages 8 rows of the ramp: off by at least a step somewhere.
    assert!(tri_err > 0.02, "{tri_err}");
}

#[test]
fn clones_rebuild_and_prepared_chains_match_lazy_ones() {
    let t = noise("n", 37, 20, true, 5);
    let lazy = t.fetch_level(2, 3, 1);
    let u = t.clone();
    assert_eq!(u, t, "the chain takes no part in equality");
    assert!(format!("{u:?}").contains("MipCache(not built)"));
    u.prepare_mips();
    assert_eq!(
        u.fetch_level(2, 3, 1),
        lazy,
        "parallel and serial builds agree"
    );
    for level in 1..t.levels() {
        let (w, h) = t.level_size(level);
        for y in 0..h {
            for x in 0..w {
                assert_eq!(u.fetch_level(level, x, y), t.fetch_level(level, x, y));
            }
        }
    }
}
