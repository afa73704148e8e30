//! Whether two [`Settings`] ask for the same frame, NaN included.
//!
//! The viewer renders when the settings differ from the last job's. `Settings` compares
//! with `PartialEq`, and NaN equals nothing, not even itself: a light or material holding a
//! NaN (from a file, copied into an override when another light is edited) would make every
//! UI pass look like a change, and the viewer would render for ever. Here a NaN matches a
//! NaN in the same place; the settings themselves are left as they are (the renderer drops
//! such a light, and the editor shows the value without writing it back).

use glam::{Vec2, Vec3, Vec4};

use crate::render::{Lights, Settings};
use crate::scene::{AlphaMode, Attenuation, Light, Material};

/// What NaN becomes for the comparison: a subnormal no widget produces.
const NAN_STANDS_FOR: f32 = f32::from_bits(0x8001_2345);

fn f(v: &mut f32) {
    if v.is_nan() {
        *v = NAN_STANDS_FOR;
    }
}

fn v2(v: &mut Vec2) {
    f(&mut v.x);
    f(&mut v.y);
}

fn v3(v: &mut Vec3) {
    f(&mut v.x);
    f(&mut v.y);
    f(&mut v.z);
}

fn v4(v: &mut Vec4) {
    f(&mut v.x);
    f(&mut v.y);
    f(&mut v.z);
    f(&mut v.w);
}

fn light(l: &mut Light) {
    v3(&mut l.color);
    f(&mut l.intensity);
    v3(&mut l.position);
    v3(&mut l.direction);
    f(&mut l.inner);
    f(&mut l.outer);
    v2(&mut l.rect);
    v3(&mut l.up);
    match &mut l.attenuation {
        Attenuation::Linear { near, far } => {
            f(near);
            f(far);
        }
        Attenuation::Range(r) => f(r),
        Attenuation::None | Attenuation::InverseSquare => {}
    }
}

fn material(m: &mut Material) {
    v4(&mut m.base_color);
    v3(&mut m.ambient);
    v3(&mut m.specular);
    f(&mut m.shininess);
    v3(&mut m.emissive);
    f(&mut m.metallic);
    f(&mut m.roughness);
    if let AlphaMode::Mask(c) = &mut m.alpha_mode {
        f(c);
    }
}

/// `s` with every NaN the viewer can hold replaced by [`NAN_STANDS_FOR`].
#[must_use]
pub fn canonical(s: &Settings) -> Settings {
    let mut s = s.clone();
    v4(&mut s.background);
    if let Lights::Custom { lights, .. } = &mut s.lights {
        lights.iter_mut().for_each(light);
    }
    if let Some(ms) = &mut s.materials {
        ms.iter_mut().for_each(material);
    }
    if let Some(fog) = &mut s.fog {
        v3(&mut fog.color);
        f(&mut fog.near);
        f(&mut fog.far);
    }
    if let Some(g) = &mut s.ground {
        v3(&mut g.color);
        f(&mut g.extent);
    }
    f(&mut s.shadow.bias);
    f(&mut s.shadow.slope);
    f(&mut s.point_size);
    f(&mut s.line_width);
    s
}

/// Whether `a` and `b` are equal, a NaN matching a NaN in the same place.
#[must_use]
pub fn same(a: &Settings, b: &Settings) -> bool {
    a == b || canonical(a) == canonical(b)
}
