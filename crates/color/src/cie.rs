//! CIE colour spaces derived from XYZ: xyY, the CIE 1960 UCS (u, v), the CIE 1976 UCS
//! (u', v'), CIE L\*a\*b\*, LCh(ab) and CIE L\*u\*v\*.
//!
//! Conventions (those of colour-science): XYZ is scaled so that the white has Y = 1; L\* is in
//! [0, 100]; hue angles are in degrees in [0, 360). White points are given as XYZ with Y = 1
//! (see [`xy_to_xyz`]). The L\* curve uses the exact CIE constants ε = 216/24389 and
//! κ = 24389/27 rather than the rounded 0.008856 and 903.3, so that it is continuous.

/// ε of the L\* curve: (6/29)^3.
pub const CIE_EPSILON: f64 = 216.0 / 24389.0;
/// κ of the L\* curve: (29/3)^3.
pub const CIE_KAPPA: f64 = 24389.0 / 27.0;

/// XYZ to xyY. Black (X + Y + Z = 0) maps to (0, 0, 0), as colour-science 0.4.7 does; many
/// implementations return the white point's chromaticity instead.
#[must_use]
pub fn xyz_to_xyy(xyz: [f64; 3]) -> [f64; 3] {
    let s = xyz[0] + xyz[1] + xyz[2];
    if s == 0.0 {
        return [0.0, 0.0, 0.0];
    }
    [xyz[0] / s, xyz[1] / s, xyz[1]]
}

/// xyY to XYZ; y = 0 gives (0, 0, 0).
#[must_use]
pub fn xyy_to_xyz(xyy: [f64; 3]) -> [f64; 3] {
    let [x, y, big_y] = xyy;
    if y == 0.0 {
        return [0.0, 0.0, 0.0];
    }
    [x * big_y / y, big_y, (1.0 - x - y) * big_y / y]
}

/// Chromaticity xy to XYZ with Y = 1 (how white points are used).
#[must_use]
pub fn xy_to_xyz(xy: [f64; 2]) -> [f64; 3] {
    xyy_to_xyz([xy[0], xy[1], 1.0])
}

/// xy to CIE 1960 UCS uv: u = 4x / (-2x + 12y + 3), v = 6y / (-2x + 12y + 3).
#[must_use]
pub fn xy_to_uv1960(xy: [f64; 2]) -> [f64; 2] {
    let d = -2.0 * xy[0] + 12.0 * xy[1] + 3.0;
    [4.0 * xy[0] / d, 6.0 * xy[1] / d]
}

/// CIE 1960 uv to xy: x = 3u / (2u - 8v + 4), y = 2v / (2u - 8v + 4).
#[must_use]
pub fn uv1960_to_xy(uv: [f64; 2]) -> [f64; 2] {
    let d = 2.0 * uv[0] - 8.0 * uv[1] + 4.0;
    [3.0 * uv[0] / d, 2.0 * uv[1] / d]
}

/// xy to CIE 1976 UCS u'v': u' = 4x / (-2x + 12y + 3), v' = 9y / (-2x + 12y + 3).
#[must_use]
pub fn xy_to_uv_prime(xy: [f64; 2]) -> [f64; 2] {
    let d = -2.0 * xy[0] + 12.0 * xy[1] + 3.0;
    [4.0 * xy[0] / d, 9.0 * xy[1] / d]
}

/// CIE 1976 u'v' to xy: x = 9u' / (6u' - 16v' + 12), y = 4v' / (6u' - 16v' + 12).
#[must_use]
pub fn uv_prime_to_xy(uv: [f64; 2]) -> [f64; 2] {
    let d = 6.0 * uv[0] - 16.0 * uv[1] + 12.0;
    [9.0 * uv[0] / d, 4.0 * uv[1] / d]
}

fn lab_f(t: f64) -> f64 {
    if t > CIE_EPSILON {
        libm::cbrt(t)
    } else {
        (CIE_KAPPA * t + 16.0) / 116.0
    }
}

fn lab_f_inv(f: f64) -> f64 {
    let t = f * f * f;
    if t > CIE_EPSILON {
        t
    } else {
        (116.0 * f - 16.0) / CIE_KAPPA
    }
}

/// XYZ to CIE L\*a\*b\* relative to the white `white` (XYZ, Y = 1).
#[must_use]
pub fn xyz_to_lab(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let f = [0, 1, 2].map(|i| lab_f(xyz[i] / white[i]));
    [
        116.0 * f[1] - 16.0,
        500.0 * (f[0] - f[1]),
        200.0 * (f[1] - f[2]),
    ]
}

/// CIE L\*a\*b\* to XYZ relative to `white`.
#[must_use]
pub fn lab_to_xyz(lab: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let fy = (lab[0] + 16.0) / 116.0;
    let fx = fy + lab[1] / 500.0;
    let fz = fy - lab[2] / 200.0;
    // Y uses L* directly below the knee, which is exact there.
    let y = if lab[0] > CIE_KAPPA * CIE_EPSILON {
        fy * fy * fy
    } else {
        lab[0] / CIE_KAPPA
    };
    [
        lab_f_inv(fx) * white[0],
        y * white[1],
        lab_f_inv(fz) * white[2],
    ]
}

/// Cartesian (L, a, b) to cylindrical (L, C, h) with h in degrees in [0, 360).
#[must_use]
pub fn lab_to_lch(lab: [f64; 3]) -> [f64; 3] {
    let c = libm::hypot(lab[1], lab[2]);
    let h = libm::atan2(lab[2], lab[1]).to_degrees().rem_euclid(360.0);
    [lab[0], c, h]
}

/// Cylindrical (L, C, h in degrees) to cartesian (L, a, b).
#[must_use]
pub fn lch_to_lab(lch: [f64; 3]) -> [f64; 3] {
    let (s, c) = libm::sincos(lch[2].to_radians());
    [lch[0], lch[1] * c, lch[1] * s]
}

/// XYZ to CIE L\*u\*v\* relative to `white` (XYZ, Y = 1). Black gives (0, 0, 0).
#[must_use]
pub fn xyz_to_luv(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let l = 116.0 * lab_f(xyz[1] / white[1]) - 16.0;
    let d = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
    if d == 0.0 {
        return [l, 0.0, 0.0];
    }
    let (u, v) = (4.0 * xyz[0] / d, 9.0 * xyz[1] / d);
    let dn = white[0] + 15.0 * white[1] + 3.0 * white[2];
    let (un, vn) = (4.0 * white[0] / dn, 9.0 * white[1] / dn);
    [l, 13.0 * l * (u - un), 13.0 * l * (v - vn)]
}

/// CIE L\*u\*v\* to XYZ relative to `white`.
#[must_use]
pub fn luv_to_xyz(luv: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let [l, u_star, v_star] = luv;
    if l <= 0.0 {
        return [0.0, 0.0, 0.0];
    }
    let y = lab_to_xyz([l, 0.0, 0.0], [1.0; 3])[1] * white[1];
    let dn = white[0] + 15.0 * white[1] + 3.0 * white[2];
    let (un, vn) = (4.0 * white[0] / dn, 9.0 * white[1] / dn);
    let u = u_star / (13.0 * l) + un;
    let v = v_star / (13.0 * l) + vn;
    if v == 0.0 {
        return [0.0, y, 0.0];
    }
    let x = y * 9.0 * u / (4.0 * v);
    let z = y * (12.0 - 3.0 * u - 20.0 * v) / (4.0 * v);
    [x, y, z]
}
