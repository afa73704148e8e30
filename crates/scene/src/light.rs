//! Light sources of the textbook (§9.2 and its pipeline chapter's §4.3) (and glTF
//! `KHR_lights_punctual`): ambient, directional, point, round spot and the rectangular (pyramid)
//! spot that can project an image. One struct for every kind, so an editor can switch a light's
//! kind and keep its values; fields a kind does not use are ignored by it. Colours are linear RGB;
//! what arrives is `color * intensity` times the attenuation, cone and shadow factors.

use std::borrow::Cow;
use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::texture::Texture;

/// What kind of source a [`Light`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum LightKind {
    /// Global ambient light `g_amb`: reaches everything equally, never attenuates.
    Ambient,
    /// The sun: parallel rays travelling along `direction`, no position, no attenuation.
    #[default]
    Directional,
    /// An omni light (the textbook's floodlight) at `position`.
    Point,
    /// A round spotlight at `position` shining along `direction`: full strength inside the
    /// hotspot half-angle `inner`, nothing outside the falloff half-angle `outer`, a smooth
    /// transition between.
    Spot,
    /// The textbook's rectangular spotlight (its pipeline chapter, §4.3): a pyramid of light with
    /// half-angles `rect` (horizontal, vertical) around `direction`, oriented by `up`, optionally
    /// projecting `image` like a slide projector.
    Rect,
}

impl LightKind {
    /// Every kind, in the order an editor lists them.
    pub const ALL: [LightKind; 5] = [
        LightKind::Ambient,
        LightKind::Directional,
        LightKind::Point,
        LightKind::Spot,
        LightKind::Rect,
    ];

    /// The kind's name in scene files and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            LightKind::Ambient => "ambient",
            LightKind::Directional => "directional",
            LightKind::Point => "point",
            LightKind::Spot => "spot",
            LightKind::Rect => "rect",
        }
    }

    /// Whether the light has a position (and so can attenuate with distance).
    #[must_use]
    pub fn positional(self) -> bool {
        matches!(self, LightKind::Point | LightKind::Spot | LightKind::Rect)
    }

    /// Whether the light has a direction.
    #[must_use]
    pub fn directed(self) -> bool {
        matches!(
            self,
            LightKind::Directional | LightKind::Spot | LightKind::Rect
        )
    }

    /// Whether the light can cast shadow-mapped shadows (directional, spot, rectangular).
    #[must_use]
    pub fn can_shadow(self) -> bool {
        self.directed()
    }
}

impl std::str::FromStr for LightKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        LightKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!(
                    "unknown light kind '{s}' (expected ambient, directional, point, spot or rect)"
                )
            })
    }
}

/// How a positional light weakens with the distance `d` from it. Directional and ambient
/// lights never attenuate.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Attenuation {
    /// Full strength at any distance.
    #[default]
    None,
    /// The textbook's practical ramp (its pipeline chapter, §4.8): full strength within `near`
    /// (d_min), falling linearly to zero at `far` (d_max), nothing beyond.
    Linear { near: f32, far: f32 },
    /// Physical: `1 / d²` (intensity is then the light's strength at unit distance).
    InverseSquare,
    /// glTF `KHR_lights_punctual` `range`: `clamp(1 - (d / range)⁴, 0, 1) / d²`, which
    /// reaches zero at `range`.
    Range(f32),
}

impl Attenuation {
    /// The attenuation factor at distance `d` (f64, the reference form; the renderer's
    /// kernels are tested against it).
    #[must_use]
    pub fn factor(self, d: f64) -> f64 {
        match self {
            Attenuation::None => 1.0,
            Attenuation::Linear { near, far } => {
                let (near, far) = (f64::from(near), f64::from(far));
                if d <= near {
                    1.0
                } else if d >= far {
                    0.0
                } else {
                    (far - d) / (far - near)
                }
            }
            Attenuation::InverseSquare => 1.0 / (d * d).max(MIN_D2),
            Attenuation::Range(r) => {
                let q = d / f64::from(r);
                let window = (1.0 - q * q * q * q).clamp(0.0, 1.0);
                window / (d * d).max(MIN_D2)
            }
        }
    }

