//! Linear fog (the textbook's pipeline chapter, §5.1): how its distance is measured and the blend towards its colour.

use super::*;

/// How fog measures distance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum FogDistance {
    /// From the eye (spherical fog; does not change as the camera turns).
    #[default]
    Euclidean,
    /// Camera-space depth (cheaper on old hardware, changes as the camera turns).
    Depth,
}

impl FogDistance {
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            FogDistance::Euclidean => "euclidean",
            FogDistance::Depth => "depth",
        }
    }
}

impl std::str::FromStr for FogDistance {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "euclidean" | "spherical" | "radial" => Ok(FogDistance::Euclidean),
            "depth" | "z" | "planar" => Ok(FogDistance::Depth),
            _ => Err(format!(
                "unknown fog distance '{s}' (expected euclidean or depth)"
            )),
        }
    }
}

/// Linear fog (003 §5.1): `f = clamp((d - near) / (far - near), 0, 1)`,
/// `C = C_lit + f (g_fog - C_lit)`; alpha is kept.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fog {
    /// Linear RGB.
    pub color: Vec3,
    /// d_min: no fog nearer.
    pub near: f32,
    /// d_max: only fog farther.
    pub far: f32,
    pub distance: FogDistance,
}

impl Default for Fog {
    fn default() -> Self {
        Self {
            color: Vec3::splat(0.6),
            near: 2.0,
            far: 12.0,
            distance: FogDistance::Euclidean,
        }
    }
}

impl Fog {
    /// Whether its numbers make sense (finite colour and distances, `0 <= near < far`).
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.color.is_finite()
            && self.near.is_finite()
            && self.far.is_finite()
            && self.near >= 0.0
            && self.near < self.far
    }

    /// The fog distance of `p` seen from `eye` looking along unit `forward`.
    #[inline(always)]
    #[must_use]
    pub fn distance<T: Num>(&self, p: T::V, eye: T::V, forward: T::V) -> T {
        match self.distance {
            FogDistance::Euclidean => T::length(p - eye),
            FogDistance::Depth => T::dot(p - eye, forward),
        }
    }

    /// The fog factor f at distance `d`.
    #[inline(always)]
    #[must_use]
    pub fn factor<T: Num>(&self, d: T) -> T {
        ((d - T::of(self.near)) / T::of(self.far - self.near)).clamp01()
    }

    /// `c` fogged as seen at `p`.
    #[inline(always)]
    #[must_use]
    pub fn apply<T: Num>(&self, c: T::V, p: T::V, eye: T::V, forward: T::V) -> T::V {
        let f = self.factor(self.distance::<T>(p, eye, forward));
        c + (T::vec(self.color) - c) * f
    }
}
