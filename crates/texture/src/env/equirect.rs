//! The equirectangular image: storage ([`Plane`], flat RGB f32 rows from +Y down), the
//! direction/UV mapping in f32 and f64 (one formula, generated twice), bilinear sampling, and
//! loading Radiance `.hdr` / OpenEXR files under size limits with bad texels replaced.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use libm::Libm;

/// Largest accepted environment width or height, in texels.
pub const MAX_ENV_SIDE: u32 = 16384;
/// Most texels accepted in one environment image (64 Mi: 768 MiB of f32 RGB).
pub const MAX_ENV_TEXELS: u64 = 64 << 20;
/// Largest radiance kept; larger finite values are clamped to it (and counted), so sums in
/// f32 cannot overflow.
pub const MAX_RADIANCE: f32 = 1e30;

/// Why an environment image could not be made. Messages about a file start with its path.
#[derive(Debug, thiserror::Error)]
pub enum EnvError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: unsupported image format {format} (expected Radiance .hdr or OpenEXR .exr)")]
    Unsupported { path: PathBuf, format: String },
    #[error("{path}: not a Radiance .hdr or OpenEXR image (unknown contents)")]
    NotAnImage { path: PathBuf },
    #[error("{path}: cannot decode: {reason}")]
    Decode { path: PathBuf, reason: String },
    #[error("{path}: {width}x{height} texels, over the limit ({MAX_ENV_SIDE} a side, {MAX_ENV_TEXELS} in all)")]
    TooLarge {
        path: PathBuf,
        width: u32,
        height: u32,
    },
    #[error("environment image of {width}x{height} texels: {reason}")]
    BadSize {
        width: u32,
        height: u32,
        reason: String,
    },
}

macro_rules! equirect_mapping {
    ($dir_to_uv:ident, $texel_dir:ident, $f:ident, $v:ty) => {
        /// The (u, v) of a unit direction (module docs of `env`); u in [0, 1], v in [0, 1].
        /// A direction that is not unit length gives a wrong v; zero gives the image centre.
        #[inline]
        #[must_use]
        pub fn $dir_to_uv(d: $v) -> ($f, $f) {
            use std::$f::consts::PI;
            let u = 0.5 + Libm::<$f>::atan2(d.z, d.x) * (0.5 / PI);
            let v = Libm::<$f>::acos(d.y.clamp(-1.0, 1.0)) * (1.0 / PI);
            (u, v)
        }

        /// The direction through the centre of texel `(x, y)` of a `w×h` equirect image.
        #[inline]
        #[must_use]
        pub fn $texel_dir(x: usize, y: usize, w: usize, h: usize) -> $v {
            use std::$f::consts::PI;
            let phi = ((x as $f + 0.5) / w as $f - 0.5) * (2.0 * PI);
            let theta = (y as $f + 0.5) / h as $f * PI;
            let (st, ct) = Libm::<$f>::sincos(theta);
            let (sp, cp) = Libm::<$f>::sincos(phi);
            <$v>::new(st * cp, ct, st * sp)
        }
    };
}

equirect_mapping!(dir_to_uv, texel_dir, f32, Vec3);

/// The unit direction at image coordinates `(u, v)` ([`dir_to_uv`]'s inverse).
#[must_use]
pub(super) fn uv_dir(u: f32, v: f32) -> Vec3 {
    use std::f32::consts::PI;
    let (st, ct) = libm::sincosf(v * PI);
    let (sp, cp) = libm::sincosf((u - 0.5) * 2.0 * PI);
    Vec3::new(st * cp, ct, st * sp)
}
equirect_mapping!(dir_to_uv_f64, texel_dir_f64, f64, DVec3);

/// Bilinear taps of `(u, v)` on a `w×h` grid of texel centres: indices `(x0, x1, y0, y1)` and
/// weights `(tx, ty)` of `x1`, `y1`. u wraps, v clamps. NaN gives in-range indices.
macro_rules! bilinear_taps {
    ($u:expr, $v:expr, $w:expr, $h:expr, $f:ty) => {{
        let fx = $u * $w as $f - 0.5;
        let fy = $v * $h as $f - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let (w, h) = ($w as i64, $h as i64);
        // Float-to-int casts saturate (NaN -> 0), so every index is in range.
        // The usual case (u in [0, 1]) wraps by one period at most: no division.
        let xi = match x0 as i64 {
            x if (0..w).contains(&x) => x,
            x if (-w..0).contains(&x) => x + w,
            x => x.rem_euclid(w),
        };
        let yi = y0 as i64;
        let x1 = if xi + 1 == w { 0 } else { xi + 1 };
        (
            xi as usize,
            x1 as usize,
            yi.clamp(0, h - 1) as usize,
            yi.saturating_add(1).clamp(0, h - 1) as usize,
            tx,
            ty,
        )
    }};
}

