//! Texels in f64: exact sRGB decoding, wrap modes, nearest and bilinear reconstruction.

use super::*;

/// Exact sRGB decoding of the 256 byte values, in f64.
pub(super) fn srgb_table() -> &'static [f64; 256] {
    static TABLE: OnceLock<[f64; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| crate::color::srgb_decode(i as f64 / 255.0)))
}

/// Texel (x, y) in linear light, 8-bit sRGB decoded exactly in f64; transparent black
/// outside the texel array.
pub(crate) fn texel(t: &Texture, x: u32, y: u32) -> DVec4 {
    if x >= t.width || y >= t.height {
        return DVec4::ZERO;
    }
    let i = y as usize * t.width as usize + x as usize;
    match &t.texels {
        Texels::Srgb8(p) => {
            let (p, lin) = (p[i], srgb_table());
            DVec4::new(
                lin[p[0] as usize],
                lin[p[1] as usize],
                lin[p[2] as usize],
                f64::from(p[3]) / 255.0,
            )
        }
        Texels::Linear8(p) => DVec4::from_array(p[i].map(f64::from)) / 255.0,
        Texels::Linear16(p) => DVec4::from_array(p[i].map(f64::from)) / 65535.0,
        Texels::Float(p) => DVec4::from_array(p[i].map(f64::from)),
    }
}

pub(super) fn fetch(t: &Texture, x: u32, y: u32) -> DVec4 {
    texel(t, x, y)
}

/// `Texture::sample_with` in f64: same UV convention (origin at the top-left texel corner,
/// texel centres at half-integers), wrap modes and filter; non-finite UVs read (0, 0).
pub(super) fn sample_texture(t: &Texture, uv: DVec2, s: Sampler) -> DVec4 {
    if t.width == 0 || t.height == 0 {
        return DVec4::ONE;
    }
    let uv = if uv.is_finite() { uv } else { DVec2::ZERO };
    let (u, v) = (reduce(uv.x, s.wrap_u), reduce(uv.y, s.wrap_v));
    let (w, h) = (f64::from(t.width), f64::from(t.height));
    match s.filter {
        Filter::Nearest => fetch(
            t,
            wrap_index((u * w).floor(), t.width, s.wrap_u),
            wrap_index((v * h).floor(), t.height, s.wrap_v),
        ),
        // Mipmapping (and anisotropic filtering) approximates the footprint filter that the
        // supersampling computes here, so the ideal of a mipmapped texture is its base
        // level, read bilinearly.
        Filter::Bilinear | Filter::Trilinear | Filter::Anisotropic(_) => {
            let (fx, fy) = (u * w - 0.5, v * h - 0.5);
            let (x0, y0) = (fx.floor(), fy.floor());
            let (tx, ty) = (fx - x0, fy - y0);
            let xs = [x0, x0 + 1.0].map(|x| wrap_index(x, t.width, s.wrap_u));
            let ys = [y0, y0 + 1.0].map(|y| wrap_index(y, t.height, s.wrap_v));
            let top = fetch(t, xs[0], ys[0]).lerp(fetch(t, xs[1], ys[0]), tx);
            let bottom = fetch(t, xs[0], ys[1]).lerp(fetch(t, xs[1], ys[1]), tx);
            top.lerp(bottom, ty)
        }
    }
}

/// Removes whole wrap periods (see `texture::reduce`).
pub(super) fn reduce(t: f64, wrap: Wrap) -> f64 {
    match wrap {
        Wrap::Repeat => t - t.floor(),
        Wrap::MirroredRepeat => t.rem_euclid(2.0),
        Wrap::ClampToEdge => t.clamp(-1.0, 2.0),
    }
}

/// Folds an integer texel coordinate into 0..n.
pub(super) fn wrap_index(i: f64, n: u32, wrap: Wrap) -> u32 {
    let nf = f64::from(n);
    match wrap {
        Wrap::ClampToEdge => i.clamp(0.0, nf - 1.0) as u32,
        Wrap::Repeat => (i.rem_euclid(nf) as u32).min(n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2.0 * nf);
            let m = if m >= nf { 2.0 * nf - 1.0 - m } else { m };
            (m.max(0.0) as u32).min(n - 1)
        }
    }
}
