//! RGB colour spaces defined by three primaries and a white point (chromaticities xy), their
//! RGB <-> XYZ matrices, transfer functions, and Bradford chromatic adaptation.
//!
//! The matrix of a space is derived from its primaries and white point (the *normalised
//! primary matrix*: the columns are the primaries' XYZ, scaled so that RGB = (1, 1, 1) gives
//! the white with Y = 1). Two standards publish rounded matrices that files and other tools
//! actually use, and [`RgbSpace::srgb`] and [`RgbSpace::adobe_rgb`] keep those published
//! numbers (IEC 61966-2-1's 4 decimals, Adobe's 5 decimals), as colour-science does; the
//! derived ones differ by up to 1e-4. Any other space, including user-given primaries, uses
//! the derived matrix.

use super::cie::xy_to_xyz;
use super::cmf::{Observer, SpectralLocus};
use super::matrix::{diagonal, inverse, mul, mul_vec, Mat3};
use super::transfer::{srgb_decode, srgb_encode};
use super::Illuminant;

/// How a space's stored values relate to linear light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Transfer {
    /// Values are linear.
    Linear,
    /// The IEC 61966-2-1 sRGB curve (also Display P3).
    Srgb,
    /// The ITU-R BT.709 / BT.2020 camera curve (OETF).
    Bt709,
    /// A pure power law: linear = value^gamma (Adobe RGB 563/256, DCI-P3 2.6).
    Gamma(f64),
}

impl Transfer {
    /// Encoded value to linear light (negative values are mirrored).
    #[must_use]
    pub fn decode(self, v: f64) -> f64 {
        match self {
            Transfer::Linear => v,
            Transfer::Srgb => srgb_decode(v),
            Transfer::Bt709 => {
                if v.abs() < 4.5 * 0.018_053_968_510_807 {
                    v / 4.5
                } else {
                    v.signum()
                        * libm::pow(
                            (v.abs() + 0.099_296_826_809_44) / 1.099_296_826_809_44,
                            1.0 / 0.45,
                        )
                }
            }
            Transfer::Gamma(g) => v.signum() * libm::pow(v.abs(), g),
        }
    }

    /// Linear light to the encoded value (negative values are mirrored).
    #[must_use]
    pub fn encode(self, v: f64) -> f64 {
        match self {
            Transfer::Linear => v,
            Transfer::Srgb => srgb_encode(v),
            Transfer::Bt709 => {
                if v.abs() < 0.018_053_968_510_807 {
                    4.5 * v
                } else {
                    v.signum()
                        * (1.099_296_826_809_44 * libm::pow(v.abs(), 0.45) - 0.099_296_826_809_44)
                }
            }
            Transfer::Gamma(g) => v.signum() * libm::pow(v.abs(), 1.0 / g),
        }
    }
}

/// Why primaries and a white point do not define a colour space.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpaceError {
    #[error("a primary or the white point has y <= 0 or a non-finite coordinate")]
    BadChromaticity,
    #[error("the three primaries are collinear: they span no gamut")]
    Collinear,
}

/// An RGB colour space.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbSpace {
    /// Display name, e.g. "sRGB".
    pub name: String,
    /// Chromaticities of the red, green and blue primaries.
    pub primaries: [[f64; 2]; 3],
    /// Chromaticity of the white point.
    pub white: [f64; 2],
    /// Name of the white point, e.g. "D65".
    pub white_name: String,
    /// Linear RGB to XYZ (Y of the white = 1).
    pub to_xyz: Mat3,
    /// XYZ to linear RGB.
    pub from_xyz: Mat3,
    /// Transfer function of encoded values.
    pub transfer: Transfer,
}

/// The normalised primary matrix of `primaries` and `white`: linear RGB to XYZ.
pub fn normalised_primary_matrix(
    primaries: [[f64; 2]; 3],
    white: [f64; 2],
) -> Result<Mat3, SpaceError> {
    let ok = |xy: [f64; 2]| xy[0].is_finite() && xy[1].is_finite() && xy[1] > 0.0;
    if !primaries.iter().all(|&p| ok(p)) || !ok(white) {
        return Err(SpaceError::BadChromaticity);
    }
    let cols = primaries.map(xy_to_xyz);
    let p: Mat3 = [0, 1, 2].map(|row| [cols[0][row], cols[1][row], cols[2][row]]);
    // Collinear in xy <=> the xyz columns are linearly dependent.
    let [a, b, c] = primaries;
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if area.abs() < 1e-12 {
        return Err(SpaceError::Collinear);
    }
    let inv = inverse(&p).ok_or(SpaceError::Collinear)?;
    let s = mul_vec(&inv, xy_to_xyz(white));
    Ok(mul(&p, &diagonal(s)))
}

