use super::*;

fn args(turntable: Option<u32>, animated: Option<&str>, fps: Option<f32>) -> SequenceArgs {
    SequenceArgs {
        turntable,
        animated: animated.map(PathBuf::from),
        fps,
        ..SequenceArgs::default()
    }
}

#[test]
fn animation_times() {
    let mut scene = realist::scene::skinned_tube(4, 6, 3, 4).expect("tube");
    scene.animations[0].name = "bend".into();
    let a = |animation: Option<&str>, time: Option<f32>, frames: Option<&str>| SequenceArgs {
        animation: animation.map(String::from),
        time,
        frames: frames.map(String::from),
        ..SequenceArgs::default()
    };
    assert_eq!(play(&a(None, None, None), &scene).unwrap(), Play::Rest);
    assert_eq!(play(&a(None, Some(1.0), None), &scene).unwrap(), Play::All);
    assert_eq!(
        play(&a(Some("bend"), None, None), &scene).unwrap(),
        Play::One(0)
    );
    assert_eq!(
        play(&a(Some("0"), None, None), &scene).unwrap(),
        Play::One(0)
    );
    let e = play(&a(Some("walk"), None, None), &scene)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no such animation") && e.contains("0 'bend'"),
        "{e}"
    );
    let t = |f: &str| times(&a(None, None, Some(f)), &scene, Play::All);
    // The tube's animation lasts 4 s.
    assert_eq!(t("4").unwrap(), [0.0, 1.0, 2.0, 3.0].map(Some).to_vec());
    assert_eq!(t("0:1:0.5").unwrap(), [0.0, 0.5, 1.0].map(Some).to_vec());
    for bad in ["0:1:0", "2:1:1", "x", "0:1", "0"] {
        assert!(t(bad).is_err(), "{bad}");
    }
}

#[test]
fn frame_names_are_padded_to_the_last_number() {
    assert_eq!(frame_name("frame_{}.png", 0, 35), "frame_00.png");
    assert_eq!(frame_name("frame_{}.png", 35, 35), "frame_35.png");
    assert_eq!(frame_name("f{}.png", 7, 9), "f7.png");
    assert_eq!(frame_name("f{}.png", 7, 10), "f07.png");
    assert_eq!(frame_name("f{}.png", 42, 100), "f042.png");
    assert_eq!(frame_name("d{}/f{}.png", 3, 99), "d03/f03.png");
    assert_eq!(frame_name("one.png", 0, 0), "one.png");
}

#[test]
fn output_names() {
    let plan = |out: &str, a: &SequenceArgs, n| Outputs::plan(Some(out.into()), a, n, (64, 48));
    let tt = args(Some(36), None, None);
    assert_eq!(
        plan("frame_{}.png", &tt, 36).unwrap(),
        Outputs {
            images: Some(Names::Numbered("frame_{}.png".into())),
            animated: None
        }
    );
    // No `{}` in a .png name and more than one frame: an error naming the file.
    let e = plan("frame.png", &tt, 36).unwrap_err().to_string();
    assert!(e.contains("frame.png") && e.contains("{}"), "{e}");
    // One frame needs no number.
    assert_eq!(
        plan("one.png", &args(None, None, None), 1).unwrap().images,
        Some(Names::Single("one.png".into()))
    );
    // An .apng name: one animated image at the turntable's 12 fps.
    assert_eq!(
        plan("spin.APNG", &tt, 36).unwrap(),
        Outputs {
            images: None,
            animated: Some(Animated {
                path: "spin.APNG".into(),
                fps: 12.0
            })
        }
    );
    // Both, with --animated and --fps.
    let both = plan("f_{}.png", &args(Some(4), Some("a.apng"), Some(30.0)), 4).unwrap();
    assert!(both.images.is_some());
    assert_eq!(both.animated.unwrap().fps, 30.0);
    // Only --animated.
    let only = Outputs::plan(None, &args(Some(4), Some("a.png"), None), 4, (64, 48)).unwrap();
    assert!(only.images.is_none() && only.animated.is_some());
    for (out, a, why) in [
        ("x.apng", args(Some(4), Some("y.apng"), None), "two"),
        ("x_{}.png", args(Some(4), Some("y_{}.apng"), None), "{}"),
        ("x_{}.png", args(Some(4), Some("y.gif"), None), "y.gif"),
        ("x.apng", args(Some(4), None, Some(0.0)), "--fps"),
        ("x.apng", args(Some(4), None, Some(f32::NAN)), "--fps"),
    ] {
        let e = plan(out, &a, 4).unwrap_err().to_string();
        assert!(e.contains(why), "{out}: {e}");
    }
}

