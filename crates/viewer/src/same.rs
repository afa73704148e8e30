//! Whether two [`Settings`] ask for the same frame, NaN included.
//!
//! The viewer renders when the settings differ from the last job's. `Settings` compares
//! with `PartialEq`, and NaN equals nothing, not even itself: a light or material holding a
//! NaN (from a file, copied into an override when another light is edited) would make every
//! UI pass look like a change, and the viewer would render for ever. Here a NaN matches a
//! NaN in the same place; the settings themselves are left as they are (the renderer drops
//! such a light, and the editor shows the value without writing it back).

use glam::{Vec2, Vec3, Vec4};

use crate::render::{Lights, Settings, NUMERIC};
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
    if let Some(p) = &mut m.pbr {
        f(&mut p.ior);
        f(&mut p.specular);
        v3(&mut p.specular_color);
        f(&mut p.emissive_strength);
        f(&mut p.clearcoat);
        f(&mut p.clearcoat_roughness);
        v3(&mut p.sheen_color);
        f(&mut p.sheen_roughness);
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
    }
    if let Some(g) = &mut s.ground {
        v3(&mut g.color);
    }
    s.sections.planes.iter_mut().for_each(v4);
    if let Some(c) = &mut s.sections.cap {
        v3(c);
    }
    // Every numeric setting, from its one description (exposure, the environment's turn
    // and strength, the fog's distances, ...).
    for n in NUMERIC {
        if (n.get)(&s).is_some_and(f64::is_nan) {
            (n.set)(&mut s, f64::from(NAN_STANDS_FOR));
        }
    }
    s
}

/// Whether `a` and `b` are equal, a NaN matching a NaN in the same place.
#[must_use]
pub fn same(a: &Settings, b: &Settings) -> bool {
    a == b || canonical(a) == canonical(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::{Environment, Ground};
    use crate::scene::{PbrMaterial, Slot, SlotOverride, TextureSource};

    /// Settings in which every numeric setting is present (fog, ground, an environment, a
    /// bump override, a blurred background).
    fn full() -> Settings {
        let mut s = Settings {
            fog: Some(crate::shade::Fog::default()),
            ground: Some(Ground::default()),
            env_background: Some(0.5),
            environment: Environment::On(crate::texture::env::EnvView::new(
                Environment::builtin("uniform").unwrap(),
            )),
            ..Settings::default()
        };
        let noise =
            TextureSource::bump_from_spec("noise", |_, _| Err::<_, String>("no image".into()))
                .unwrap()
                .0;
        s.slots
            .set(Slot::Bump, Some(SlotOverride::source(noise, 0.1)));
        s
    }

    #[test]
    fn a_nan_in_any_numeric_setting_matches_itself_and_nothing_else() {
        for n in NUMERIC {
            let mut a = full();
            assert!(
                (n.get)(&a).is_some(),
                "{}: not present in the test settings",
                n.key
            );
            (n.set)(&mut a, f64::NAN);
            if !(n.get)(&a).is_some_and(f64::is_nan) {
                continue; // a whole number: cannot hold a NaN
            }
            assert!(same(&a, &a.clone()), "{}: NaN against itself", n.key);
            assert!(!same(&a, &full()), "{}: NaN against the default", n.key);
        }
    }

    #[test]
    fn a_nan_in_a_pbr_material_float_matches_itself() {
        let m = Material {
            pbr: Some(PbrMaterial::default()),
            ..Material::default()
        };
        let mut s = Settings::default();
        for k in 0..8 {
            let mut m = m.clone();
            let p = m.pbr.as_mut().unwrap();
            match k {
                0 => p.ior = f32::NAN,
                1 => p.specular = f32::NAN,
                2 => p.specular_color.y = f32::NAN,
                3 => p.clearcoat = f32::NAN,
                4 => p.clearcoat_roughness = f32::NAN,
                5 => p.sheen_color.z = f32::NAN,
                6 => p.sheen_roughness = f32::NAN,
                _ => p.emissive_strength = f32::NAN,
            }
            s.materials = Some(vec![m]);
            assert!(same(&s, &s.clone()), "field {k}");
        }
    }
}
