//! Lights: the light table's units and targets, the `--light` syntax, and the automatic
//! rig made explicit by shadows and extra lights.

use glam::{Vec2, Vec3};

use super::*;
use crate::render::Lights;
use crate::scene::{Attenuation, Light, LightKind};

#[test]
fn lights_convert_from_degrees_and_targets() {
    let file = toml(
        "model = \"demo\"\n[[light]]\nkind = \"spot\"\nposition = [0, 4, 0]\ntarget = [0, 0, 0]\n\
         inner = 10\nouter = 20\nattenuation = { mode = \"range\", range = 9 }\n\
         [[light]]\nkind = \"rect\"\nrect = [30, 15]\nup = [0, 0, 1]\n",
    )
    .unwrap();
    let s = file.settings(&crate::scene::demo()).unwrap();
    let Lights::Custom {
        lights,
        follow_camera: false,
    } = &s.lights
    else {
        panic!("{:?}", s.lights)
    };
    assert_eq!(lights[0].direction, Vec3::new(0.0, -4.0, 0.0));
    assert!((lights[0].inner - 10f32.to_radians()).abs() < 1e-7);
    assert!((lights[0].outer - 20f32.to_radians()).abs() < 1e-7);
    assert_eq!(lights[0].attenuation, Attenuation::Range(9.0));
    assert_eq!(lights[1].kind, LightKind::Rect);
    assert!((lights[1].rect - Vec2::new(30f32.to_radians(), 15f32.to_radians())).length() < 1e-7);
    assert_eq!(lights[1].up, Vec3::Z);
}

#[test]
fn light_flag_syntax() {
    let l = parse_light("spot:pos=0,4,2:target=0,0,0:inner=20:outer=30:color=1,0.5,0.25:att=linear,1,10:shadow:name=key")
        .unwrap();
    assert_eq!(l.kind, LightKind::Spot);
    assert_eq!(
        (l.position, l.direction),
        (Vec3::new(0.0, 4.0, 2.0), Vec3::new(0.0, -4.0, -2.0))
    );
    assert_eq!(l.color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(
        l.attenuation,
        Attenuation::Linear {
            near: 1.0,
            far: 10.0
        }
    );
    assert!(l.shadow && l.name == "key");
    assert_eq!(
        parse_light("point:att=range,5").unwrap().attenuation,
        Attenuation::Range(5.0)
    );
    assert_eq!(
        parse_light("ambient:color=0.1,0.1,0.1").unwrap().kind,
        LightKind::Ambient
    );
    for (bad, want) in [
        ("lamp", "unknown light kind 'lamp'"),
        ("spot:pos=1,2", "pos: expected 3 numbers"),
        ("spot:outer=120", "--light.outer: 120"),
        ("point:att=linear,1", "att=linear,1"),
        ("point:glow=1", "unknown light key 'glow'"),
        ("rect:image=/no/such.png", "/no/such.png"),
    ] {
        let e = parse_light(bad).unwrap_err();
        assert!(e.contains(want), "{bad}: {e}");
    }
}

#[test]
fn shadow_and_extra_lights_make_the_automatic_rig_explicit() {
    let rig = shadow_every_light(&Lights::Auto, &[]);
    let Lights::Custom {
        lights,
        follow_camera: true,
    } = &rig
    else {
        panic!("{rig:?}")
    };
    assert_eq!(lights.len(), Light::default_rig(glam::Mat3::IDENTITY).len());
    assert!(lights.iter().all(|l| l.shadow == l.kind.can_shadow()));
    let own = [Light::point(Vec3::ONE, Vec3::ONE)];
    let spot = Light::spot(Vec3::Y, Vec3::NEG_Y, Vec3::ONE, 0.2, 0.3);
    let added = add_lights(&Lights::Auto, &own, std::slice::from_ref(&spot));
    assert_eq!(
        added,
        Lights::Custom {
            lights: vec![own[0].clone(), spot.clone()],
            follow_camera: false
        }
    );
    // No lights of its own: the added ones replace the default rig.
    let added = add_lights(&Lights::Auto, &[], std::slice::from_ref(&spot));
    assert_eq!(
        added,
        Lights::Custom {
            lights: vec![spot],
            follow_camera: false
        }
    );
}