/// A `width×height` RGB f32 equirect grid, rows from v = 0 (+Y) down, 3 floats a texel.
/// Invariant: `width, height >= 1` and `rgb.len() == 3·width·height`.
#[derive(Clone, PartialEq)]
pub(super) struct Plane {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<f32>,
}

impl Plane {
    #[inline(always)]
    pub fn texel(&self, x: usize, y: usize) -> Vec3 {
        let i = 3 * (y * self.width + x);
        Vec3::new(self.rgb[i], self.rgb[i + 1], self.rgb[i + 2])
    }

    fn texel_f64(&self, x: usize, y: usize) -> DVec3 {
        self.texel(x, y).as_dvec3()
    }

    /// Bilinear at (u, v).
    #[inline(always)]
    pub fn bilinear(&self, u: f32, v: f32) -> Vec3 {
        let (x0, x1, y0, y1, tx, ty) = bilinear_taps!(u, v, self.width, self.height, f32);
        let top = self.texel(x0, y0).lerp(self.texel(x1, y0), tx);
        let bottom = self.texel(x0, y1).lerp(self.texel(x1, y1), tx);
        top.lerp(bottom, ty)
    }

    /// Bilinear at (u, v), in f64.
    pub fn bilinear_f64(&self, u: f64, v: f64) -> DVec3 {
        let (x0, x1, y0, y1, tx, ty) = bilinear_taps!(u, v, self.width, self.height, f64);
        let top = self.texel_f64(x0, y0).lerp(self.texel_f64(x1, y0), tx);
        let bottom = self.texel_f64(x0, y1).lerp(self.texel_f64(x1, y1), tx);
        top.lerp(bottom, ty)
    }

    /// Bytes of texel storage.
    pub fn bytes(&self) -> usize {
        self.rgb.len() * 4
    }
}

/// An equirectangular, linear-RGB, f32 environment image (conventions: `env` module docs).
/// Every texel is finite, non-negative and at most [`MAX_RADIANCE`].
#[derive(Clone, PartialEq)]
pub struct EnvImage {
    name: String,
    pub(super) plane: Plane,
    replaced: usize,
}

impl std::fmt::Debug for EnvImage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EnvImage")
            .field("name", &self.name)
            .field("width", &self.plane.width)
            .field("height", &self.plane.height)
            .field("replaced", &self.replaced)
            .finish_non_exhaustive()
    }
}

/// Checks `width×height` against the limits.
fn check_size(width: u32, height: u32) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err("no texels".into());
    }
    if width > MAX_ENV_SIDE
        || height > MAX_ENV_SIDE
        || u64::from(width) * u64::from(height) > MAX_ENV_TEXELS
    {
        return Err(format!(
            "over the limit ({MAX_ENV_SIDE} a side, {MAX_ENV_TEXELS} in all)"
        ));
    }
    Ok(())
}

