//! Colour differences between two CIE L\*a\*b\* colours: ΔE\*ab (CIE 1976), ΔE\*94 (CIE 1994,
//! graphic-arts weights) and ΔE00 (CIEDE2000, following Sharma, Wu and Dalal 2005, with
//! kL = kC = kH = 1).

/// CIE 1976: Euclidean distance in L\*a\*b\*.
#[must_use]
pub fn delta_e_1976(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// CIE 1994 with the graphic-arts constants (kL = 1, K1 = 0.045, K2 = 0.015); `a` is the
/// reference colour (the formula is not symmetric).
#[must_use]
pub fn delta_e_1994(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (k1, k2) = (0.045, 0.015);
    let c1 = libm::hypot(a[1], a[2]);
    let c2 = libm::hypot(b[1], b[2]);
    let dl = a[0] - b[0];
    let dc = c1 - c2;
    let da = a[1] - b[1];
    let db = a[2] - b[2];
    // ΔH² = Δa² + Δb² - ΔC², clamped: rounding can make it slightly negative.
    let dh2 = (da * da + db * db - dc * dc).max(0.0);
    let sc = 1.0 + k1 * c1;
    let sh = 1.0 + k2 * c1;
    (dl * dl + (dc / sc).powi(2) + dh2 / (sh * sh)).sqrt()
}

/// CIEDE2000 (ΔE00) with kL = kC = kH = 1.
#[must_use]
pub fn delta_e_2000(lab1: [f64; 3], lab2: [f64; 3]) -> f64 {
    let [l1, a1, b1] = lab1;
    let [l2, a2, b2] = lab2;
    let c_bar = (libm::hypot(a1, b1) + libm::hypot(a2, b2)) / 2.0;
    let c7 = c_bar.powi(7);
    let g = 0.5 * (1.0 - (c7 / (c7 + 25f64.powi(7))).sqrt());
    let a1p = (1.0 + g) * a1;
    let a2p = (1.0 + g) * a2;
    let c1p = libm::hypot(a1p, b1);
    let c2p = libm::hypot(a2p, b2);
    let hue = |b: f64, ap: f64| {
        if b == 0.0 && ap == 0.0 {
            0.0
        } else {
            libm::atan2(b, ap).to_degrees().rem_euclid(360.0)
        }
    };
    let h1p = hue(b1, a1p);
    let h2p = hue(b2, a2p);

    let dlp = l2 - l1;
    let dcp = c2p - c1p;
    let chroma_zero = c1p * c2p == 0.0;
    let dhp = if chroma_zero {
        0.0
    } else if (h2p - h1p).abs() <= 180.0 {
        h2p - h1p
    } else if h2p - h1p > 180.0 {
        h2p - h1p - 360.0
    } else {
        h2p - h1p + 360.0
    };
    let d_big_hp = 2.0 * (c1p * c2p).sqrt() * libm::sin(dhp.to_radians() / 2.0);

    let lp_bar = (l1 + l2) / 2.0;
    let cp_bar = (c1p + c2p) / 2.0;
    let hp_bar = if chroma_zero {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        (h1p + h2p) / 2.0
    } else if h1p + h2p < 360.0 {
        (h1p + h2p + 360.0) / 2.0
    } else {
        (h1p + h2p - 360.0) / 2.0
    };
    let t = 1.0 - 0.17 * libm::cos((hp_bar - 30.0).to_radians())
        + 0.24 * libm::cos((2.0 * hp_bar).to_radians())
        + 0.32 * libm::cos((3.0 * hp_bar + 6.0).to_radians())
        - 0.20 * libm::cos((4.0 * hp_bar - 63.0).to_radians());
    let d_theta = 30.0 * libm::exp(-((hp_bar - 275.0) / 25.0).powi(2));
    let cp7 = cp_bar.powi(7);
    let rc = 2.0 * (cp7 / (cp7 + 25f64.powi(7))).sqrt();
    let l50 = (lp_bar - 50.0).powi(2);
    let sl = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let sc = 1.0 + 0.045 * cp_bar;
    let sh = 1.0 + 0.015 * cp_bar * t;
    let rt = -libm::sin((2.0 * d_theta).to_radians()) * rc;
    let (l, c, h) = (dlp / sl, dcp / sc, d_big_hp / sh);
    (l * l + c * c + h * h + rt * c * h).max(0.0).sqrt()
}