impl RgbSpace {
    /// A space from primaries and white point, with the derived matrix.
    pub fn new(
        name: &str,
        primaries: [[f64; 2]; 3],
        white: [f64; 2],
        white_name: &str,
        transfer: Transfer,
    ) -> Result<Self, SpaceError> {
        let to_xyz = normalised_primary_matrix(primaries, white)?;
        let from_xyz = inverse(&to_xyz).ok_or(SpaceError::Collinear)?;
        Ok(Self {
            name: name.into(),
            primaries,
            white,
            white_name: white_name.into(),
            to_xyz,
            from_xyz,
            transfer,
        })
    }

    fn derived(
        name: &str,
        primaries: [[f64; 2]; 3],
        white: Illuminant,
        transfer: Transfer,
    ) -> Self {
        let xy = white.xy(Observer::Cie1931);
        // The built-in primaries are valid; `new` cannot fail for them.
        Self::new(name, primaries, xy, white.name(), transfer).unwrap_or_else(|_| unreachable!())
    }

    /// sRGB (IEC 61966-2-1): BT.709 primaries, D65, with the standard's 4-decimal matrices.
    #[must_use]
    pub fn srgb() -> Self {
        Self {
            to_xyz: [
                [0.4124, 0.3576, 0.1805],
                [0.2126, 0.7152, 0.0722],
                [0.0193, 0.1192, 0.9505],
            ],
            from_xyz: [
                [3.2406, -1.5372, -0.4986],
                [-0.9689, 1.8758, 0.0415],
                [0.0557, -0.2040, 1.0570],
            ],
            ..Self::derived("sRGB", BT709_PRIMARIES, Illuminant::D65, Transfer::Srgb)
        }
    }

    /// ITU-R BT.709 (derived matrix, BT.709 curve).
    #[must_use]
    pub fn bt709() -> Self {
        Self::derived(
            "ITU-R BT.709",
            BT709_PRIMARIES,
            Illuminant::D65,
            Transfer::Bt709,
        )
    }

    /// Display P3: DCI-P3 primaries, D65 white, sRGB curve.
    #[must_use]
    pub fn display_p3() -> Self {
        Self::derived("Display P3", P3_PRIMARIES, Illuminant::D65, Transfer::Srgb)
    }

    /// DCI-P3 (digital cinema): P3 primaries, the DCI white (0.314, 0.351), gamma 2.6.
    #[must_use]
    pub fn dci_p3() -> Self {
        let s = Self::new(
            "DCI-P3",
            P3_PRIMARIES,
            [0.314, 0.351],
            "DCI-P3",
            Transfer::Gamma(2.6),
        );
        s.unwrap_or_else(|_| unreachable!())
    }

    /// ITU-R BT.2020 (UHD): D65, BT.709-style curve.
    #[must_use]
    pub fn rec2020() -> Self {
        let p = [[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]];
        Self::derived("ITU-R BT.2020", p, Illuminant::D65, Transfer::Bt709)
    }

    /// Adobe RGB (1998): D65, gamma 563/256, with Adobe's published 5-decimal matrices.
    #[must_use]
    pub fn adobe_rgb() -> Self {
        let p = [[0.64, 0.33], [0.21, 0.71], [0.15, 0.06]];
        Self {
            to_xyz: [
                [0.57667, 0.18556, 0.18823],
                [0.29734, 0.62736, 0.07529],
                [0.02703, 0.07069, 0.99134],
            ],
            from_xyz: [
                [2.04159, -0.56501, -0.34473],
                [-0.96924, 1.87597, 0.04156],
                [0.01344, -0.11836, 1.01517],
            ],
            ..Self::derived(
                "Adobe RGB (1998)",
                p,
                Illuminant::D65,
                Transfer::Gamma(563.0 / 256.0),
            )
        }
    }

