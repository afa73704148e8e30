//! Default parameters of every [`Procedural`] kind, and the names the command line uses:
//! `checker[:N]`, `grid[:N]`, `wood`, `marble`, `noise[:OCTAVES]`.

use std::str::FromStr;

use super::{Procedural, MAX_CHECKER_SQUARES, MAX_GRID_CELLS};
use crate::noise::MAX_OCTAVES;

/// The kinds a name can select, for help texts and menus.
pub const PROCEDURAL_NAMES: [&str; 5] = ["checker", "grid", "wood", "marble", "noise"];

/// Why a name is not a procedural texture.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ParseProceduralError {
    #[error(
        "unknown procedural texture '{0}': expected checker[:N], grid[:N], wood, marble \
         or noise[:OCTAVES]"
    )]
    Unknown(String),
    #[error("'{name}': the count '{count}' is not a whole number from 1 to {max}")]
    Count {
        name: String,
        count: String,
        max: u32,
    },
}

impl Procedural {
    /// A light/dark grey chequerboard of `n` x `n` squares per unit of UV.
    #[must_use]
    pub fn checker(n: u32) -> Self {
        Procedural::Checker {
            n,
            a: [0.9; 3],
            b: [0.15; 3],
        }
    }

    /// The UV test grid with `cells` x `cells` cells.
    #[must_use]
    pub fn grid(cells: u32) -> Self {
        Procedural::Grid { cells }
    }

    /// Pine-coloured wood, 8 rings per unit of radius, lightly wobbled.
    #[must_use]
    pub fn wood() -> Self {
        Procedural::Wood {
            rings: 8.0,
            wobble: 0.4,
            light: [0.86, 0.66, 0.42],
            dark: [0.52, 0.31, 0.15],
        }
    }

    /// White marble with blue-grey veins, 2 bands per unit.
    #[must_use]
    pub fn marble() -> Self {
        Procedural::Marble {
            frequency: 2.0,
            turbulence: 0.8,
            base: [0.93, 0.92, 0.89],
            vein: [0.32, 0.34, 0.42],
        }
    }

    /// Black-to-white fBm with `octaves` octaves at 4 per unit.
    #[must_use]
    pub fn noise(octaves: u32) -> Self {
        Procedural::Noise {
            frequency: 4.0,
            octaves,
            low: [0.0; 3],
            high: [1.0; 3],
        }
    }

    /// The kind's name (one of [`PROCEDURAL_NAMES`]).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Procedural::Checker { .. } => "checker",
            Procedural::Grid { .. } => "grid",
            Procedural::Wood { .. } => "wood",
            Procedural::Marble { .. } => "marble",
            Procedural::Noise { .. } => "noise",
        }
    }
}

impl FromStr for Procedural {
    type Err = ParseProceduralError;

    /// `checker[:N]` (default 8), `grid[:N]` (default 8), `wood`, `marble`,
    /// `noise[:OCTAVES]` (default 5), case-insensitive; other parameters take their defaults.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let lower = s.trim().to_ascii_lowercase();
        let (name, count) = match lower.split_once(':') {
            Some((n, c)) => (n, Some(c)),
            None => (lower.as_str(), None),
        };
        let parse = |default: u32, max: u32| -> Result<u32, ParseProceduralError> {
            let Some(c) = count else { return Ok(default) };
            match c.parse::<u32>() {
                Ok(v) if (1..=max).contains(&v) => Ok(v),
                _ => Err(ParseProceduralError::Count {
                    name: name.to_owned(),
                    count: c.to_owned(),
                    max,
                }),
            }
        };
        let unknown = || ParseProceduralError::Unknown(s.to_owned());
        match name {
            "checker" => Ok(Procedural::checker(parse(8, MAX_CHECKER_SQUARES)?)),
            "grid" => Ok(Procedural::grid(parse(8, MAX_GRID_CELLS)?)),
            "noise" => Ok(Procedural::noise(parse(5, MAX_OCTAVES)?)),
            "wood" | "marble" if count.is_some() => Err(unknown()),
            "wood" => Ok(Procedural::wood()),
            "marble" => Ok(Procedural::marble()),
            _ => Err(unknown()),
        }
    }
}
