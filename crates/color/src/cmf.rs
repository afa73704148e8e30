//! The CIE standard observers (colour-matching functions, 1 nm from 360 to 830 nm), the
//! spectral locus they trace, and the CIE illuminants' white points.

use super::cie::xyz_to_xyy;
use super::cmf_data::{CIE1931_2DEG, CIE1964_10DEG};

/// First wavelength of the tables, in nm.
pub const FIRST_NM: u32 = 360;
/// Last wavelength of the tables (inclusive), in nm.
pub const LAST_NM: u32 = 830;

/// A CIE standard colorimetric observer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Observer {
    /// CIE 1931 2 degree.
    Cie1931,
    /// CIE 1964 10 degree.
    Cie1964,
}

impl Observer {
    /// The 1 nm table, `[x̄, ȳ, z̄]` for 360..=830 nm.
    #[must_use]
    pub fn table(self) -> &'static [[f64; 3]; 471] {
        match self {
            Observer::Cie1931 => &CIE1931_2DEG,
            Observer::Cie1964 => &CIE1964_10DEG,
        }
    }

    /// The colour-matching functions at `nm`, linearly interpolated between the 1 nm rows
    /// (exact at whole nanometres); zero outside 360..=830 nm or for NaN.
    #[must_use]
    pub fn cmf(self, nm: f64) -> [f64; 3] {
        let t = self.table();
        let pos = nm - f64::from(FIRST_NM);
        if !(0.0..=f64::from(LAST_NM - FIRST_NM)).contains(&pos) {
            return [0.0; 3];
        }
        let i = (pos.floor() as usize).min(t.len() - 1);
        let f = pos - i as f64;
        if f == 0.0 {
            return t[i];
        }
        let (a, b) = (t[i], t[(i + 1).min(t.len() - 1)]);
        [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * f)
    }

    /// Display name, as the CIE and colour-science use it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Observer::Cie1931 => "CIE 1931 2 Degree Standard Observer",
            Observer::Cie1964 => "CIE 1964 10 Degree Standard Observer",
        }
    }
}

/// The spectral locus of an observer: the chromaticity of monochromatic light.
#[derive(Clone, Copy, Debug)]
pub struct SpectralLocus {
    pub observer: Observer,
}

impl SpectralLocus {
    #[must_use]
    pub fn new(observer: Observer) -> Self {
        Self { observer }
    }

    /// The xy chromaticity of monochromatic light at `nm` (360..=830).
    #[must_use]
    pub fn xy(&self, nm: f64) -> [f64; 2] {
        let [x, y, _] = xyz_to_xyy(self.observer.cmf(nm));
        [x, y]
    }

    /// The locus at every whole nanometre from `first` to `last` inclusive, as
    /// `(nm, [x, y])`.
    #[must_use]
    pub fn points(&self, first: u32, last: u32) -> Vec<(u32, [f64; 2])> {
        (first.max(FIRST_NM)..=last.min(LAST_NM))
            .map(|nm| (nm, self.xy(f64::from(nm))))
            .collect()
    }
}

/// A CIE illuminant (white point).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Illuminant {
    /// Tungsten-filament light, 2856 K.
    A,
    /// Average daylight (obsolete, the white of NTSC and of the textbook's chapter).
    C,
    /// Horizon daylight, ~5003 K: the white of print and ICC profile connection.
    D50,
    /// Noon daylight, ~6504 K: the white of sRGB and most displays.
    D65,
    /// Equal energy.
    E,
}

impl Illuminant {
    /// Every illuminant, in the order of the CLI's help.
    pub const ALL: [Illuminant; 5] = [
        Illuminant::A,
        Illuminant::C,
        Illuminant::D50,
        Illuminant::D65,
        Illuminant::E,
    ];

    /// The tabulated chromaticity (CIE 015:2018 Table T.3, 5 decimals; E exactly 1/3).
    #[must_use]
    pub fn xy(self, observer: Observer) -> [f64; 2] {
        match (self, observer) {
            (Illuminant::A, Observer::Cie1931) => [0.44758, 0.40745],
            (Illuminant::C, Observer::Cie1931) => [0.31006, 0.31616],
            (Illuminant::D50, Observer::Cie1931) => [0.3457, 0.3585],
            (Illuminant::D65, Observer::Cie1931) => [0.3127, 0.3290],
            (Illuminant::A, Observer::Cie1964) => [0.45117, 0.40594],
            (Illuminant::C, Observer::Cie1964) => [0.31039, 0.31905],
            (Illuminant::D50, Observer::Cie1964) => [0.34773, 0.35952],
            (Illuminant::D65, Observer::Cie1964) => [0.31382, 0.33100],
            (Illuminant::E, _) => [1.0 / 3.0, 1.0 / 3.0],
        }
    }

    /// The white point as XYZ with Y = 1.
    #[must_use]
    pub fn xyz(self, observer: Observer) -> [f64; 3] {
        super::cie::xy_to_xyz(self.xy(observer))
    }

    /// Short name, e.g. "D65".
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Illuminant::A => "A",
            Illuminant::C => "C",
            Illuminant::D50 => "D50",
            Illuminant::D65 => "D65",
            Illuminant::E => "E",
        }
    }

    /// By name, case-insensitive.
    #[must_use]
    pub fn named(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|i| i.name().eq_ignore_ascii_case(name.trim()))
    }
}