    /// The distance beyond which the factor is zero (infinite if it never is).
    #[must_use]
    pub fn reach(self) -> f32 {
        match self {
            Attenuation::Linear { far, .. } => far.max(0.0),
            Attenuation::Range(r) => r.max(0.0),
            Attenuation::None | Attenuation::InverseSquare => f32::INFINITY,
        }
    }

    /// The mode's name in scene files ("none", "linear", "inverse-square", "range").
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Attenuation::None => "none",
            Attenuation::Linear { .. } => "linear",
            Attenuation::InverseSquare => "inverse-square",
            Attenuation::Range(_) => "range",
        }
    }

    /// Whether its numbers make sense (finite, non-negative, `near <= far`, range > 0).
    #[must_use]
    pub fn is_valid(self) -> bool {
        match self {
            Attenuation::None | Attenuation::InverseSquare => true,
            Attenuation::Linear { near, far } => {
                near.is_finite() && far.is_finite() && near >= 0.0 && near <= far && far > 0.0
            }
            Attenuation::Range(r) => r.is_finite() && r > 0.0,
        }
    }
}

/// The smallest squared distance inverse-square attenuation divides by (a light inside a
/// surface would otherwise give infinity): 1 mm at 1 unit = 1 m.
pub const MIN_D2: f64 = 1e-6;

/// A light source. Build one with [`Light::ambient`], [`Light::directional`],
/// [`Light::point`], [`Light::spot`] or [`Light::rect`] and the `with_*` methods.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Shown in editors and reports (glTF light name, scene-file name); may be empty.
    pub name: Cow<'static, str>,
    pub kind: LightKind,
    /// Linear RGB colour; multiplied by `intensity`.
    pub color: Vec3,
    pub intensity: f32,
    /// Where a point, spot or rectangular light is.
    pub position: Vec3,
    /// The way the light travels (directional, spot, rectangular); need not be unit.
    pub direction: Vec3,
    /// Spot hotspot half-angle in radians (full strength inside).
    pub inner: f32,
    /// Spot falloff half-angle in radians (no light outside).
    pub outer: f32,
    /// Rectangular spot: horizontal and vertical half-angles in radians.
    pub rect: Vec2,
    /// Rectangular spot: the image's "up" direction (projected perpendicular to `direction`).
    pub up: Vec3,
    /// Rectangular spot: the projected image (linear RGB, multiplies the colour); its top
    /// edge is towards `up`.
    pub image: Option<Arc<Texture>>,
    pub attenuation: Attenuation,
    /// Casts shadow-mapped shadows (directional, spot and rectangular lights).
    pub shadow: bool,
}

impl Default for Light {
    fn default() -> Self {
        Self {
            name: Cow::Borrowed(""),
            kind: LightKind::Directional,
            color: Vec3::ONE,
            intensity: 1.0,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            inner: 20f32.to_radians(),
            outer: 30f32.to_radians(),
            rect: Vec2::splat(25f32.to_radians()),
            up: Vec3::Y,
            image: None,
            attenuation: Attenuation::None,
            shadow: false,
        }
    }
}

impl Light {
    /// Global ambient light of colour `color`.
    #[must_use]
    pub fn ambient(color: Vec3) -> Self {
        Self {
            kind: LightKind::Ambient,
            color,
            ..Self::default()
        }
    }

    /// Parallel light travelling along `direction`.
    #[must_use]
    pub fn directional(direction: Vec3, color: Vec3) -> Self {
        Self {
            kind: LightKind::Directional,
            direction,
            color,
            ..Self::default()
        }
    }