impl EnvImage {
    /// An image from `width×height` texels, rows from the top (+Y). NaN, infinite and negative
    /// channels become 0 and channels above [`MAX_RADIANCE`] are clamped; the texels touched
    /// are counted ([`EnvImage::replaced_texels`]). Named `"rgb"` ([`EnvImage::with_name`]).
    ///
    /// # Errors
    /// [`EnvError::BadSize`] if a side is 0, the size is over [`MAX_ENV_SIDE`] /
    /// [`MAX_ENV_TEXELS`], or `texels.len() != width·height`.
    pub fn from_rgb(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Result<Self, EnvError> {
        let bad = |reason: String| EnvError::BadSize {
            width,
            height,
            reason,
        };
        check_size(width, height).map_err(bad)?;
        let n = width as usize * height as usize;
        if texels.len() != n {
            return Err(bad(format!("{} texels given, {n} needed", texels.len())));
        }
        Ok(Self::from_flat(
            "rgb",
            width as usize,
            height as usize,
            texels.into_iter().flatten().collect(),
        ))
    }

    /// From flat RGB (`3·width·height` floats, checked by the caller), sanitising texels.
    pub(super) fn from_flat(name: &str, width: usize, height: usize, mut rgb: Vec<f32>) -> Self {
        debug_assert_eq!(rgb.len(), 3 * width * height);
        let mut replaced = 0;
        for t in rgb.chunks_exact_mut(3) {
            let mut bad = false;
            for c in t {
                if !c.is_finite() || *c < 0.0 {
                    *c = 0.0;
                    bad = true;
                } else if *c > MAX_RADIANCE {
                    *c = MAX_RADIANCE;
                    bad = true;
                }
            }
            replaced += usize::from(bad);
        }
        Self {
            name: name.to_owned(),
            plane: Plane { width, height, rgb },
            replaced,
        }
    }

    /// From a plane whose texels are already valid (built-ins, resampling).
    pub(super) fn from_plane(name: &str, plane: Plane) -> Self {
        Self {
            name: name.to_owned(),
            plane,
            replaced: 0,
        }
    }

    /// Loads a Radiance `.hdr` or OpenEXR file (format guessed from the contents, then the
    /// extension), refusing sizes over [`MAX_ENV_SIDE`] / [`MAX_ENV_TEXELS`] from the header
    /// before decoding. Alpha is dropped; bad texels are replaced as in [`EnvImage::from_rgb`]
    /// and counted in [`EnvImage::replaced_texels`]. Named after the file's name.
    ///
    /// # Errors
    /// Each [`EnvError`] names the file: missing or unreadable, not an image, another image
    /// format, too large, or undecodable (truncated, corrupt; a decoder panic is caught).
    pub fn load(path: &Path) -> Result<Self, EnvError> {
        let io = |source| EnvError::Io {
            path: path.to_owned(),
            source,
        };
        let decode = |reason: String| EnvError::Decode {
            path: path.to_owned(),
            reason,
        };
        let open = || -> Result<image::ImageReader<_>, EnvError> {
            let reader = image::ImageReader::open(path)
                .map_err(io)?
                .with_guessed_format()
                .map_err(io)?;
            match reader.format() {
                Some(image::ImageFormat::Hdr | image::ImageFormat::OpenExr) => Ok(reader),
                Some(other) => Err(EnvError::Unsupported {
                    path: path.to_owned(),
                    format: format!("{other:?}"),
                }),
                None => Err(EnvError::NotAnImage {
                    path: path.to_owned(),
                }),
            }
        };
        let (width, height) = open()?
            .into_dimensions()
            .map_err(|e| decode(e.to_string()))?;
        if check_size(width, height).is_err() {
            return Err(EnvError::TooLarge {
                path: path.to_owned(),
                width,
                height,
            });
        }
        let mut reader = open()?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_ENV_SIDE);
        limits.max_image_height = Some(MAX_ENV_SIDE);
        // RGBA f32 as decoded plus the decoder's own buffers.
        limits.max_alloc = Some(u64::from(width) * u64::from(height) * 16 + (64 << 20));
        reader.limits(limits);
        let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| reader.decode()))
            .map_err(|_| decode("the decoder panicked".into()))?
            .map_err(|e| decode(e.to_string()))?;
        let (w, h) = (decoded.width() as usize, decoded.height() as usize);
        if check_size(decoded.width(), decoded.height()).is_err() {
            return Err(decode(format!(
                "decoded {w}x{h} texels, header said {width}x{height}"
            )));
        }
        let rgb = decoded.into_rgb32f().into_raw();
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        Ok(Self::from_flat(&name, w, h, rgb))
    }

    /// The same image under another name.
    #[must_use]
    pub fn with_name(mut self, name: &str) -> Self {
        name.clone_into(&mut self.name);
        self
    }

    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Width in texels (u direction).
    #[must_use]
    pub fn width(&self) -> u32 {
        self.plane.width as u32
    }

    /// Height in texels (v direction).
    #[must_use]
    pub fn height(&self) -> u32 {
        self.plane.height as u32
    }

    /// Texels whose NaN, infinite, negative or too large channels were replaced on the way in.
    #[must_use]
    pub fn replaced_texels(&self) -> usize {
        self.replaced
    }

    /// Texel `(x, y)`, or `None` outside the image.
    #[must_use]
    pub fn texel(&self, x: u32, y: u32) -> Option<Vec3> {
        (x < self.width() && y < self.height()).then(|| self.plane.texel(x as usize, y as usize))
    }

    /// The flat RGB texels, rows from the top, 3 floats a texel.
    #[must_use]
    pub fn rgb(&self) -> &[f32] {
        &self.plane.rgb
    }

    /// Bilinear radiance from direction `dir` (any length; zero reads the image centre).
    #[must_use]
    pub fn sample(&self, dir: Vec3) -> Vec3 {
        let (u, v) = dir_to_uv(dir.normalize_or_zero());
        self.plane.bilinear(u, v)
    }

    /// [`EnvImage::sample`] in f64.
    #[must_use]
    pub fn sample_f64(&self, dir: DVec3) -> DVec3 {
        let (u, v) = dir_to_uv_f64(dir.normalize_or_zero());
        self.plane.bilinear_f64(u, v)
    }
}
