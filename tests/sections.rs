//! Section planes: a sphere cut by `x >= 0` is checked pixel by pixel against a ray-cast
//! classification (kept surface, cap, background) from three orthographic views, on every
//! kernel and on one and two threads; the command line's `--section` and a scene file's
//! `[section]` draw the same cut; bad planes are refused with the flag or key named.

mod common;

use std::path::{Path, PathBuf};

use glam::{Vec3, Vec4};
use realist::mesh::Mesh;
use realist::render::{Sections, Settings, Shot};
use realist::scene::{Camera, Material};

const BACKGROUND: Vec4 = Vec4::new(0.0, 0.0, 0.0, 1.0);
const CAP: Vec3 = Vec3::new(0.0, 1.0, 0.0);
/// Orthographic half-height of the views, in world units.
const HALF: f32 = 1.25;
const SIZE: u32 = 160;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Seen {
    Surface,
    Cap,
    Background,
}

/// What the ray from `origin` along `dir` sees of the unit sphere cut to `x >= 0` with its
/// cap: the first point of the solid `{|p| <= 1, x >= 0}` it meets, on the sphere or on
/// the plane.
fn classify(origin: Vec3, dir: Vec3) -> Seen {
    // |o + t d|^2 = 1.
    let b = origin.dot(dir);
    let c = origin.length_squared() - 1.0;
    let disc = b * b - c;
    if disc < 0.0 {
        return Seen::Background;
    }
    let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
    let entry = origin + dir * t0;
    if entry.x >= 0.0 {
        return Seen::Surface;
    }
    // The entry is cut away: the ray meets the cap if it crosses x = 0 inside the sphere.
    if dir.x > 0.0 {
        let tp = -origin.x / dir.x;
        if tp > t0 && tp < t1 {
            return Seen::Cap;
        }
    }
    Seen::Background
}

fn sphere_scene() -> realist::scene::Scene {
    common::scene_of(
        Mesh::sphere(1.0, 128, 64).expect("sphere"),
        Material {
            base_color: Vec4::new(0.8, 0.3, 0.2, 1.0),
            ..Material::default()
        },
    )
}

fn view_from(eye: Vec3) -> Camera {
    Camera {
        eye,
        target: Vec3::ZERO,
        up: Vec3::Y,
        ortho: Some(HALF),
        near: 0.1,
        far: 20.0,
        ..Camera::default()
    }
}

fn cut(cap: Option<Vec3>) -> Settings {
    Settings {
        background: BACKGROUND,
        sections: Sections {
            planes: vec![Vec4::new(1.0, 0.0, 0.0, 0.0)],
            cap,
        },
        ..Settings::default()
    }
}

/// The ray through the centre of pixel (`x`, `y`) shifted by (`dx`, `dy`) pixels, for the
/// orthographic camera `cam`.
fn ray(cam: &Camera, x: f32, y: f32) -> (Vec3, Vec3) {
    let f = (cam.target - cam.eye).normalize();
    let r = f.cross(cam.up).normalize();
    let u = r.cross(f);
    let px = 2.0 * HALF / SIZE as f32;
    let sx = (x + 0.5 - SIZE as f32 * 0.5) * px;
    let sy = (SIZE as f32 * 0.5 - y - 0.5) * px;
    (cam.eye + r * sx + u * sy, f)
}

#[test]
fn a_section_plane_removes_half_a_sphere_and_caps_the_cut() {
    let scene = sphere_scene();
    for (name, eye) in [
        ("from the cut side", Vec3::new(-4.0, 0.0, 0.0)),
        ("from the front", Vec3::new(0.0, 0.0, 4.0)),
        ("obliquely", Vec3::new(-3.0, 1.5, 2.5)),
    ] {
        let cam = view_from(eye);
        let shot = Shot {
            settings: cut(Some(CAP)),
            width: SIZE,
            height: SIZE,
            camera: Some(cam.clone()),
        };
        let (one, _) = common::render_with(&scene, &shot, 1);
        let (fb, _) = common::render_with(&scene, &shot, 2);
        assert!(one.color == fb.color, "{name}: one and two threads differ");
        let (mut checked, mut caps, mut surface) = (0, 0, 0);
        for y in 0..SIZE {
            for x in 0..SIZE {
                // Only where the classification is the same 1.5 pixels around (edges of
                // the silhouette and of the cut, and the sphere's facets, are left out).
                let at = |dx: f32, dy: f32| {
                    let (o, d) = ray(&cam, x as f32 + dx, y as f32 + dy);
                    classify(o, d)
                };
                let seen = at(0.0, 0.0);
                if [(-1.5, 0.0), (1.5, 0.0), (0.0, -1.5), (0.0, 1.5)]
                    .iter()
                    .any(|&(dx, dy)| at(dx, dy) != seen)
                {
                    continue;
                }
                checked += 1;
                let c = fb.color[(y * SIZE + x) as usize];
                match seen {
                    Seen::Cap => {
                        caps += 1;
                        assert_eq!(c, CAP.extend(1.0), "{name}: pixel ({x}, {y}) is in the cap");
                    }
                    Seen::Background => {
                        assert_eq!(c, BACKGROUND, "{name}: pixel ({x}, {y}) was cut away");
                    }
                    Seen::Surface => {
                        surface += 1;
                        assert!(
                            c != BACKGROUND && c.truncate() != CAP,
                            "{name}: pixel ({x}, {y}) is on the kept half, drawn {c}"
                        );
                    }
                }
            }
        }
        assert!(
            checked > (SIZE * SIZE * 8 / 10) as usize,
            "{name}: {checked} pixels checked"
        );
        match name {
            "from the cut side" => assert!(caps > 5000 && surface == 0, "{name}: {caps} {surface}"),
            "from the front" => assert!(caps == 0 && surface > 2000, "{name}: {caps} {surface}"),
            _ => assert!(caps > 1000 && surface > 1000, "{name}: {caps} {surface}"),
        }
    }
}

