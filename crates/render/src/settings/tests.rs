use super::*;
use glam::{Vec3, Vec4};

fn tone(t: ToneMap, c: Vec3) -> Vec3 {
    t.apply(c.extend(0.5)).truncate()
}

#[test]
fn pbr_neutral_keeps_the_middle_range_and_rolls_off_the_highlights() {
    // In [0.08, 0.8] - 0.04 per channel: the colour minus 0.04, hue kept.
    let c = Vec3::new(0.1, 0.4, 0.7);
    assert!(
        (tone(ToneMap::PbrNeutral, c) - (c - 0.04))
            .abs()
            .max_element()
            < 1e-6
    );
    // Black stays black; the toe is x - 6.25 x^2 below 0.08 (continuous at 0.08).
    assert_eq!(tone(ToneMap::PbrNeutral, Vec3::ZERO), Vec3::ZERO);
    let g = 0.05f32;
    let want = g - (g - 6.25 * g * g);
    assert!((tone(ToneMap::PbrNeutral, Vec3::splat(g)).x - want).abs() < 1e-7);
    // Highlights: below 1, increasing, and desaturated towards white.
    let mut last = 0.0;
    for k in 1..200 {
        let v = tone(ToneMap::PbrNeutral, Vec3::splat(k as f32 * 0.1)).x;
        assert!(v > last && v < 1.0, "{k}: {v}");
        last = v;
    }
    let red = tone(ToneMap::PbrNeutral, Vec3::new(8.0, 0.5, 0.5));
    assert!(red.x < 1.0 && red.y > 0.5 - 0.04, "desaturated: {red}");
}

#[test]
fn the_aces_fits_give_their_published_values() {
    // Narkowicz: f(1) = 2.54 / 3.16.
    let n = tone(ToneMap::AcesNarkowicz, Vec3::ONE);
    assert!(
        (n - Vec3::splat(2.54 / 3.16)).abs().max_element() < 1e-6,
        "{n}"
    );
    // Hill: the matrices keep grey grey (rows sum to 1), so f(1) is the rational
    // curve at 1: (1.0245786 - 0.000090537) / (0.983729 + 0.432951 + 0.238081).
    let h = tone(ToneMap::AcesHill, Vec3::ONE);
    let want = (1.024_578_6 - 0.000_090_537) / (0.983_729 + 0.432_951 + 0.238_081);
    assert!((h - Vec3::splat(want)).abs().max_element() < 1e-5, "{h}");
    for t in [ToneMap::AcesNarkowicz, ToneMap::AcesHill] {
        assert_eq!(tone(t, Vec3::ZERO), Vec3::ZERO, "{t:?}: black stays black");
        let big = tone(t, Vec3::splat(1e6));
        assert!(
            big.max_element() <= 1.0 && big.min_element() > 0.99,
            "{t:?}: {big}"
        );
    }
}

#[test]
fn every_tone_map_keeps_alpha_parses_its_name_and_leaves_non_finite_colours() {
    for t in ToneMap::ALL {
        assert_eq!(t.name().parse::<ToneMap>(), Ok(t));
        let c = t.apply(Vec4::new(2.0, 1.0, 0.5, 0.25));
        assert_eq!(c.w, 0.25, "{t:?}");
        assert!(
            c.truncate().max_element() <= 1.0 + 1e-6 || matches!(t, ToneMap::Clamp | ToneMap::Auto)
        );
        let nan = Vec4::new(f32::NAN, 0.5, 0.5, 1.0);
        assert!(t.apply(nan).x.is_nan(), "{t:?}");
    }
    assert!("aces".parse::<ToneMap>().unwrap_err().contains("aces-hill"));
}
