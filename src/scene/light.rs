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
    /// The default rig for any model, attached to the camera so a model stays readable from
    /// every side: a dim ambient, a white key light from above and to the right of the
    /// viewer, and a weak fill from the left. `camera_to_world` rotates camera-space
    /// directions (x right, y up, z towards the viewer) into the world.
    #[must_use]
    pub fn default_rig(camera_to_world: glam::Mat3) -> Vec<Light> {
        let towards =
            |x: f32, y: f32, z: f32| -(camera_to_world * Vec3::new(x, y, z)).normalize_or(Vec3::Y);
        vec![
            Light::Ambient {
                color: Vec3::splat(0.1),
            },
            Light::Directional {
                direction: towards(0.45, 0.8, 0.55),
                color: Vec3::splat(0.9),
            },
            Light::Directional {
                direction: towards(-0.7, -0.1, 0.4),
                color: Vec3::splat(0.25),
            },
        ]
    }
}
