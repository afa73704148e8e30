//! The one description of every numeric setting: its name, what it measures, its range and
//! where it lives in [`Settings`]. The command line (`--exposure 100`), the scene files
//! (`exposure = 100`, `[shadow] size = 4`) and the viewer's change detection all read this
//! table, so a bad value gives the same message whichever way it came in, and a new
//! numeric setting is added here once. The defaults are [`Settings::default`]'s.

use crate::raster::{MAX_STROKE_PX, SAMPLE_COUNTS, SUBPIXEL_BITS};
use crate::scene::{Slot, SlotOverride};
use crate::shade::MAX_SHADOW_SIZE;

use super::{Environment, Settings};

/// The values a setting accepts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// Any finite number from the first to the second, both included.
    Between(f64, f64),
    /// A whole number from the first to the second, both included.
    Whole(u32, u32),
    /// One of these whole numbers.
    OneOf(&'static [u32]),
}

/// One numeric setting.
#[derive(Clone, Copy, Debug)]
pub struct Numeric {
    /// The name: the scene file's key (a dotted key is a table's: `shadow.size` is
    /// `[shadow] size`) and, with `.` and `_` as `-`, the command line's flag unless
    /// [`Numeric::flag`] says otherwise.
    pub key: &'static str,
    /// What the number measures, as the message says it ("a number of stops").
    pub what: &'static str,
    pub range: Range,
    /// How the command line writes it, the value as `{}`, when not as `--KEY VALUE`
    /// (`--fog {},1000` for the fog's near distance); `None` when the flag is `--KEY`,
    /// `Some("")` when the command line has no flag for it.
    pub flag: Option<&'static str>,
    /// The value in `s`, `None` where `s` does not have the part it belongs to (no fog, no
    /// environment, no bump override).
    pub get: fn(&Settings) -> Option<f64>,
    /// Writes `v` where `get` finds the value (nothing where it does not).
    pub set: fn(&mut Settings, f64),
}

impl Numeric {
    /// `v` if it is in range, else the message naming the setting and its range.
    ///
    /// # Errors
    /// `v` is not finite, outside the range, not whole where it must be, or not one of
    /// the accepted values.
    pub fn check(&self, v: f64) -> Result<f64, String> {
        let ok = v.is_finite()
            && match self.range {
                Range::Between(lo, hi) => (lo..=hi).contains(&v),
                Range::Whole(lo, hi) => {
                    v.fract() == 0.0 && (f64::from(lo)..=f64::from(hi)).contains(&v)
                }
                Range::OneOf(set) => set.iter().any(|&n| f64::from(n) == v),
            };
        if ok {
            Ok(v)
        } else {
            Err(self.message(&v.to_string()))
        }
    }

    /// The smallest and the largest value accepted (what a widget's range is).
    #[must_use]
    pub fn bounds(&self) -> (f64, f64) {
        match self.range {
            Range::Between(lo, hi) => (lo, hi),
            Range::Whole(lo, hi) => (f64::from(lo), f64::from(hi)),
            Range::OneOf(set) => (
                set.iter().copied().min().map_or(0.0, f64::from),
                set.iter().copied().max().map_or(0.0, f64::from),
            ),
        }
    }

    /// Parses `text` (a command-line value) and checks it: the message for a value that is
    /// not a number is the one for a number out of range.
    ///
    /// # Errors
    /// As [`Numeric::check`], or `text` is not a number.
    pub fn parse(&self, text: &str) -> Result<f64, String> {
        match text.trim().parse::<f64>() {
            Ok(v) => self.check(v),
            Err(_) => Err(self.message(text)),
        }
    }

    /// `"exposure = 100: expected a number of stops from -64 to 64"`.
    #[must_use]
    pub fn message(&self, written: &str) -> String {
        let range = match self.range {
            Range::Between(lo, hi) => format!(" from {lo} to {hi}"),
            Range::Whole(lo, hi) => format!(", a whole number from {lo} to {hi}"),
            Range::OneOf(set) => {
                let names: Vec<String> = set.iter().map(u32::to_string).collect();
                format!(", one of {}", names.join(", "))
            }
        };
        format!("{} = {written}: expected {}{range}", self.key, self.what)
    }

