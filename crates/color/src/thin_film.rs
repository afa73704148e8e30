//! The colour of a thin dielectric film, exactly: the Airy reflectance of the film between
//! air and a substrate, per wavelength and polarisation, integrated against a standard
//! observer. The reference the renderer's analytic approximation of
//! `KHR_materials_iridescence` (Belcour and Barla 2017) is measured against.

use crate::{Observer, RgbSpace};

/// The reflectance of a film of IOR `n2`, `d` nm thick, between air (IOR 1) and a
/// substrate of real IOR `n3`, at wavelength `nm` and incidence `cos1`, unpolarised (the
/// mean of s and p): the Airy sum of the amplitudes, `r = (r12 + r23 e^{iδ}) / (1 + r12
/// r23 e^{iδ})` with `δ = 4π n2 d cos θ2 / λ` and Fresnel's amplitude coefficients at both
/// interfaces.
#[must_use]
pub fn reflectance(n2: f64, n3: f64, d: f64, cos1: f64, nm: f64) -> f64 {
    let sin_sq = 1.0 - cos1 * cos1;
    let cos2 = (1.0 - sin_sq / (n2 * n2)).sqrt();
    let cos3 = (1.0 - sin_sq / (n3 * n3)).sqrt();
    let delta = 4.0 * std::f64::consts::PI * n2 * d * cos2 / nm;
    let (sn, cs) = libm::sincos(delta);
    // [s, p] amplitude coefficients of the two interfaces.
    let s12 = (cos1 - n2 * cos2) / (cos1 + n2 * cos2);
    let s23 = (n2 * cos2 - n3 * cos3) / (n2 * cos2 + n3 * cos3);
    let p12 = (n2 * cos1 - cos2) / (n2 * cos1 + cos2);
    let p23 = (n3 * cos2 - n2 * cos3) / (n3 * cos2 + n2 * cos3);
    let mut sum = 0.0;
    for (a, b) in [(s12, s23), (p12, p23)] {
        let num = (a + b * cs).powi(2) + (b * sn).powi(2);
        let den = (1.0 + a * b * cs).powi(2) + (a * b * sn).powi(2);
        sum += num / den;
    }
    sum / 2.0
}

/// The film's reflection in linear Rec. 709 over a substrate whose normal-incidence
/// reflectance is `f0` (its IOR `(1 + √F0) / (1 - √F0)`): [`reflectance`] at 1 nm from
/// 380 to 780 nm against the CIE 1931 2° observer, XYZ divided by the integral of ȳ (a flat
/// reflectance of 1 has Y = 1), through the D65 Rec. 709 matrix.
#[must_use]
pub fn rec709(n2: f64, f0: f64, d: f64, cos1: f64) -> [f64; 3] {
    let n3 = (1.0 + f0.sqrt()) / (1.0 - f0.sqrt());
    let (mut xyz, mut y) = ([0.0; 3], 0.0);
    for nm in 380..=780 {
        let cmf = Observer::Cie1931.cmf(f64::from(nm));
        let r = reflectance(n2, n3, d, cos1, f64::from(nm));
        for k in 0..3 {
            xyz[k] += r * cmf[k];
        }
        y += cmf[1];
    }
    RgbSpace::bt709().xyz_to_linear(xyz.map(|v| v / y))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without a film (d = 0) the reflectance is Fresnel's at the substrate, and at normal
    /// incidence `((n3 - 1) / (n3 + 1))²` whatever the film.
    #[test]
    fn no_film_is_the_substrate() {
        for nm in [400.0, 550.0, 700.0] {
            let r = reflectance(1.8, 1.5, 0.0, 1.0, nm);
            assert!((r - 0.04).abs() < 1e-12, "{r}");
        }
        // A quarter-wave film of IOR √1.5 cancels the reflection at that wavelength.
        let n2 = 1.5f64.sqrt();
        let r = reflectance(n2, 1.5, 550.0 / (4.0 * n2), 1.0, 550.0);
        assert!(r < 1e-12, "{r}");
        let white = rec709(1.3, 0.04, 0.0, 1.0);
        // An equal-energy 0.04 in Rec. 709 (not white: E is not D65).
        assert!(white.iter().all(|c| (c - 0.04).abs() < 0.01), "{white:?}");
    }
}