    /// An omni light at `position`.
    #[must_use]
    pub fn point(position: Vec3, color: Vec3) -> Self {
        Self {
            kind: LightKind::Point,
            position,
            color,
            ..Self::default()
        }
    }

    /// A round spotlight at `position` shining along `direction`, hotspot and falloff
    /// half-angles `inner` <= `outer` in radians.
    #[must_use]
    pub fn spot(position: Vec3, direction: Vec3, color: Vec3, inner: f32, outer: f32) -> Self {
        Self {
            kind: LightKind::Spot,
            position,
            direction,
            color,
            inner,
            outer,
            ..Self::default()
        }
    }

    /// A rectangular spotlight at `position` shining along `direction` with half-angles
    /// `half_angles` (horizontal, vertical) in radians, its vertical axis towards `up`.
    #[must_use]
    pub fn rect(position: Vec3, direction: Vec3, up: Vec3, half_angles: Vec2, color: Vec3) -> Self {
        Self {
            kind: LightKind::Rect,
            position,
            direction,
            up,
            rect: half_angles,
            color,
            ..Self::default()
        }
    }

    #[must_use]
    pub fn with_attenuation(mut self, a: Attenuation) -> Self {
        self.attenuation = a;
        self
    }

    #[must_use]
    pub fn with_shadow(mut self, on: bool) -> Self {
        self.shadow = on;
        self
    }

    #[must_use]
    pub fn with_intensity(mut self, i: f32) -> Self {
        self.intensity = i;
        self
    }

    #[must_use]
    pub fn with_name(mut self, name: impl Into<Cow<'static, str>>) -> Self {
        self.name = name.into();
        self
    }

    #[must_use]
    pub fn with_image(mut self, image: Arc<Texture>) -> Self {
        self.image = Some(image);
        self
    }

    /// `color * intensity`: what arrives before attenuation, cone and shadow.
    #[must_use]
    pub fn radiance(&self) -> Vec3 {
        self.color * self.intensity
    }

    /// The default rig for any model, attached to the camera so a model stays readable from
    /// every side: a studio three-point rig (a dim ambient, a white key light from above
    /// and to the right of the viewer that puts a highlight on the side facing the camera, a
    /// weak fill from the left and a rim light from behind). `camera_to_world` rotates
    /// camera-space directions (x right, y up, z towards the viewer) into the world.
    #[must_use]
    pub fn default_rig(camera_to_world: glam::Mat3) -> Vec<Light> {
        Self::default_rig_array(camera_to_world).to_vec()
    }

    /// [`Light::default_rig`] without a `Vec`.
    #[must_use]
    pub fn default_rig_array(camera_to_world: glam::Mat3) -> [Light; 4] {
        let towards =
            |x: f32, y: f32, z: f32| -(camera_to_world * Vec3::new(x, y, z)).normalize_or(Vec3::Y);
        [
            Light::ambient(Vec3::splat(0.08)).with_name("ambient"),
            Light::directional(towards(0.55, 0.25, 0.8), Vec3::new(0.9, 0.87, 0.82))
                .with_name("key"),
            Light::directional(towards(-0.8, 0.0, 0.45), Vec3::new(0.22, 0.24, 0.28))
                .with_name("fill"),
            Light::directional(towards(0.0, 0.6, -0.8), Vec3::splat(0.35)).with_name("rim"),
        ]
    }

    /// The light moved by `m` (a rigid transform): position as a point, direction and up as
    /// vectors; ambient light is unchanged.
    #[must_use]
    pub fn transformed(&self, m: glam::Mat4) -> Light {
        let mut l = self.clone();
        if self.kind != LightKind::Ambient {
            l.position = m.transform_point3(self.position);
            l.direction = m.transform_vector3(self.direction);
            l.up = m.transform_vector3(self.up);
        }
        l
    }

    /// A short name of the light's kind ("ambient", "directional", "point", "spot", "rect").
    #[must_use]
    pub fn kind(&self) -> &'static str {
        self.kind.name()
    }
}