    /// The command-line flag (`--shadow-size`), or `None` when there is none.
    #[must_use]
    pub fn flag_name(&self) -> Option<String> {
        match self.flag {
            Some("") => None,
            Some(form) => form.split_whitespace().next().map(str::to_owned),
            None => Some(format!("--{}", self.key.replace(['.', '_'], "-"))),
        }
    }

    /// The command-line arguments that set it to `written`, or `None` when there is no flag.
    #[must_use]
    pub fn flag_args(&self, written: &str) -> Option<Vec<String>> {
        match self.flag {
            Some("") => None,
            Some(form) => Some(
                form.replace("{}", written)
                    .split_whitespace()
                    .map(str::to_owned)
                    .collect(),
            ),
            None => Some(vec![self.flag_name()?, written.to_owned()]),
        }
    }

    /// A clap value parser for the flag, as an `f32`.
    pub fn parser_f32(&'static self) -> impl Fn(&str) -> Result<f32, String> + Clone + Send + Sync {
        move |s| self.parse(s).map(|v| v as f32)
    }

    /// A clap value parser for the flag, as a `u32` (for [`Range::Whole`] and
    /// [`Range::OneOf`]).
    pub fn parser_u32(&'static self) -> impl Fn(&str) -> Result<u32, String> + Clone + Send + Sync {
        move |s| self.parse(s).map(|v| v as u32)
    }
}

/// The setting called `key`.
///
/// # Panics
/// No setting has that name (a programming error: the names are fixed).
#[must_use]
pub fn numeric(key: &str) -> &'static Numeric {
    NUMERIC
        .iter()
        .find(|n| n.key == key)
        .unwrap_or_else(|| panic!("no numeric setting {key}"))
}

fn env_view(s: &Settings) -> Option<crate::texture::env::EnvView> {
    match &s.environment {
        Environment::On(v) => Some(v.clone()),
        Environment::Auto | Environment::Off => None,
    }
}

fn bump_scale(s: &Settings) -> Option<f64> {
    match s.slots.get(Slot::Bump) {
        Some(SlotOverride::Source { scale, .. }) => Some(f64::from(*scale)),
        Some(SlotOverride::Off) | None => None,
    }
}

/// A setting held in one field of [`Settings`].
macro_rules! scalar {
    ($key:literal, $what:literal, $range:expr, $flag:expr, $($field:ident).+ : $t:ty) => {
        Numeric {
            key: $key,
            what: $what,
            range: $range,
            flag: $flag,
            get: |s| Some(f64::from(s.$($field).+)),
            set: |s, v| s.$($field).+ = v as $t,
        }
    };
}

