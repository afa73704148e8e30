//! Colour: the float RGBA type of the renderer ([`Rgba`]), device colour models (HSV, HSL,
//! CMY(K), YIQ, YUV, YCbCr), and colorimetry: the CIE standard observers, XYZ and the spaces
//! derived from it (xyY, CIE 1960 uv, CIE 1976 u'v', Lab, LCh, Luv), colour differences,
//! RGB colour spaces from primaries and white point with Bradford adaptation, illuminants,
//! and the Planckian locus with correlated colour temperature.
//!
//! Colorimetry is in f64 and follows colour-science's conventions (its reference values are
//! the tests: `tests/color_reference.rs`): XYZ scaled so the white has Y = 1, L\* in [0, 100],
//! hue in [0, 1) for HSV/HSL and in degrees for LCh, D65 and the 2 degree observer unless a
//! function takes a white point. Encoded sRGB is the working model of files and screens;
//! [`srgb_to_xyz`] and [`xyz_to_srgb`] connect it to XYZ.
//!
//! | file | owns |
//! |---|---|
//! | `rgba.rs` | [`Rgba`]: arithmetic, clamping, max-normalisation, tone mapping, blending |
//! | `transfer.rs` | the sRGB transfer functions |
//! | `models.rs` | HSV, HSL, CMY, CMYK, YIQ, YUV, YCbCr |
//! | `named.rs` | one colour read from text and given in every model by name (`realist color`, Python) |
//! | `cie.rs` | xyY, uv, u'v', Lab, LCh, Luv |
//! | `delta_e.rs` | ΔE 1976, 1994, 2000 |
//! | `space.rs` | RGB spaces, matrices from primaries, transfer curves, Bradford |
//! | `cmf.rs`, `cmf_data.rs` | the CIE 1931 and 1964 observers at 1 nm, spectral locus, illuminants |
//! | `png.rs` | the one PNG writer, with the image's metadata |
//! | `planck.rs` | Planckian locus (integrated and approximated), daylight locus, CCT |
//! | `thin_film.rs` | the exact colour of a thin dielectric film (Airy, spectral) |

mod cie;
mod cmf;
mod cmf_data;
mod delta_e;
mod matrix;
mod models;
pub mod named;
mod planck;
pub mod png;
mod rgba;
mod space;
pub mod thin_film;
mod transfer;

pub use cie::*;
pub use cmf::{Illuminant, Observer, SpectralLocus, FIRST_NM, LAST_NM};
pub use delta_e::{delta_e_1976, delta_e_1994, delta_e_2000};
pub use matrix::Mat3;
pub use models::*;
pub use planck::*;
pub use rgba::Rgba;
pub use space::{
    adapt, bradford, normalised_primary_matrix, RgbSpace, SpaceError, Transfer, BRADFORD,
};
pub use transfer::{
    linear_to_srgb, srgb8, srgb8_decode, srgb8_decode_table, srgb8_f64, srgb_decode, srgb_decode3,
    srgb_encode, srgb_encode3, srgb_to_linear, unorm8, Srgb8Table, ENCODE_STEPS,
};

/// Encoded sRGB (components in [0, 1]) to XYZ (D65, Y of white = 1), with the IEC matrix.
#[must_use]
pub fn srgb_to_xyz(rgb: [f64; 3]) -> [f64; 3] {
    RgbSpace::srgb().encoded_to_xyz(rgb)
}

/// XYZ to encoded sRGB (unclipped), with the IEC matrix.
#[must_use]
pub fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    RgbSpace::srgb().xyz_to_encoded(xyz)
}

/// Encoded sRGB to CIE L\*a\*b\* relative to D65 (2 degree observer).
#[must_use]
pub fn srgb_to_lab(rgb: [f64; 3]) -> [f64; 3] {
    xyz_to_lab(srgb_to_xyz(rgb), Illuminant::D65.xyz(Observer::Cie1931))
}
