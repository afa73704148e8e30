//! The sRGB transfer functions of IEC 61966-2-1, exactly as the standard states them
//! (piecewise: a linear segment near black, a 2.4 power above). Values below zero stay on
//! the linear segment, so out-of-gamut negatives survive a round trip (as in colour-science).

/// Encoded sRGB value below which [`srgb_decode`] is linear.
const DECODE_KNEE: f64 = 0.04045;
/// Linear value below which [`srgb_encode`] is linear (`DECODE_KNEE / 12.92`, as published).
const ENCODE_KNEE: f64 = 0.003_130_8;

/// The transfer pair for one float width, from one body: `decode` (the EOTF, encoded to
/// linear) and `encode` (its inverse). The power is the `libm` crate's (the same bits on every
/// machine), not std's (the platform's libm).
macro_rules! transfer {
    ($t:ty, $decode:ident, $encode:ident) => {
        /// sRGB EOTF: encoded (non-linear) value to linear light (IEC 61966-2-1).
        #[must_use]
        pub fn $decode(v: $t) -> $t {
            if v <= DECODE_KNEE as $t {
                v / 12.92
            } else {
                libm::Libm::<$t>::pow((v + 0.055) / 1.055, 2.4)
            }
        }

        /// sRGB inverse EOTF: linear light to the encoded (non-linear) value.
        #[must_use]
        pub fn $encode(v: $t) -> $t {
            if v <= ENCODE_KNEE as $t {
                v * 12.92
            } else {
                1.055 * libm::Libm::<$t>::pow(v, 1.0 / 2.4) - 0.055
            }
        }
    };
}

transfer!(f64, srgb_decode, srgb_encode);
transfer!(f32, srgb_to_linear, linear_to_srgb);

/// [`srgb_decode`] per component.
#[must_use]
pub fn srgb_decode3(rgb: [f64; 3]) -> [f64; 3] {
    rgb.map(srgb_decode)
}

/// [`srgb_encode`] per component.
#[must_use]
pub fn srgb_encode3(rgb: [f64; 3]) -> [f64; 3] {
    rgb.map(srgb_encode)
}

/// Linear light to an 8-bit sRGB code: clamped to [0, 1] (NaN is 0), encoded exactly and
/// rounded to the nearest code. The one byte encoder of every image realist writes but the
/// frame's own ([`Srgb8Table`], within one code of this and exact at the codes' centres).
#[must_use]
pub fn srgb8(v: f32) -> u8 {
    let v = if v > 0.0 { v.min(1.0) } else { 0.0 };
    (linear_to_srgb(v) * 255.0 + 0.5) as u8
}

/// [`srgb8`] from f64 (the reference renders' images): the same code for the same value
/// to within the f32 rounding of the input.
#[must_use]
pub fn srgb8_f64(v: f64) -> u8 {
    let v = if v > 0.0 { v.min(1.0) } else { 0.0 };
    (srgb_encode(v) * 255.0 + 0.5) as u8
}

/// An 8-bit sRGB code to linear light, exactly (rounded once, from f64).
#[must_use]
pub fn srgb8_decode(code: u8) -> f32 {
    srgb8_decode_table()[usize::from(code)]
}

/// [`srgb8_decode`] of the 256 codes, for decoders that index it themselves.
#[must_use]
pub fn srgb8_decode_table() -> &'static [f32; 256] {
    static TABLE: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| srgb_decode(i as f64 / 255.0) as f32))
}

/// A linear value to a plain 8-bit code, no transfer (`v * 255` rounded, clamped; NaN is 0):
/// for data that is not colour (alpha, normals, linear textures).
#[must_use]
pub fn unorm8(v: f32) -> u8 {
    let v = if v > 0.0 { v.min(1.0) } else { 0.0 };
    (v * 255.0 + 0.5) as u8
}

/// Table steps of [`Srgb8Table`] over [0, 1].
pub const ENCODE_STEPS: usize = 16384;

/// Linear -> sRGB byte through a 16384-entry table indexed by the rounded linear value: the
/// frame's encoder, within one code value of [`srgb8`] everywhere (the table step is
/// 1/16384, and sRGB's steepest slope, 12.92 * 255 codes per unit at 0, moves 0.2 codes
/// per step).
pub struct Srgb8Table(Box<[u8; ENCODE_STEPS + 1]>);

