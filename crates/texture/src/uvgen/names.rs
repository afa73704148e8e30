//! The names of UV generators on the command line: `planar:x|y|z`, `cylindrical[:x|y|z]`,
//! `spherical[:x|y|z]`, `box` ([`Display`](fmt::Display) writes them, [`FromStr`] reads them
//! back).

use std::fmt;
use std::str::FromStr;

use super::{Axis, UvGenerator};

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        })
    }
}

/// `planar:x|y|z`, `cylindrical`, `spherical` (axis y) or `cylindrical:x` etc., `box`.
impl fmt::Display for UvGenerator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UvGenerator::Planar { axis } => write!(f, "planar:{axis}"),
            UvGenerator::Cylindrical { axis: Axis::Y } => f.write_str("cylindrical"),
            UvGenerator::Cylindrical { axis } => write!(f, "cylindrical:{axis}"),
            UvGenerator::Spherical { axis: Axis::Y } => f.write_str("spherical"),
            UvGenerator::Spherical { axis } => write!(f, "spherical:{axis}"),
            UvGenerator::Box => f.write_str("box"),
        }
    }
}

/// Why a name is not a UV generator.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown UV generator '{0}': expected planar:x|y|z, cylindrical[:x|y|z], \
     spherical[:x|y|z] or box"
)]
pub struct ParseUvGeneratorError(pub String);

impl FromStr for UvGenerator {
    type Err = ParseUvGeneratorError;

    /// The names [`Display`](fmt::Display) writes, case-insensitive; `planar` alone is
    /// `planar:z`, `cylindrical` and `spherical` alone are about y.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let lower = s.trim().to_ascii_lowercase();
        let (name, axis) = match lower.split_once(':') {
            Some((n, a)) => (n, Some(a)),
            None => (lower.as_str(), None),
        };
        let err = || ParseUvGeneratorError(s.to_owned());
        let axis = |default: Axis| match axis {
            None => Ok(default),
            Some("x") => Ok(Axis::X),
            Some("y") => Ok(Axis::Y),
            Some("z") => Ok(Axis::Z),
            Some(_) => Err(err()),
        };
        match name {
            "planar" => Ok(UvGenerator::Planar {
                axis: axis(Axis::Z)?,
            }),
            "cylindrical" => Ok(UvGenerator::Cylindrical {
                axis: axis(Axis::Y)?,
            }),
            "spherical" => Ok(UvGenerator::Spherical {
                axis: axis(Axis::Y)?,
            }),
            "box" if lower.contains(':') => Err(err()),
            "box" => Ok(UvGenerator::Box),
            _ => Err(err()),
        }
    }
}
