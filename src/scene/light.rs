//! Light sources of seeds 000-003. Colours are linear RGB with the intensity folded in.

use glam::Vec3;

/// A light source.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Global ambient light `g_amb`; never attenuates.
    Ambient { color: Vec3 },
    /// The sun: parallel rays travelling along `direction` (unit), no position, no attenuation.
    Directional { direction: Vec3, color: Vec3 },
    /// An omni light (the seed's floodlight) at `position`.
    Point { position: Vec3, color: Vec3 },
}

impl Light {
    /// The default rig for any model: a white key light from above-left-front of the default
    /// camera plus a dim ambient, so every model is readable.
    #[must_use]
    pub fn default_rig() -> Vec<Light> {
        vec![
            Light::Ambient {
                color: Vec3::splat(0.1),
            },
            Light::Directional {
                direction: -Vec3::new(0.5, 1.0, 0.8).normalize(),
                color: Vec3::splat(0.9),
            },
            Light::Directional {
                direction: -Vec3::new(-0.6, 0.2, -0.5).normalize(),
                color: Vec3::splat(0.25),
            },
        ]
    }
}