#[test]
fn without_caps_the_cut_is_open() {
    let scene = sphere_scene();
    let cam = view_from(Vec3::new(-4.0, 0.0, 0.0));
    let shot = Shot {
        settings: cut(None),
        width: SIZE,
        height: SIZE,
        camera: Some(cam),
    };
    let (fb, stats) = common::render_with(&scene, &shot, 2);
    // Looking into the open half shell: only its inside, whose back faces are culled.
    assert!(fb.color.iter().all(|&c| c == BACKGROUND));
    assert!(stats.culled_section > 1000, "{stats:?}");
}

fn realist() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
}

/// A folder of its own for one test's files.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("realist-sections-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A sphere seen from -x, orthographic, black background.
const SCENE: &str = r#"size = [96, 96]
background = [0, 0, 0]

[primitive]
shape = "sphere"
radius = 1.0

[camera]
eye = [-4, 0, 0]
target = [0, 0, 0]
ortho = 1.25
"#;

fn pixel(png: &Path, x: u32, y: u32) -> [u8; 3] {
    let img = image::open(png).unwrap().into_rgb8();
    img.get_pixel(x, y).0
}

#[test]
fn render_section_caps_the_cut_and_a_scene_file_says_the_same() {
    let dir = folder("cli");
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();
    let run = |args: &[&str]| {
        let r = realist()
            .current_dir(&dir)
            .arg("render")
            .arg("s.toml")
            .args(args)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    };
    run(&[
        "--section",
        "1,0,0,0",
        "--section-cap",
        "#00ff00",
        "-o",
        "cli.png",
    ]);
    assert_eq!(pixel(&dir.join("cli.png"), 48, 48), [0, 255, 0], "the cap");
    assert_eq!(
        pixel(&dir.join("cli.png"), 2, 2),
        [0, 0, 0],
        "the background"
    );
    // The default cap colour; the plane given unnormalised.
    run(&["--section", "2,0,0,0", "-o", "default.png"]);
    assert_eq!(pixel(&dir.join("default.png"), 48, 48), [0xdb, 0x60, 0x50]);
    // Keeping x <= 0 from the same side: the near half, lit, no cap.
    run(&["--section", "-1,0,0,0", "-o", "flip.png"]);
    let c = pixel(&dir.join("flip.png"), 48, 48);
    assert!(c != [0, 0, 0] && c != [0xdb, 0x60, 0x50], "{c:?}");
    // The same cut from the file.
    let file = format!("{SCENE}\n[section]\nplanes = [[1, 0, 0, 0]]\ncap_color = \"#00ff00\"\n");
    std::fs::write(dir.join("f.toml"), file).unwrap();
    let r = realist()
        .current_dir(&dir)
        .args(["render", "f.toml", "-o", "file.png"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let (a, b) = (
        image::open(dir.join("cli.png")).unwrap(),
        image::open(dir.join("file.png")).unwrap(),
    );
    assert!(
        a.into_rgb8() == b.into_rgb8(),
        "--section and [section] differ"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_section_planes_are_refused_with_the_flag_or_key_named() {
    let dir = folder("bad");
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();
    for (args, says) in [
        (
            &["--section", "0,0,0,1"][..],
            "the normal must be finite and not zero",
        ),
        (&["--section", "1,0,0"][..], "expected NX,NY,NZ,D"),
        (&["--section", "1,0,nan,0"][..], "the normal must be finite"),
        (
            &[
                "--section",
                "1,0,0,0",
                "--section",
                "0,1,0,0",
                "--section",
                "0,0,1,0",
                "--section",
                "1,1,0,0",
            ][..],
            "at most 3 section planes",
        ),
        (&["--section-cap", "2,0,0"][..], "--section-cap 2,0,0"),
    ] {
        let r = realist()
            .current_dir(&dir)
            .args(["render", "s.toml", "-o", "x.png"])
            .args(args)
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success() && e.contains(says), "{args:?}: {e}");
    }
    let file = format!("{SCENE}\n[section]\nplanes = [[0, 0, 0, 1]]\n");
    std::fs::write(dir.join("f.toml"), file).unwrap();
    let r = realist()
        .current_dir(&dir)
        .args(["render", "f.toml", "-o", "x.png"])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(
        !r.status.success() && e.contains("f.toml") && e.contains("section.planes[0]"),
        "{e}"
    );
    assert!(!dir.join("x.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
