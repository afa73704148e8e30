//! Procedural ("function") textures, the textbook's §9.5: a colour computed from the sample
//! point instead of read from an image. Usable in any colour slot (a linear-light RGBA
//! colour) and as a bump-map height (a scalar in `[0, 1]`).
//!
//! - [`Procedural`] describes a texture as a user or a scene file states it, colours in sRGB;
//!   [`ProceduralTexture`] is its prepared form (colours decoded to linear light once,
//!   parameters clamped to their documented ranges), which the shaders evaluate.
//! - 2D patterns ([`Domain::Uv`]): the chequerboard and a UV test grid, repeating per unit of
//!   UV (glTF convention: origin top left, v downwards). 3D solid textures
//!   ([`Domain::Object`]): wood, marble and fBm noise, read at an object-space position,
//!   best normalised to the model's bounds ([`UvFrame::local`](super::UvFrame::local)) so
//!   the parameters mean the same on any model.
//!
//! # Antialiasing
//!
//! A procedural texture has no mip chain; evaluated at pixel centres it aliases when
//! minified. Every evaluation therefore takes the sample's footprint ([`SamplePoint`]): UV
//! derivatives for 2D patterns, a width in object units for solid ones. The 2D patterns are
//! box-filtered exactly over the footprint's axis-aligned box, `max(|d/dx|, |d/dy|)` wide
//! per axis (`procedural/pattern.rs`); solid textures attenuate their periodic part by the
//! exact Gaussian response of a cosine and clamp noise octaves above the Nyquist limit
//! (`procedural/solid.rs`, `noise.rs`). A zero footprint is a point sample; a footprint of
//! many periods gives the texture's mean colour, the linear-light average of its colours.
//!
//! # Robustness
//!
//! No input makes a NaN or infinite output: a non-finite UV or position gives the mean
//! colour (as an infinitely wide footprint would), a NaN footprint is a point sample, an
//! infinite one the mean; parameters out of range are clamped and NaN colour components read
//! as 0.

mod names;
mod pattern;
mod sample;
mod solid;

#[cfg(test)]
mod tests;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::{linear_to_srgb, srgb_to_linear};
pub use names::{ParseProceduralError, PROCEDURAL_NAMES};
pub use pattern::MAX_GRID_CELLS;
pub use sample::SamplePoint;

/// Most chequer squares per unit of UV.
pub const MAX_CHECKER_SQUARES: u32 = 4096;

/// Largest baked image side, in texels.
pub const MAX_BAKE: u32 = 4096;

/// Smallest finite-difference step of [`ProceduralTexture::height_gradient`] (in UV or
/// object units), used when the footprint is narrower.
pub const MIN_GRADIENT_STEP: f32 = 1e-4;

/// Frequencies and ring counts are clamped to `[MIN_FREQUENCY, MAX_FREQUENCY]`.
pub const MIN_FREQUENCY: f32 = 1e-3;
/// See [`MIN_FREQUENCY`].
pub const MAX_FREQUENCY: f32 = 1e4;
/// Noise amplitudes (wood wobble, marble turbulence) are clamped to `[0, MAX_AMOUNT]`.
pub const MAX_AMOUNT: f32 = 100.0;

/// A procedural texture as described; colours are sRGB-encoded, each component in `[0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub enum Procedural {
    /// `n` x `n` squares per unit of UV (`1..=MAX_CHECKER_SQUARES`); the top-left square is `a`.
    Checker { n: u32, a: [f32; 3], b: [f32; 3] },
    /// UV test grid of `cells` x `cells` per unit of UV (`1..=MAX_GRID_CELLS`): a hue per
    /// column (red at the left, round the colour wheel), lighter rows at the top, dark
    /// lines, and a white letter F in every cell, which shows any flip or rotation.
    Grid { cells: u32 },
    /// Concentric rings around the object's Y axis, `rings` per unit of radius, wobbled by
    /// fBm noise of `wobble` ring widths; `light` between the rings, `dark` on them.
    Wood {
        rings: f32,
        wobble: f32,
        light: [f32; 3],
        dark: [f32; 3],
    },
    /// Perlin's marble: veins across object x, `frequency` per unit, displaced along x by
    /// `turbulence` times the turbulence of the point, mixing `base` and `vein`.
    Marble {
        frequency: f32,
        turbulence: f32,
        base: [f32; 3],
        vein: [f32; 3],
    },
    /// fBm of gradient noise at `frequency` per object unit with `octaves` octaves
    /// (`1..=MAX_OCTAVES`), a height map from `low` (0) to `high` (1).
    Noise {
        frequency: f32,
        octaves: u32,
        low: [f32; 3],
        high: [f32; 3],
    },
}

/// What a texture reads from the sample point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    /// `uv`, `duv_dx`, `duv_dy`.
    Uv,
    /// `position`, `width`.
    Object,
}