/// Every numeric setting.
pub static NUMERIC: &[Numeric] = &[
    scalar!("exposure", "a number of stops", Range::Between(-64.0, 64.0), None, exposure: f32),
    Numeric {
        key: "env_rotate",
        what: "degrees",
        range: Range::Between(-36_000.0, 36_000.0),
        flag: None,
        get: |s| env_view(s).map(|v| f64::from(v.rotation_deg)),
        set: |s, x| {
            if let Environment::On(v) = &mut s.environment {
                v.rotation_deg = x as f32;
            }
        },
    },
    Numeric {
        key: "env_intensity",
        what: "a scale",
        range: Range::Between(0.0, 1e6),
        flag: None,
        get: |s| env_view(s).map(|v| f64::from(v.intensity)),
        set: |s, x| {
            if let Environment::On(v) = &mut s.environment {
                v.intensity = x as f32;
            }
        },
    },
    Numeric {
        key: "env_background",
        what: "a blur",
        range: Range::Between(0.0, 1.0),
        flag: None,
        get: |s| s.env_background.map(f64::from),
        set: |s, v| {
            if let Some(b) = &mut s.env_background {
                *b = v as f32;
            }
        },
    },
    scalar!("samples", "samples per pixel side", Range::Whole(1, 8), None, samples: u32),
    scalar!("ray_depth", "a number of bounces", Range::Whole(0, super::MAX_RAY_DEPTH), None, ray_depth: u32),
    scalar!("msaa", "samples per pixel", Range::OneOf(&SAMPLE_COUNTS), None, msaa: u32),
    scalar!("subpixel_bits", "bits of the vertex snap", Range::Whole(0, SUBPIXEL_BITS), None, subpixel_bits: u8),
    scalar!("point_size", "pixels", Range::Between(1.0, MAX_STROKE_PX as f64), None, point_size: f32),
    scalar!("line_width", "pixels", Range::Between(1.0, MAX_STROKE_PX as f64), None, line_width: f32),
    Numeric {
        key: "bump_scale",
        what: "a height scale",
        range: Range::Between(-1e4, 1e4),
        flag: Some("--bump noise:4 --bump-scale {}"),
        get: bump_scale,
        set: |s, v| {
            if let Some(SlotOverride::Source { scale, .. }) = s.slots.get_mut(Slot::Bump) {
                *scale = v as f32;
            }
        },
    },
    scalar!("shadow.size", "texels per side", Range::Whole(16, MAX_SHADOW_SIZE), None, shadow.size: u32),
    scalar!("shadow.pcf", "a filter radius in texels", Range::Whole(0, 16), Some("--pcf {}"), shadow.pcf: u32),
    scalar!("shadow.bias", "a depth bias in texels", Range::Between(0.0, 1e4), Some(""), shadow.bias: f32),
    scalar!("shadow.slope", "a slope bias in texels", Range::Between(0.0, 1e4), Some(""), shadow.slope: f32),
    Numeric {
        key: "ground.extent",
        what: "multiples of the scene's radius",
        range: Range::Between(1e-3, 1e3),
        flag: Some(""),
        get: |s| s.ground.map(|g| f64::from(g.extent)),
        set: |s, v| {
            if let Some(g) = &mut s.ground {
                g.extent = v as f32;
            }
        },
    },
    Numeric {
        key: "fog.near",
        what: "a distance in scene units",
        range: Range::Between(0.0, 1e7),
        flag: Some("--fog {},1e7"),
        get: |s| s.fog.map(|f| f64::from(f.near)),
        set: |s, v| {
            if let Some(f) = &mut s.fog {
                f.near = v as f32;
            }
        },
    },
    Numeric {
        key: "fog.far",
        what: "a distance in scene units",
        range: Range::Between(0.0, 1e7),
        flag: Some("--fog 0,{}"),
        get: |s| s.fog.map(|f| f64::from(f.far)),
        set: |s, v| {
            if let Some(f) = &mut s.fog {
                f.far = v as f32;
            }
        },
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_default_is_in_range_and_reads_back_through_set() {
        let mut s = Settings {
            fog: Some(crate::shade::Fog::default()),
            ground: Some(super::super::Ground::default()),
            env_background: Some(0.0),
            ..Settings::default()
        };
        for n in NUMERIC {
            if let Some(v) = (n.get)(&s) {
                assert_eq!(n.check(v), Ok(v), "{}: default {v}", n.key);
                let lo = match n.range {
                    Range::Between(lo, _) => lo,
                    Range::Whole(lo, _) => f64::from(lo),
                    Range::OneOf(set) => f64::from(set[set.len() - 1]),
                };
                (n.set)(&mut s, lo);
                // Stored as f32 (or a whole number): the f32 nearest the value.
                assert_eq!((n.get)(&s), Some(f64::from(lo as f32)), "{}", n.key);
            }
        }
        let mut keys: Vec<&str> = NUMERIC.iter().map(|n| n.key).collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), NUMERIC.len(), "names are unique");
    }

    #[test]
    fn the_message_names_the_setting_and_its_range() {
        let e = numeric("exposure");
        assert_eq!(
            e.check(100.0).unwrap_err(),
            "exposure = 100: expected a number of stops from -64 to 64"
        );
        assert_eq!(e.parse("100"), e.check(100.0));
        assert_eq!(
            e.parse("lots").unwrap_err(),
            "exposure = lots: expected a number of stops from -64 to 64"
        );
        assert!(e.check(f64::NAN).is_err());
        assert_eq!(e.check(-64.0), Ok(-64.0));
        let s = numeric("samples");
        assert!(s
            .check(2.5)
            .unwrap_err()
            .contains(", a whole number from 1 to 8"));
        assert_eq!(
            numeric("msaa").check(2.0).unwrap_err(),
            "msaa = 2: expected samples per pixel, one of 1, 4"
        );
        assert_eq!(
            numeric("shadow.size").flag_name().as_deref(),
            Some("--shadow-size")
        );
        assert_eq!(numeric("shadow.bias").flag_name(), None);
        assert_eq!(
            numeric("fog.near").flag_args("-1").unwrap(),
            ["--fog", "-1,1e7"]
        );
    }
}
