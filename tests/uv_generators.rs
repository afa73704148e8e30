//! Generated texture coordinates (the textbook's §9.5: texture space from an auxiliary
//! plane, cylinder or sphere, or a box) on the sphere, cylinder and torus primitives and on
//! a model file without UVs, through the library, the loader (`LoadOptions::uv`), the scene
//! file's `uv` key and `realist render --uv`.
//!
//! What is checked cannot hold by accident: the maps are compared with formulas written
//! here from the module's conventions (not with the generator's own code), the spherical
//! map on the sphere with the primitive's own analytic UVs, and the seam with rendered
//! frames, against a deliberately smeared map that the same check must reject.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};

use realist::load::{load, LoadOptions};
use realist::mesh::{generate_uvs, uv_frame, Channel, Mesh, MAX_WRAP_EXTENT};
use realist::raster::Framebuffer;
use realist::render::{render, Lights, PreparedScene, Settings, Shot};
use realist::scene::{Camera, Instance, Light, Material, Scene, Style};
use realist::shade::Shading;
use realist::texture::{Axis, Texture, UvGenerator};

/// Every generator the module offers (the presets and the other axes).
fn generators() -> Vec<UvGenerator> {
    let mut all = Vec::new();
    for axis in Axis::ALL {
        all.push(UvGenerator::Planar { axis });
        all.push(UvGenerator::Cylindrical { axis });
        all.push(UvGenerator::Spherical { axis });
    }
    all.push(UvGenerator::Box);
    all
}

fn sphere() -> Mesh {
    Mesh::sphere(1.0, 48, 24).unwrap()
}

fn cylinder() -> Mesh {
    Mesh::cylinder(0.5, 2.0, 32, true).unwrap()
}

fn torus() -> Mesh {
    Mesh::torus(1.0, 0.35, 32, 16).unwrap()
}