/// An sRGB-encoded component (NaN read as 0, clamped to `[0, 1]`) in linear light.
fn linear(c: f32) -> f32 {
    srgb_to_linear(if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) })
}

fn linear3(c: [f32; 3]) -> Vec3 {
    Vec3::from_array(c.map(linear))
}

/// A frequency clamped to its range; NaN gives `default`.
fn frequency(f: f32, default: f32) -> f64 {
    f64::from(if f.is_nan() { default } else { f }.clamp(MIN_FREQUENCY, MAX_FREQUENCY))
}

/// An amplitude clamped to `[0, MAX_AMOUNT]`; NaN gives 0.
fn amount(a: f32) -> f64 {
    f64::from(if a.is_nan() {
        0.0
    } else {
        a.clamp(0.0, MAX_AMOUNT)
    })
}

/// The prepared pattern.
#[derive(Clone, Debug, PartialEq)]
enum Pattern {
    Checker {
        n: f64,
    },
    /// Boxed: its colour tables are large.
    Grid(Box<pattern::Grid>),
    Wood {
        rings: f64,
        wobble: f64,
    },
    Marble {
        frequency: f64,
        turbulence: f64,
    },
    Noise {
        frequency: f64,
        octaves: u32,
    },
}

/// A [`Procedural`] ready to evaluate: colours in linear light, parameters in range.
#[derive(Clone, Debug, PartialEq)]
pub struct ProceduralTexture {
    source: Procedural,
    pattern: Pattern,
    /// The colours at height 0 and 1 (unused by the grid).
    ends: [Vec3; 2],
}

impl From<Procedural> for ProceduralTexture {
    fn from(p: Procedural) -> Self {
        Self::new(p)
    }
}

/// A baked image: row-major RGBA8 texels, sRGB-encoded, alpha 255.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Baked {
    pub width: u32,
    pub height: u32,
    /// `width * height` texels, top row first (as [`Texture::texels`](super::Texture)).
    pub texels: Vec<[u8; 4]>,
}

impl ProceduralTexture {
    /// Prepares `source`: clamps its parameters and decodes its colours to linear light.
    #[must_use]
    pub fn new(source: Procedural) -> Self {
        let (pattern, ends) = match &source {
            Procedural::Checker { n, a, b } => (
                Pattern::Checker {
                    n: f64::from((*n).clamp(1, MAX_CHECKER_SQUARES)),
                },
                [linear3(*a), linear3(*b)],
            ),
            Procedural::Grid { cells } => (
                Pattern::Grid(Box::new(pattern::Grid::new(*cells))),
                [Vec3::ZERO; 2],
            ),
            Procedural::Wood {
                rings,
                wobble,
                light,
                dark,
            } => (
                Pattern::Wood {
                    rings: frequency(*rings, 8.0),
                    wobble: amount(*wobble),
                },
                [linear3(*light), linear3(*dark)],
            ),
            Procedural::Marble {
                frequency: f,
                turbulence,
                base,
                vein,
            } => (
                Pattern::Marble {
                    frequency: frequency(*f, 2.0),
                    turbulence: amount(*turbulence),
                },
                [linear3(*base), linear3(*vein)],
            ),
            Procedural::Noise {
                frequency: f,
                octaves,
                low,
                high,
            } => (
                Pattern::Noise {
                    frequency: frequency(*f, 4.0),
                    octaves: (*octaves).clamp(1, super::noise::MAX_OCTAVES),
                },
                [linear3(*low), linear3(*high)],
            ),
        };
        Self {
            source,
            pattern,
            ends,
        }
    }

    /// The description this texture was prepared from.
    #[must_use]
    pub fn source(&self) -> &Procedural {
        &self.source
    }

    /// Which fields of a [`SamplePoint`] the texture reads.
    #[must_use]
    pub fn domain(&self) -> Domain {
        match self.pattern {
            Pattern::Checker { .. } | Pattern::Grid(_) => Domain::Uv,
            Pattern::Wood { .. } | Pattern::Marble { .. } | Pattern::Noise { .. } => Domain::Object,
        }
    }

    /// The filtered colour at `s` in linear light (alpha 1), never NaN.
    #[must_use]
    pub fn color(&self, s: &SamplePoint) -> Vec4 {
        let rgb = match &self.pattern {
            Pattern::Grid(g) => self.grid(g, s).0,
            _ => {
                let t = self.height(s);
                self.ends[0].lerp(self.ends[1], t)
            }
        };
        rgb.extend(1.0)
    }

