//! The CIE chromaticity diagram: the spectral locus closed by the purple line, filled with
//! the colours it stands for, with wavelength ticks, axes and grid, RGB gamut triangles
//! with their white points and a legend, the Planckian locus with iso-temperature ticks,
//! named illuminants, user points and the chromaticities of an image's pixels; in the CIE
//! 1931 xy, CIE 1960 uv or CIE 1976 u'v' plane.
//!
//! [`diagram`] builds a [`Canvas`](super::Canvas) (so the same drawing goes to PNG, SVG or
//! the viewer as a tiny-skia `Pixmap`); `realist chroma` is its command line. Layout scales
//! with the size; every length below is given for a 1024 px diagram.
//!
//! | file | owns |
//! |---|---|
//! | `draw.rs` | layout and drawing |
//! | `raster.rs` | the raster layers: the fill, an image's pixels |
//! | `fill.rs` | the colours inside the horseshoe (smooth gamut mapping) |
//! | `gamut.rs` | areas, intersections, coverage |
//! | `pixels.rs` | an image's chromaticities: histogram and out-of-gamut fractions |

mod draw;
pub mod fill;
pub mod gamut;
pub mod pixels;
mod raster;

pub use draw::diagram;
pub use fill::FillStyle;
pub use pixels::{PixelReport, PixelStyle};

use crate::color::{self, Observer, RgbSpace};

/// The chromaticity plane of a diagram.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Plane {
    /// CIE 1931 xy.
    #[default]
    Xy,
    /// CIE 1960 UCS uv.
    Uv,
    /// CIE 1976 UCS u'v'.
    UvPrime,
}

impl Plane {
    /// Coordinates in this plane of chromaticity `xy`.
    #[must_use]
    pub fn from_xy(self, xy: [f64; 2]) -> [f64; 2] {
        match self {
            Plane::Xy => xy,
            Plane::Uv => color::xy_to_uv1960(xy),
            Plane::UvPrime => color::xy_to_uv_prime(xy),
        }
    }

    /// Chromaticity xy of coordinates `p` in this plane.
    #[must_use]
    pub fn to_xy(self, p: [f64; 2]) -> [f64; 2] {
        match self {
            Plane::Xy => p,
            Plane::Uv => color::uv1960_to_xy(p),
            Plane::UvPrime => color::uv_prime_to_xy(p),
        }
    }

    /// Axis names.
    #[must_use]
    pub fn axes(self) -> (&'static str, &'static str) {
        match self {
            Plane::Xy => ("CIE x", "CIE y"),
            Plane::Uv => ("CIE u", "CIE v"),
            Plane::UvPrime => ("CIE u\u{2032}", "CIE v\u{2032}"),
        }
    }

    /// Title of the plane, e.g. "CIE 1931 Chromaticity Diagram".
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            Plane::Xy => "CIE 1931 Chromaticity Diagram",
            Plane::Uv => "CIE 1960 UCS Chromaticity Diagram",
            Plane::UvPrime => "CIE 1976 UCS Chromaticity Diagram",
        }
    }

    /// The plotted range `[u0, u1, v0, v1]` (colour-science's overlay boxes).
    #[must_use]
    pub fn bounds(self) -> [f64; 4] {
        match self {
            Plane::Xy => [-0.1, 0.9, -0.1, 0.9],
            Plane::Uv => [-0.1, 0.7, -0.2, 0.6],
            Plane::UvPrime => [-0.1, 0.7, -0.1, 0.7],
        }
    }

    /// Wavelengths labelled on the locus (colour-science's defaults).
    #[must_use]
    pub fn wavelength_labels(self) -> &'static [u32] {
        match self {
            Plane::Xy => &[
                390, 460, 470, 480, 490, 500, 510, 520, 540, 560, 580, 600, 620, 700,
            ],
            Plane::Uv | Plane::UvPrime => &[
                420, 440, 450, 460, 470, 480, 490, 500, 510, 520, 530, 540, 550, 560, 570, 580,
                590, 600, 610, 620, 630, 645, 680,
            ],
        }
    }

    /// By command-line name: `xy`, `uv` (1960) or `u'v'` (also `upvp`, `1976`).
    #[must_use]
    pub fn named(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "xy" | "1931" => Some(Plane::Xy),
            "uv" | "1960" => Some(Plane::Uv),
            "u'v'" | "upvp" | "uvp" | "1976" => Some(Plane::UvPrime),
            _ => None,
        }
    }
}

/// A labelled chromaticity to mark on the diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    pub xy: [f64; 2],
    pub label: String,
}

/// Temperatures labelled on the Planckian locus (colour-science's defaults), in K.
pub const PLANCKIAN_LABELS_K: [f64; 7] =
    [1e6 / 600.0, 2000.0, 2500.0, 3000.0, 4000.0, 6000.0, 10000.0];

/// Everything a diagram shows.
#[derive(Clone, Debug)]
pub struct ChromaOptions {
    pub plane: Plane,
    /// Width and height in pixels.
    pub size: u32,
    pub observer: Observer,
    pub fill: FillStyle,
    /// Gamut triangles, drawn with their white points and listed in the legend.
    pub gamuts: Vec<RgbSpace>,
    /// Named white points (illuminants).
    pub illuminants: Vec<Marker>,
    /// Draw the Planckian locus with iso-temperature ticks.
    pub planckian: bool,
    /// User points (e.g. from a CSV file).
    pub points: Vec<Marker>,
    /// An image's chromaticities.
    pub pixels: Option<PixelReport>,
    pub pixel_style: PixelStyle,
    /// Title; `None` gives "gamuts - observer - plane".
    pub title: Option<String>,
}

impl Default for ChromaOptions {
    fn default() -> Self {
        Self {
            plane: Plane::Xy,
            size: 1024,
            observer: Observer::Cie1931,
            fill: FillStyle::Smooth,
            gamuts: Vec::new(),
            illuminants: Vec::new(),
            planckian: false,
            points: Vec::new(),
            pixels: None,
            pixel_style: PixelStyle::Scatter,
            title: None,
        }
    }
}

/// The diagram as a tiny-skia pixmap (for the viewer's panel or overlay).
#[must_use]
pub fn diagram_pixmap(opts: &ChromaOptions) -> tiny_skia::Pixmap {
    diagram(opts).to_pixmap()
}