fn primitives() -> [(&'static str, Mesh); 3] {
    [
        ("sphere", sphere()),
        ("cylinder", cylinder()),
        ("torus", torus()),
    ]
}

/// Scratch folder for this test binary (under cargo's target folder).
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("uv_generators")
        .join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `mesh` as an OBJ file with positions and faces only (no `vt`, no `vn`).
fn write_obj(mesh: &Mesh, path: &Path) {
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for f in mesh.facets() {
        text += "f";
        for c in f.corners() {
            text += &format!(" {}", mesh.corners[c] + 1);
        }
        text += "\n";
    }
    std::fs::write(path, text).unwrap();
}

/// The longitude of `p` about +y as a fraction of a turn in [0, 1), from +z towards +x.
fn longitude(p: Vec3) -> f32 {
    (libm::atan2f(p.x, p.z) / std::f32::consts::TAU).rem_euclid(1.0)
}

/// Distance of two longitudes on the circle (fractions of a turn).
fn circle_distance(a: f32, b: f32) -> f32 {
    let d = (a - b).rem_euclid(1.0);
    d.min(1.0 - d)
}

const UV_EPS: f32 = 1e-5;

#[test]
fn every_generator_gives_finite_uvs_in_range_on_every_primitive() {
    for (name, mesh) in primitives() {
        for g in generators() {
            let uvs = generate_uvs(&mesh, &g);
            let frame = uv_frame(&mesh);
            let axis = match g {
                UvGenerator::Cylindrical { axis } | UvGenerator::Spherical { axis } => Some(axis),
                _ => None,
            };
            for f in mesh.facets() {
                let at: Vec<Vec2> = f.corners().map(|c| uvs.at(c, mesh.corners[c])).collect();
                for uv in &at {
                    assert!(uv.is_finite(), "{name} {g}: {uv}");
                    assert!(
                        (-UV_EPS..=1.0 + UV_EPS).contains(&uv.y),
                        "{name} {g}: v = {}",
                        uv.y
                    );
                }
                let (lo, hi) = at.iter().fold((f32::MAX, f32::MIN), |(lo, hi), uv| {
                    (lo.min(uv.x), hi.max(uv.x))
                });
                let Some(axis) = axis else {
                    assert!(
                        lo >= -UV_EPS && hi <= 1.0 + UV_EPS,
                        "{name} {g}: u {lo}..{hi}"
                    );
                    continue;
                };
                // A facet around the axis (a cap) is mapped planar along it; every other
                // facet is unwrapped: its u spans at most half a turn (no smear), and
                // starts in [0, 1).
                let n = frame.direction(f.normal);
                let cap = at.iter().zip(f.corners()).all(|(uv, c)| {
                    let p = mesh.positions[mesh.corners[c] as usize];
                    *uv == g.cap(&frame, p, f.normal)
                });
                if cap {
                    assert!(
                        n[axis.index()].abs() > 0.9,
                        "{name} {g}: a cap-mapped facet with normal {n}"
                    );
                    continue;
                }
                assert!(
                    hi - lo <= MAX_WRAP_EXTENT,
                    "{name} {g}: a facet spans u {lo}..{hi}"
                );
                assert!(
                    (-UV_EPS..1.0).contains(&lo) && hi < 1.0 + MAX_WRAP_EXTENT,
                    "{name} {g}: u {lo}..{hi}"
                );
            }
        }
    }
}

#[test]
fn spherical_on_the_sphere_is_longitude_and_latitude() {
    let mesh = sphere();
    let uvs = generate_uvs(&mesh, &UvGenerator::Spherical { axis: Axis::Y });
    let own = &mesh.uvs[0];
    let mut checked = 0;
    for (c, &v) in mesh.corners.iter().enumerate() {
        let p = mesh.positions[v as usize];
        let uv = uvs.at(c, v);
        // The primitive's analytic UVs are longitude / 2pi and polar angle / pi, with its
        // own seam (u = 1 on the last column) and pole corners at the facet's mid longitude.
        let want = own.at(c, v);
        assert!(
            (uv - want).abs().max_element() < UV_EPS,
            "corner {c} at {p}: generated {uv}, the sphere's own {want}"
        );
        // And directly: u is the longitude, v the latitude, away from the poles.
        let polar = libm::acosf(p.y.clamp(-1.0, 1.0)) / std::f32::consts::PI;
        assert!(
            (uv.y - polar).abs() < UV_EPS,
            "corner {c}: v {} vs {polar}",
            uv.y
        );
        if p.y.abs() < 0.999 {
            let d = circle_distance(uv.x, longitude(p));
            assert!(
                d < UV_EPS,
                "corner {c} at {p}: u {} vs {}",
                uv.x,
                longitude(p)
            );
            checked += 1;
        }
    }
    assert!(checked > 4000, "{checked} corners off the poles");
}

#[test]
fn cylindrical_takes_longitude_and_height() {
    let mesh = cylinder();
    let uvs = generate_uvs(&mesh, &UvGenerator::Cylindrical { axis: Axis::Y });
    let mut side = 0;
    for f in mesh.facets() {
        if f.normal.y.abs() > 0.5 {
            // A cap: planar along y, seen from the side it faces (the frame is
            // [-0.5, 0.5] x [-1, 1] x [-0.5, 0.5]).
            for c in f.corners() {
                let p = mesh.positions[mesh.corners[c] as usize];
                let uv = uvs.at(c, mesh.corners[c]);
                let want = if f.normal.y > 0.0 {
                    Vec2::new(p.x + 0.5, p.z + 0.5)
                } else {
                    Vec2::new(p.x + 0.5, 0.5 - p.z)
                };
                assert!(
                    (uv - want).abs().max_element() < UV_EPS,
                    "cap: {uv} vs {want}"
                );
            }
            continue;
        }
        side += 1;
        for c in f.corners() {
            let p = mesh.positions[mesh.corners[c] as usize];
            let uv = uvs.at(c, mesh.corners[c]);
            assert!(
                circle_distance(uv.x, longitude(p)) < UV_EPS,
                "{p}: u {}",
                uv.x
            );
            assert!((uv.y - (0.5 - 0.5 * p.y)).abs() < UV_EPS, "{p}: v {}", uv.y);
        }
    }
    assert_eq!(side, 32);
    // The torus' longitude too (its own u is the same angle).
    let t = torus();
    let uvs = generate_uvs(&t, &UvGenerator::Cylindrical { axis: Axis::Y });
    for (c, &v) in t.corners.iter().enumerate() {
        let d = circle_distance(uvs.at(c, v).x, t.uvs[0].at(c, v).x);
        assert!(d < UV_EPS, "torus corner {c}");
    }
}

/// The planar map of `p` on the face seen from `axis` (`positive` or not) of the box
/// `[lo, hi]`, written from the module's table: `+x` has u along -z, `+y` u along +x with -z
/// up, `+z` u along +x, y up elsewhere; the opposite faces mirror them; v runs downwards.
fn face_uv(p: Vec3, lo: Vec3, hi: Vec3, axis: usize, positive: bool) -> Vec2 {
    let t = (p - lo) / (hi - lo); // 0..1 along each axis
    match (axis, positive) {
        (0, true) => Vec2::new(1.0 - t.z, 1.0 - t.y),
        (0, false) => Vec2::new(t.z, 1.0 - t.y),
        (1, true) => Vec2::new(t.x, t.z),
        (1, false) => Vec2::new(t.x, 1.0 - t.z),
        (2, true) => Vec2::new(t.x, 1.0 - t.y),
        (2, false) => Vec2::new(1.0 - t.x, 1.0 - t.y),
        _ => unreachable!(),
    }
}

#[test]
fn planar_is_affine_in_position() {
    for (name, mesh) in primitives() {
        let (lo, hi) = mesh.bounds().unwrap();
        for axis in Axis::ALL {
            let uvs = generate_uvs(&mesh, &UvGenerator::Planar { axis });
            assert!(uvs.indices.is_none(), "{name}: a planar map needs no seam");
            for (v, p) in mesh.positions.iter().enumerate() {
                let want = face_uv(*p, lo, hi, axis.index(), true);
                let got = uvs.values[v];
                assert!(
                    (got - want).abs().max_element() < UV_EPS,
                    "{name} planar:{axis} at {p}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn box_picks_the_dominant_axis_face() {
    // On the cube, the box map is the cube's own face mapping.
    let cube = Mesh::cube(1.0).unwrap();
    let uvs = generate_uvs(&cube, &UvGenerator::Box);
    for (c, &v) in cube.corners.iter().enumerate() {
        let (got, want) = (uvs.at(c, v), cube.uvs[0].at(c, v));
        assert!((got - want).abs().max_element() < UV_EPS, "cube corner {c}");
    }
    // Elsewhere every facet takes the face its normal points to most.
    let mut faces = [0usize; 6];
    for (name, mesh) in primitives() {
        let (lo, hi) = mesh.bounds().unwrap();
        let uvs = generate_uvs(&mesh, &UvGenerator::Box);
        for f in mesh.facets() {
            let a = f.normal.abs();
            let axis = if a.x >= a.y && a.x >= a.z {
                0
            } else if a.y >= a.z {
                1
            } else {
                2
            };
            let positive = f.normal[axis] >= 0.0;
            faces[2 * axis + usize::from(positive)] += 1;
            for c in f.corners() {
                let p = mesh.positions[mesh.corners[c] as usize];
                let want = face_uv(p, lo, hi, axis, positive);
                let got = uvs.at(c, mesh.corners[c]);
                assert!(
                    (got - want).abs().max_element() < UV_EPS,
                    "{name}: facet normal {} at {p}: {got} vs {want}",
                    f.normal
                );
            }
        }
    }
    assert!(
        faces.iter().all(|&n| n > 10),
        "every face is used: {faces:?}"
    );
}

/// A white, matte material under an ambient light of 1: a pixel is its texel.
fn unlit_scene(mesh: Mesh, world: Mat4) -> Scene {
    let mut scene = Scene::default();
    scene.materials.push(Material {
        base_color: Vec4::ONE,
        specular: Vec3::ZERO,
        ambient: Vec3::ONE,
        ..Material::default()
    });
    let mut mesh = mesh;
    mesh.material = Some(0);
    scene.meshes.push(mesh);
    scene.instances.push(Instance {
        mesh: 0,
        world,
        name: "test".into(),
        style: Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    scene
}

/// 8 x 8 squares per unit of UV: one square is 45 degrees of longitude.
fn chequer() -> Arc<Texture> {
    Arc::new(Texture::checker(
        256,
        8,
        [235, 235, 235, 255],
        [30, 60, 160, 255],
    ))
}

const SIZE: u32 = 240;

/// The sphere seen from +z (its seam, longitude 0, faces the camera), orthographic.
fn frame(scene: Scene) -> Framebuffer {
    let opts = Shot {
        width: SIZE,
        height: SIZE,
        camera: Some(Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            ortho: Some(1.1),
            near: 0.1,
            far: 20.0,
            ..Camera::default()
        }),
        settings: Settings {
            slots: {
                let mut slots = realist::scene::SlotOverrides::default();
                slots.set(
                    realist::scene::Slot::BaseColor,
                    Some(realist::scene::SlotOverride::source(
                        realist::scene::TextureSource::Image(chequer()),
                        1.0,
                    )),
                );
                slots
            },
            shading: Some(Shading::Textured),
            lights: Lights::Custom {
                lights: vec![Light::ambient(Vec3::ONE)],
                follow_camera: false,
            },
            ..Settings::default()
        },
    };
    render(&PreparedScene::new(scene), &opts).image()
}

/// Mean absolute difference in 8-bit sRGB levels of the columns `x0..x1` of two frames.
fn column_levels(a: &Framebuffer, b: &Framebuffer, x: u32) -> f64 {
    let (a8, b8) = (a.to_srgb8(), b.to_srgb8());
    let w = a.width as usize;
    let mut sum = 0u64;
    for y in 0..a.height as usize {
        for k in 0..3 {
            let i = (y * w + x as usize) * 3 + k;
            sum += u64::from(a8[i].abs_diff(b8[i]));
        }
    }
    sum as f64 / (3 * a.height) as f64
}

fn mean_levels(a: &Framebuffer, b: &Framebuffer) -> f64 {
    (0..a.width).map(|x| column_levels(a, b, x)).sum::<f64>() / f64::from(a.width)
}

/// Mean levels of a frame column-by-column, worst column in `band` around the centre.
fn worst_column(a: &Framebuffer, b: &Framebuffer, band: u32) -> (u32, f64) {
    let mid = a.width / 2;
    (mid - band..=mid + band)
        .map(|x| (x, column_levels(a, b, x)))
        .max_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap()
}

/// Named tolerances of the seam comparison (8-bit sRGB levels).
/// Mean over the frame, same pattern drawn twice from different UV channels.
const SAME_MEAN: f64 = 0.5;
/// Worst single column near the seam.
const SAME_COLUMN: f64 = 3.0;
/// What a smeared strip costs at least in its worst column (measured: see the test output).
const SMEAR_COLUMN: f64 = 20.0;

#[test]
fn no_seam_strip_on_the_spherically_mapped_sphere() {
    let spherical = UvGenerator::Spherical { axis: Axis::Y };
    let own = sphere();
    let mut generated = own.clone();
    generated.uvs = vec![generate_uvs(&generated, &spherical)];
    // Reference: the primitive's analytic UVs, its seam split by construction.
    let reference = frame(unlit_scene(own.clone(), Mat4::IDENTITY));
    let front = frame(unlit_scene(generated.clone(), Mat4::IDENTITY));
    // The same sphere turned 90 degrees about y: its seam at the side, out of view, and
    // the chequer (2 squares = 90 degrees) lands on itself.
    let turned = frame(unlit_scene(
        generated.clone(),
        Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2),
    ));
    // Teeth: the per-vertex map without seam handling (each vertex its own longitude),
    // whose facets across the seam run u from about 1 back to 0.
    let frame_uv = uv_frame(&own);
    let mut smeared = own.clone();
    smeared.uvs = vec![Channel::per_vertex(
        own.positions
            .iter()
            .map(|&p| spherical.map(&frame_uv, p, Vec3::ZERO))
            .collect(),
    )];
    let smeared = frame(unlit_scene(smeared, Mat4::IDENTITY));

    let covered = front.depth.iter().filter(|&&d| d > 0.0).count();
    assert!(
        covered > (SIZE * SIZE / 2) as usize,
        "the sphere fills the frame: {covered}"
    );
    for (what, other) in [
        ("the sphere's own UVs", &reference),
        ("turned 90 degrees", &turned),
    ] {
        let mean = mean_levels(&front, other);
        let (x, col) = worst_column(&front, other, 12);
        eprintln!("generated vs {what}: mean {mean:.3} levels, worst seam column {x}: {col:.3}");
        assert!(mean < SAME_MEAN, "{what}: mean {mean} levels");
        assert!(
            col < SAME_COLUMN,
            "{what}: column {x} differs by {col} levels"
        );
    }
    let (x, col) = worst_column(&smeared, &reference, 12);
    eprintln!("smeared map vs reference: worst seam column {x}: {col:.3}");
    assert!(
        col > SMEAR_COLUMN,
        "the smeared strip must show: column {x}, {col} levels"
    );
}

#[test]
fn the_loader_adds_generated_uvs_to_a_model_without_them() {
    let dir = scratch("loader");
    let path = dir.join("torus.obj");
    write_obj(&torus(), &path);
    let plain = load(&path, &LoadOptions::default()).unwrap();
    assert!(plain.meshes[0].uvs.is_empty(), "the file has no vt");
    for g in generators() {
        let opts = LoadOptions {
            uv: Some(g),
            ..LoadOptions::default()
        };
        let scene = load(&path, &opts).unwrap();
        let mesh = &scene.meshes[0];
        assert_eq!(mesh.uvs.len(), 1, "{g}");
        assert_eq!(mesh.uvs[0], generate_uvs(mesh, &g), "{g}");
        let line = scene
            .report
            .generated
            .iter()
            .find(|l| l.contains("TEXCOORD_0"))
            .unwrap_or_else(|| panic!("{g}: {:?}", scene.report.generated));
        assert!(
            line.contains(&g.to_string()) && line.contains("§9.5") && line.contains("none"),
            "{line}"
        );
    }
}

#[test]
fn a_normal_mapped_model_gets_tangents_for_the_new_uvs() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/texture/normal-sphere.glb");
    let opts = LoadOptions {
        uv: Some(UvGenerator::Planar { axis: Axis::Z }),
        ..LoadOptions::default()
    };
    let scene = load(&path, &opts).unwrap();
    let mesh = &scene.meshes[0];
    let material = &scene.materials[mesh.material.unwrap()];
    assert_eq!(material.normal_texture.unwrap().uv_set, 0);
    assert!(
        scene
            .report
            .generated
            .iter()
            .any(|g| g.contains("MikkTSpace") && g.contains("generated TEXCOORD_0")),
        "{:?}",
        scene.report.generated
    );
    // planar:z keeps v (so y) constant along u, which grows with x: every tangent is the
    // surface direction with no y component and +x, +-(n.z, 0, -n.x). (The file's own
    // tangents follow its longitude and fail this away from the meridian z = 0.)
    let tangents = mesh.tangents.as_ref().unwrap();
    let file_tangents = load(&path, &LoadOptions::default()).unwrap().meshes[0]
        .tangents
        .clone()
        .unwrap();
    let (mut checked, mut unlike_file) = (0, 0);
    for (c, &v) in mesh.corners.iter().enumerate() {
        let n = mesh.normals.at(c, v);
        if n.z.abs() < 0.3 || n.y.abs() > 0.9 {
            continue; // seen edge-on from z, or near a pole: the map degenerates there
        }
        let want = (n.z.signum() * Vec3::new(n.z, 0.0, -n.x)).normalize();
        let t = tangents.at(c, v).truncate();
        assert!(
            t.dot(want) > 0.95,
            "corner {c}: tangent {t}, expected {want}"
        );
        unlike_file += usize::from(file_tangents.at(c, v).truncate().dot(want) < 0.95);
        checked += 1;
    }
    assert!(
        checked > 100 && unlike_file > checked / 4,
        "{checked}, {unlike_file}"
    );
}

#[test]
fn a_degenerate_mesh_gets_a_warning_naming_the_file_not_a_panic() {
    let dir = scratch("degenerate");
    let path = dir.join("point.obj");
    // Three distinct vertices at one point (kept by the loader: the indices differ).
    std::fs::write(&path, "o dot\nv 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n").unwrap();
    for g in generators() {
        let opts = LoadOptions {
            uv: Some(g),
            ..LoadOptions::default()
        };
        let scene = load(&path, &opts).unwrap();
        let warning = scene
            .report
            .warnings
            .iter()
            .find(|w| w.contains("UV map"))
            .unwrap_or_else(|| panic!("{g}: {:?}", scene.report.warnings));
        assert!(
            warning.starts_with(&path.display().to_string())
                && warning.contains("one point")
                && warning.contains(&g.to_string()),
            "{warning}"
        );
        let mesh = &scene.meshes[0];
        assert!(mesh.uvs[0].values.iter().all(|uv| uv.is_finite()), "{g}");
    }
}

fn realist(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(args)
        .output()
        .expect("run realist")
}

fn png(path: &Path) -> Vec<u8> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
        .into_raw()
}

fn mean_bytes(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| f64::from(x.abs_diff(*y)))
        .sum::<f64>()
        / a.len() as f64
}

#[test]
fn render_uv_flag_and_scene_file_key_draw_the_same() {
    let dir = scratch("cli");
    let model = dir.join("torus.obj");
    write_obj(&torus(), &model);
    let tex = dir.join("chequer.png");
    let c = chequer();
    let rgba: Vec<u8> = c.to_srgb8().iter().flatten().copied().collect();
    image::RgbaImage::from_raw(c.width, c.height, rgba)
        .unwrap()
        .save(&tex)
        .unwrap();
    let s = |p: &Path| p.to_str().unwrap().to_owned();
    let run = |extra: &[&str], out: &str| {
        let out = dir.join(out);
        let mut args = vec!["render".to_string()];
        args.extend(extra.iter().map(|a| a.to_string()));
        args.extend(
            [
                "--texture",
                &s(&tex),
                "--size",
                "160x120",
                "--camera",
                "30,35",
                "-o",
                &s(&out),
            ]
            .map(String::from),
        );
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = realist(&refs);
        assert!(
            o.status.success(),
            "{refs:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        png(&out)
    };
    let flag = run(&[&s(&model), "--uv", "spherical"], "flag.png");
    let own = run(&[&s(&model), "--uv", "mesh"], "mesh.png");
    // Without UVs the torus is drawn untextured; with them the chequer shows.
    let textured = mean_bytes(&flag, &own);
    assert!(
        textured > 5.0,
        "--uv spherical changes the frame: {textured}"
    );
    let scene = dir.join("torus.toml");
    std::fs::write(&scene, "model = \"torus.obj\"\nuv = \"spherical\"\n").unwrap();
    let keyed = run(&[&s(&scene)], "key.png");
    assert_eq!(
        mean_bytes(&flag, &keyed),
        0.0,
        "the key draws what the flag draws"
    );
    let overridden = run(&[&s(&scene), "--uv", "mesh"], "over.png");
    assert_eq!(
        mean_bytes(&own, &overridden),
        0.0,
        "--uv mesh overrides the key"
    );

    let x = s(&dir.join("x.png"));
    let bad = realist(&["render", &s(&model), "--uv", "conical", "-o", &x]);
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && err.contains("unknown uv 'conical'"),
        "{err}"
    );
    let bad_file = dir.join("bad.toml");
    std::fs::write(&bad_file, "model = \"torus.obj\"\nuv = \"planar:w\"\n").unwrap();
    let bad = realist(&["render", &s(&bad_file), "-o", &x]);
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && err.contains("bad.toml") && err.contains("line 2"),
        "{err}"
    );

    let info = realist(&["info", &s(&model), "--uv", "box"]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    assert!(
        text.contains("UV sets: TEXCOORD_0 (")
            && text.contains("generated: mesh")
            && text.contains("box map"),
        "{text}"
    );
    let plain = realist(&["info", &s(&model)]);
    assert!(String::from_utf8_lossy(&plain.stdout).contains("UV sets: none"));
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn a_model_file_without_uvs_from_the_shared_models() {
    // The Stanford bunny (no vt, no vn): every generator covers it, finite and in range.
    let root = realist_testkit::shared("the bunny without UVs");
    let path = Path::new(&root).join("models/obj/stanford-bunny.obj");
    for g in generators() {
        let opts = LoadOptions {
            uv: Some(g),
            ..LoadOptions::default()
        };
        let scene = load(&path, &opts).unwrap();
        let mesh = &scene.meshes[0];
        assert_eq!(mesh.uvs.len(), 1);
        let uvs = &mesh.uvs[0];
        let bound = if g.wraps_u() {
            1.0 + MAX_WRAP_EXTENT
        } else {
            1.0
        };
        for uv in &uvs.values {
            assert!(
                uv.is_finite() && uv.x >= -UV_EPS && uv.x <= bound + UV_EPS,
                "{g}: {uv}"
            );
            assert!((-UV_EPS..=1.0 + UV_EPS).contains(&uv.y), "{g}: {uv}");
        }
        assert!(
            scene.report.warnings.iter().all(|w| !w.contains("UV map")),
            "{g}"
        );
    }
}

#[test]
fn a_map_applied_after_loading_drops_the_missing_set_0_warning() {
    // A model whose material reads a texture from TEXCOORD_0 but has no vt: the load says
    // so; the viewer applies its UV map after loading, and then the warning is wrong.
    let dir = scratch("late-map");
    let path = dir.join("textured-torus.obj");
    write_obj(&torus(), &path);
    let obj = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, format!("mtllib t.mtl\nusemtl t\n{obj}")).unwrap();
    std::fs::write(dir.join("t.mtl"), "newmtl t\nKd 1 1 1\nmap_Kd t.png\n").unwrap();
    image::RgbaImage::from_pixel(4, 4, image::Rgba([200, 100, 50, 255]))
        .save(dir.join("t.png"))
        .unwrap();
    let mut scene = load(&path, &LoadOptions::default()).unwrap();
    let missing = |s: &Scene| {
        s.report
            .warnings
            .iter()
            .filter(|w| w.contains("TEXCOORD_0") && w.contains("does not have"))
            .count()
    };
    assert_eq!(missing(&scene), 1, "{:?}", scene.report.warnings);
    let others = scene.report.warnings.len() - 1;
    scene.apply_uv_generator(&UvGenerator::Spherical { axis: Axis::Y });
    assert_eq!(missing(&scene), 0, "{:?}", scene.report.warnings);
    assert_eq!(
        scene.report.warnings.len(),
        others,
        "only that warning went"
    );
    // Loaded with the map, it never appears.
    let opts = LoadOptions {
        uv: Some(UvGenerator::Box),
        ..LoadOptions::default()
    };
    assert_eq!(missing(&load(&path, &opts).unwrap()), 0);
}