impl Srgb8Table {
    /// The table, built once per process. The entries rise with the index, so it is built
    /// from where each of the 255 steps lies (a binary search each: about 3,600 evaluations
    /// of the transfer instead of 16,385; a test checks it entry by entry).
    #[must_use]
    pub fn get() -> &'static Srgb8Table {
        static TABLE: std::sync::OnceLock<Srgb8Table> = std::sync::OnceLock::new();
        TABLE.get_or_init(|| {
            let mut table = Box::new([0u8; ENCODE_STEPS + 1]);
            let mut from = 0usize;
            while from <= ENCODE_STEPS {
                let code = Self::entry(from);
                // The first index past `from` whose entry is above `code`.
                let (mut lo, mut hi) = (from + 1, ENCODE_STEPS + 1);
                while lo < hi {
                    let mid = lo + (hi - lo) / 2;
                    if Self::entry(mid) > code {
                        hi = mid;
                    } else {
                        lo = mid + 1;
                    }
                }
                table[from..lo].fill(code);
                from = lo;
            }
            Srgb8Table(table)
        })
    }

    /// The entry of linear value `i / ENCODE_STEPS`.
    fn entry(i: usize) -> u8 {
        srgb8(i as f32 / ENCODE_STEPS as f32)
    }

    /// The entries, for encoders that compute [`Srgb8Table::index`] a plane at a time.
    #[must_use]
    pub fn entries(&self) -> &[u8; ENCODE_STEPS + 1] {
        &self.0
    }

    /// The table index of linear value `v`: rounded, clamped to the table, 0 for NaN
    /// (written without branches, so a loop of them vectorises).
    #[inline(always)]
    #[must_use]
    pub fn index(v: f32) -> u32 {
        // `f32::max` returns the other operand for NaN; after the clamp the cast is exact
        // truncation, as `as usize` is for these values.
        (v * ENCODE_STEPS as f32 + 0.5)
            .max(0.0)
            .min(ENCODE_STEPS as f32) as u32
    }

    /// `v` encoded.
    #[inline(always)]
    #[must_use]
    pub fn encode(&self, v: f32) -> u8 {
        // `as usize` saturates and maps NaN to 0; the clamp bounds the index.
        self.0[((v * ENCODE_STEPS as f32 + 0.5) as usize).min(ENCODE_STEPS)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_is_continuous_at_the_knee() {
        for i in -100..=1100 {
            let v = f64::from(i) / 1000.0;
            assert!((srgb_encode(srgb_decode(v)) - v).abs() < 1e-12, "{v}");
        }
        // The two published constants meet within 1e-7 (IEC 61966-2-1 amendment note).
        let below = DECODE_KNEE / 12.92;
        let above = libm::pow((DECODE_KNEE + 0.055) / 1.055f64, 2.4);
        assert!((below - above).abs() < 1e-7, "{below} {above}");
        assert_eq!(srgb_decode(1.0), 1.0);
        assert_eq!(srgb_encode(0.0), 0.0);
        // The f32 pair is the same formula: it agrees with the f64 pair to f32 precision.
        for i in 0..=1000 {
            let v = i as f32 / 1000.0;
            assert!((f64::from(linear_to_srgb(v)) - srgb_encode(f64::from(v))).abs() < 1e-6);
            assert!((f64::from(srgb_to_linear(v)) - srgb_decode(f64::from(v))).abs() < 1e-6);
        }
    }

    #[test]
    fn the_byte_encoders_round_trip_every_code_and_clamp() {
        for code in 0..=255u8 {
            let lin = srgb8_decode(code);
            assert_eq!(srgb8(lin), code, "{code}");
            assert_eq!(srgb8_f64(f64::from(lin)), code, "{code}");
            assert_eq!(Srgb8Table::get().encode(lin), code, "{code}");
        }
        for v in [f32::NAN, -1.0, f32::NEG_INFINITY] {
            assert_eq!(
                (srgb8(v), unorm8(v), Srgb8Table::get().encode(v)),
                (0, 0, 0)
            );
        }
        for v in [2.0, f32::INFINITY] {
            assert_eq!(
                (srgb8(v), unorm8(v), Srgb8Table::get().encode(v)),
                (255, 255, 255)
            );
        }
        assert_eq!(unorm8(0.5), 128);
    }

    #[test]
    fn the_table_matches_its_entries_and_the_exact_encoder_within_one_code() {
        let t = Srgb8Table::get();
        for (i, &e) in t.entries().iter().enumerate() {
            assert_eq!(e, Srgb8Table::entry(i), "entry {i}");
        }
        let special = [
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            0.0,
        ];
        let steps = (0..=70_000).map(|i| i as f32 / 65_536.0 - 0.01);
        let bits = (0..1u32 << 16).map(|i| f32::from_bits(i.wrapping_mul(0x9E37_79B9)));
        for v in special.into_iter().chain(steps).chain(bits) {
            let direct = ((v * ENCODE_STEPS as f32 + 0.5) as usize).min(ENCODE_STEPS);
            assert_eq!(Srgb8Table::index(v) as usize, direct, "{v}");
            let (a, b) = (i32::from(t.encode(v)), i32::from(srgb8(v)));
            assert!((a - b).abs() <= 1, "{v}: {a} {b}");
        }
    }
}