    /// CIE RGB (1931): monochromatic primaries at 700, 546.1 and 435.8 nm, equal-energy
    /// white E, linear.
    #[must_use]
    pub fn cie_rgb() -> Self {
        let locus = SpectralLocus::new(Observer::Cie1931);
        let p = [700.0, 546.1, 435.8].map(|nm| locus.xy(nm));
        Self::derived("CIE RGB", p, Illuminant::E, Transfer::Linear)
    }

    /// A space by its command-line name: `srgb`, `bt709`, `display-p3`, `dci-p3`, `rec2020`
    /// (or `bt2020`), `adobe-rgb`, `cie-rgb` (case and `_`/`-` insensitive).
    #[must_use]
    pub fn named(name: &str) -> Option<Self> {
        let key: String = name
            .chars()
            .filter(|c| c.is_ascii_alphanumeric())
            .map(|c| c.to_ascii_lowercase())
            .collect();
        Some(match key.as_str() {
            "srgb" => Self::srgb(),
            "bt709" | "rec709" => Self::bt709(),
            "displayp3" | "p3" | "p3d65" => Self::display_p3(),
            "dcip3" => Self::dci_p3(),
            "rec2020" | "bt2020" => Self::rec2020(),
            "adobergb" | "adobergb1998" => Self::adobe_rgb(),
            "ciergb" => Self::cie_rgb(),
            _ => return None,
        })
    }

    /// Names accepted by [`RgbSpace::named`].
    pub const NAMES: [&'static str; 7] = [
        "srgb",
        "bt709",
        "display-p3",
        "dci-p3",
        "rec2020",
        "adobe-rgb",
        "cie-rgb",
    ];

    /// Linear RGB to XYZ.
    #[must_use]
    pub fn linear_to_xyz(&self, rgb: [f64; 3]) -> [f64; 3] {
        mul_vec(&self.to_xyz, rgb)
    }

    /// XYZ to linear RGB (unclipped).
    #[must_use]
    pub fn xyz_to_linear(&self, xyz: [f64; 3]) -> [f64; 3] {
        mul_vec(&self.from_xyz, xyz)
    }

    /// Encoded RGB to XYZ.
    #[must_use]
    pub fn encoded_to_xyz(&self, rgb: [f64; 3]) -> [f64; 3] {
        self.linear_to_xyz(rgb.map(|v| self.transfer.decode(v)))
    }

    /// XYZ to encoded RGB (unclipped).
    #[must_use]
    pub fn xyz_to_encoded(&self, xyz: [f64; 3]) -> [f64; 3] {
        self.xyz_to_linear(xyz).map(|v| self.transfer.encode(v))
    }

    /// Whether chromaticity `xy` lies inside the gamut triangle (edges included).
    #[must_use]
    pub fn contains_xy(&self, xy: [f64; 2]) -> bool {
        let [a, b, c] = self.primaries;
        let side = |p: [f64; 2], q: [f64; 2]| {
            (q[0] - p[0]) * (xy[1] - p[1]) - (q[1] - p[1]) * (xy[0] - p[0])
        };
        let (s0, s1, s2) = (side(a, b), side(b, c), side(c, a));
        (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0)
    }
}

/// ITU-R BT.709 / sRGB primaries.
pub const BT709_PRIMARIES: [[f64; 2]; 3] = [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]];
/// DCI-P3 / Display P3 primaries.
pub const P3_PRIMARIES: [[f64; 2]; 3] = [[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]];

/// The Bradford cone-response matrix.
pub const BRADFORD: Mat3 = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// The von Kries chromatic adaptation matrix in Bradford cone space that maps colours seen
/// under white `from` (XYZ, Y = 1) to the corresponding colours under white `to`.
#[must_use]
pub fn bradford(from: [f64; 3], to: [f64; 3]) -> Mat3 {
    let s = mul_vec(&BRADFORD, from);
    let d = mul_vec(&BRADFORD, to);
    let gain = diagonal([d[0] / s[0], d[1] / s[1], d[2] / s[2]]);
    let inv = inverse(&BRADFORD).unwrap_or_else(|| unreachable!());
    mul(&inv, &mul(&gain, &BRADFORD))
}

/// Adapts `xyz` from white `from` to white `to` (both XYZ with Y = 1) with Bradford.
#[must_use]
pub fn adapt(xyz: [f64; 3], from: [f64; 3], to: [f64; 3]) -> [f64; 3] {
    mul_vec(&bradford(from, to), xyz)
}