    /// The filtered height at `s` in `[0, 1]`, never NaN: the scalar the colour mixes by
    /// (chequer: the share of `b` squares; grid: 1 in cells, 0 on lines and letters; wood:
    /// 1 on the dark rings; marble: 1 in the veins; noise: the fBm).
    #[must_use]
    pub fn height(&self, s: &SamplePoint) -> f32 {
        let h = match &self.pattern {
            Pattern::Checker { n } => match s.uv_box(*n) {
                Some((x, y)) => pattern::checker_odd(x, y),
                None => 0.5,
            },
            Pattern::Grid(g) => return self.grid(g, s).1,
            &Pattern::Wood { rings, wobble } => {
                let (p, w) = s.object();
                solid::wood(p, w, rings, wobble)
            }
            &Pattern::Marble {
                frequency,
                turbulence,
            } => {
                let (p, w) = s.object();
                solid::marble(p, w, frequency, turbulence)
            }
            &Pattern::Noise { frequency, octaves } => {
                let (p, w) = s.object();
                solid::noise_height(p, w, frequency, octaves)
            }
        };
        h.clamp(0.0, 1.0) as f32
    }

    fn grid(&self, g: &pattern::Grid, s: &SamplePoint) -> (Vec3, f32) {
        let (x, y) = s
            .uv_box(f64::from(g.cells()))
            .unwrap_or(((0.0, f64::INFINITY), (0.0, f64::INFINITY)));
        let (rgb, h) = g.filtered(x, y);
        (rgb, h as f32)
    }

    /// The gradient of [`height`](Self::height) with respect to the domain's coordinates,
    /// by central differences: `(dh/du, dh/dv, 0)` for [`Domain::Uv`], `(dh/dx, dh/dy,
    /// dh/dz)` for [`Domain::Object`]. The step is the footprint (at least
    /// [`MIN_GRADIENT_STEP`]), so a bump map is no sharper than its filtered height.
    #[must_use]
    pub fn height_gradient(&self, s: &SamplePoint) -> Vec3 {
        let diff = |a: SamplePoint, b: SamplePoint, step: f32| {
            let d = (self.height(&b) - self.height(&a)) / (2.0 * step);
            if d.is_finite() {
                d
            } else {
                0.0
            }
        };
        match self.domain() {
            Domain::Uv => {
                let width = s.duv_dx.abs().max(s.duv_dy.abs());
                let step = width.max_element().max(MIN_GRADIENT_STEP);
                let at = |d: Vec2| SamplePoint { uv: s.uv + d, ..*s };
                Vec3::new(
                    diff(at(-step * Vec2::X), at(step * Vec2::X), step),
                    diff(at(-step * Vec2::Y), at(step * Vec2::Y), step),
                    0.0,
                )
            }
            Domain::Object => {
                let step = s.object().1.max(f64::from(MIN_GRADIENT_STEP)) as f32;
                let at = |d: Vec3| SamplePoint {
                    position: s.position + d,
                    ..*s
                };
                Vec3::from_array(
                    [Vec3::X, Vec3::Y, Vec3::Z].map(|e| diff(at(-step * e), at(step * e), step)),
                )
            }
        }
    }

    /// The texture as an sRGB RGBA8 image of `width` x `height` texels (each clamped to
    /// `MAX_BAKE`; 0 gives an empty image), antialiased with a one-texel footprint: a 2D
    /// pattern over one unit of UV, a solid texture on the slice `y = 0` seen from above
    /// (across the wood's rings), `x` from -1 to 1 rightwards and `z` from -1 to 1 downwards.
    #[must_use]
    pub fn bake(&self, width: u32, height: u32) -> Baked {
        let (w, h) = (width.min(MAX_BAKE), height.min(MAX_BAKE));
        let mut texels = vec![[0u8; 4]; w as usize * h as usize];
        let (fw, fh) = (w as f32, h as f32);
        if w > 0 {
            texels
                .par_chunks_mut(w as usize)
                .enumerate()
                .for_each(|(y, row)| {
                    for (x, texel) in row.iter_mut().enumerate() {
                        let (u, v) = ((x as f32 + 0.5) / fw, (y as f32 + 0.5) / fh);
                        let s = match self.domain() {
                            Domain::Uv => SamplePoint::uv_grad(
                                Vec2::new(u, v),
                                Vec2::new(1.0 / fw, 0.0),
                                Vec2::new(0.0, 1.0 / fh),
                            ),
                            Domain::Object => SamplePoint::position(
                                Vec3::new(2.0 * u - 1.0, 0.0, 2.0 * v - 1.0),
                                2.0 / fw.max(fh),
                            ),
                        };
                        *texel = encode(self.color(&s));
                    }
                });
        }
        Baked {
            width: w,
            height: h,
            texels,
        }
    }
}

/// Linear RGBA to sRGB-encoded RGBA8.
fn encode(c: Vec4) -> [u8; 4] {
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    [
        byte(linear_to_srgb(c.x)),
        byte(linear_to_srgb(c.y)),
        byte(linear_to_srgb(c.z)),
        byte(c.w),
    ]
}
