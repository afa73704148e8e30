//! Gamut geometry in a chromaticity plane: areas, intersections and coverage of RGB gamut
//! triangles and of the spectral locus.
//!
//! The maps from xy to CIE 1960 uv and CIE 1976 u'v' are projective, so straight lines stay
//! straight: a gamut triangle in uv is the triangle of its mapped primaries, and the
//! spectral locus closed by the purple line maps to the polygon of its mapped points.

use super::Plane;
use crate::color::{Observer, RgbSpace, SpectralLocus, FIRST_NM, LAST_NM};

/// Signed area of a polygon (shoelace; positive when counter-clockwise).
#[must_use]
pub fn signed_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

/// Counter-clockwise copy of a polygon.
fn ccw(mut poly: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    if signed_area(&poly) < 0.0 {
        poly.reverse();
    }
    poly
}

/// `subject` clipped to the convex, counter-clockwise polygon `clip` (Sutherland-Hodgman).
#[must_use]
pub fn clip_convex(subject: &[[f64; 2]], clip: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out = subject.to_vec();
    for i in 0..clip.len() {
        let (a, b) = (clip[i], clip[(i + 1) % clip.len()]);
        let side = |p: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let input = std::mem::take(&mut out);
        let cut = |p: &[f64; 2], q: &[f64; 2]| {
            let t = crate::geom::crossing(side(*p), side(*q));
            [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t]
        };
        crate::geom::clip_polygon(&input, |p| side(*p) >= 0.0, cut, &mut out);
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The gamut triangle of `space` in `plane`, counter-clockwise.
#[must_use]
pub fn triangle(space: &RgbSpace, plane: Plane) -> Vec<[f64; 2]> {
    ccw(space
        .primaries
        .iter()
        .map(|&xy| plane.from_xy(xy))
        .collect())
}

/// The spectral locus (every nm from 360 to 830) closed by the purple line, in `plane`.
#[must_use]
pub fn locus_polygon(observer: Observer, plane: Plane) -> Vec<[f64; 2]> {
    let locus = SpectralLocus::new(observer);
    locus
        .points(FIRST_NM, LAST_NM)
        .into_iter()
        .map(|(_, xy)| plane.from_xy(xy))
        .collect()
}

/// Area of `space`'s triangle in `plane`.
#[must_use]
pub fn area(space: &RgbSpace, plane: Plane) -> f64 {
    signed_area(&triangle(space, plane))
}

/// Fraction of `b`'s triangle that `a`'s triangle covers, in `plane`.
#[must_use]
pub fn coverage(a: &RgbSpace, b: &RgbSpace, plane: Plane) -> f64 {
    let tb = triangle(b, plane);
    let inter = clip_convex(&tb, &triangle(a, plane));
    signed_area(&inter).abs() / signed_area(&tb)
}

/// Area enclosed by the spectral locus and the purple line in `plane`.
#[must_use]
pub fn locus_area(observer: Observer, plane: Plane) -> f64 {
    signed_area(&locus_polygon(observer, plane)).abs()
}

/// Fraction of the visible chromaticities (inside the locus) that `space` covers in `plane`.
/// Every built-in gamut but CIE RGB lies inside the locus; for those outside, only the part
/// inside counts (the locus is clipped against the triangle, which is convex).
#[must_use]
pub fn visible_coverage(space: &RgbSpace, observer: Observer, plane: Plane) -> f64 {
    let locus = locus_polygon(observer, plane);
    let inter = clip_convex(&locus, &triangle(space, plane));
    signed_area(&inter).abs() / signed_area(&locus).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn areas_and_coverage_of_known_gamuts() {
        let srgb = RgbSpace::srgb();
        let p3 = RgbSpace::display_p3();
        let r2020 = RgbSpace::rec2020();
        // sRGB in xy: 0.5 |(0.30-0.64)(0.06-0.33) - (0.15-0.64)(0.60-0.33)| = 0.11205.
        assert!((area(&srgb, Plane::Xy) - 0.11205).abs() < 1e-12);
        // Widely quoted figures: P3 is ~1.36x sRGB in xy, Rec.2020 ~1.89x.
        let ratio = |g: &RgbSpace| area(g, Plane::Xy) / area(&srgb, Plane::Xy);
        assert!((ratio(&p3) - 1.357).abs() < 1e-3, "{}", ratio(&p3));
        assert!((ratio(&r2020) - 1.891).abs() < 1e-3, "{}", ratio(&r2020));
        assert!((coverage(&r2020, &srgb, Plane::Xy) - 1.0).abs() < 1e-12);
        assert!((coverage(&srgb, &srgb, Plane::UvPrime) - 1.0).abs() < 1e-12);
        let s_in_p3 = coverage(&srgb, &p3, Plane::Xy);
        assert!(
            (s_in_p3 - area(&srgb, Plane::Xy) / area(&p3, Plane::Xy)).abs() < 1e-3,
            "{s_in_p3}"
        );
        // A gamut inside the locus covers its area's share of it; one that pokes out
        // only the part inside. (P3's red and Rec.2020's primaries sit on the locus, a hair
        // outside at 1e-7, so sRGB is the clean case.)
        for plane in [Plane::Xy, Plane::Uv, Plane::UvPrime] {
            let locus = locus_area(Observer::Cie1931, plane);
            let v = visible_coverage(&srgb, Observer::Cie1931, plane);
            assert!(
                (v - area(&srgb, plane) / locus).abs() < 1e-9,
                "{plane:?} {v}"
            );
            let wide = RgbSpace::new(
                "wide",
                [[0.8, 0.2], [0.0, 1.0], [0.1, 0.01]],
                [0.3127, 0.329],
                "D65",
                crate::color::Transfer::Linear,
            )
            .unwrap();
            let w = visible_coverage(&wide, Observer::Cie1931, plane);
            assert!(
                w < area(&wide, plane) / locus && w > 0.9 && w <= 1.0,
                "{plane:?} {w}"
            );
        }
    }
}
