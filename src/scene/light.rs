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
        Self::default_rig_array(camera_to_world).to_vec()
    }

    /// [`Light::default_rig`] without allocating.
    #[must_use]
    pub fn default_rig_array(camera_to_world: glam::Mat3) -> [Light; 3] {
        let towards =
            |x: f32, y: f32, z: f32| -(camera_to_world * Vec3::new(x, y, z)).normalize_or(Vec3::Y);
        [
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

    /// The light moved by `m` (a rigid transform): positions as points, directions as
    /// vectors; ambient light is unchanged.
    #[must_use]
    pub fn transformed(&self, m: glam::Mat4) -> Light {
        match *self {
            Light::Ambient { color } => Light::Ambient { color },
            Light::Directional { direction, color } => Light::Directional {
                direction: m.transform_vector3(direction),
                color,
            },
            Light::Point { position, color } => Light::Point {
                position: m.transform_point3(position),
                color,
            },
        }
    }

    /// A short name of the light's kind ("ambient", "directional", "point").
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Light::Ambient { .. } => "ambient",
            Light::Directional { .. } => "directional",
            Light::Point { .. } => "point",
        }
    }
}