#[test]
fn animated_images_are_bounded() {
    let p = Path::new("big.apng");
    assert!(check_animated(p, MAX_ANIMATED_FRAMES, (1, 1)).is_ok());
    let e = check_animated(p, MAX_ANIMATED_FRAMES + 1, (1, 1)).unwrap_err();
    assert!(e.to_string().contains("big.apng"), "{e}");
    // 1920x1080 RGB is 6.2 MB: 345 frames fit in 2 GiB, 346 do not.
    assert!(check_animated(p, 345, (1920, 1080)).is_ok());
    let e = check_animated(p, 346, (1920, 1080))
        .unwrap_err()
        .to_string();
    assert!(e.contains("GiB") && e.contains("1920x1080"), "{e}");
}

#[test]
fn turntable_cameras_turn_evenly_at_one_distance() {
    let pivot = Vec3::new(0.5, -1.0, 2.0);
    let base = Camera::orbit(pivot, 35.0, 25.0, 4.0, 0.8);
    let cams = turntable(&base, pivot, 36, Up::Y);
    assert_eq!(cams.len(), 36);
    assert_eq!(cams[0].eye, base.eye);
    let (az0, el0, d0) = orbit_of(base.eye, pivot);
    assert!((az0 - 35.0).abs() < 1e-3 && (el0 - 25.0).abs() < 1e-3 && (d0 - 4.0).abs() < 1e-5);
    for (i, c) in cams.iter().enumerate() {
        let (az, el, d) = orbit_of(c.eye, pivot);
        assert!((d - d0).abs() < 1e-4, "frame {i}: distance {d}");
        assert!((el - el0).abs() < 1e-3, "frame {i}: elevation {el}");
        let want = 35.0 + 10.0 * i as f32;
        let off = (az - want + 180.0).rem_euclid(360.0) - 180.0;
        assert!(off.abs() < 1e-2, "frame {i}: azimuth {az}, want {want}");
        assert!((c.target - pivot).length() < 1e-5);
        assert_eq!((c.near, c.far, c.yfov), (base.near, base.far, base.yfov));
    }
}

#[test]
fn a_framed_turntable_fits_every_frame() {
    // A long box seen along its length: the default distance for that direction is too
    // close once it turns side on, so the turntable moves back to the farthest framing.
    let mut scene = Scene::default();
    let mesh = realist::mesh::Mesh::cube(1.0).unwrap();
    scene.meshes.push(mesh);
    scene.instances.push(realist::scene::Instance {
        mesh: 0,
        world: glam::Mat4::from_scale(Vec3::new(12.0, 1.0, 1.0)),
        name: "long".into(),
        style: realist::scene::Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    let (lo, hi) = scene.bounds().unwrap();
    let aspect = 4.0 / 3.0;
    let base = Camera::frame_box(lo, hi, aspect, 90.0, 0.0);
    let a = args(Some(4), None, None);
    let framed = frames(&a, base.clone(), &scene, aspect, true, Up::Y).unwrap();
    let fixed = frames(&a, base.clone(), &scene, aspect, false, Up::Y).unwrap();
    assert_eq!(framed.len(), 4);
    let center = (lo + hi) * 0.5;
    let dist = |c: &Camera| (c.eye - center).length();
    assert!((dist(&fixed[1].camera) - dist(&base)).abs() < 1e-4);
    let side = Camera::frame_box(lo, hi, aspect, 180.0, 0.0);
    assert!(dist(&side) > dist(&base) * 1.3);
    for f in &framed {
        assert!((dist(&f.camera) - dist(&side)).abs() < 1e-3 * dist(&side));
        assert!(f.time.is_none());
    }
    assert!(frames(
        &args(Some(0), None, None),
        base.clone(),
        &scene,
        aspect,
        true,
        Up::Y
    )
    .is_err());

    // A still model: --frames or --time alone would write the same frame over and over.
    for (frames_flag, time) in [(Some("3".to_owned()), None), (None, Some(1.0))] {
        let a = SequenceArgs {
            frames: frames_flag,
            time,
            ..SequenceArgs::default()
        };
        let e = frames(&a, base.clone(), &scene, aspect, true, Up::Y)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no animations") && e.contains("--turntable"),
            "{e}"
        );
    }
    // With a turntable the camera moves: fine.
    let a = SequenceArgs {
        frames: Some("4".into()),
        ..args(Some(4), None, None)
    };
    assert_eq!(
        frames(&a, base, &scene, aspect, true, Up::Y).unwrap().len(),
        4
    );
}
