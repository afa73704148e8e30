use glam::{Vec2, Vec3};

use crate::scene::{AlphaMode, Scene};
use crate::tests::TempDir;
use crate::{load, LoadError, LoadOptions};

fn load_obj_text(dir: &TempDir, obj: &str) -> Result<Scene, LoadError> {
    let path = dir.write("model.obj", obj);
    load(&path, &LoadOptions::default())
}

#[test]
fn groups_quads_negative_indices_and_missing_mtl() {
    let dir = TempDir::new("obj-groups");
    let scene = load_obj_text(
        &dir,
        "mtllib missing.mtl\n\
         v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
         g first\nf -4 -3 -2 -1\n\
         v 0 0 1\nv 1 0 1\nv 0 1 1\n\
         o second\nf 5 6 7\nf 1 2\nl 1 2 3\n",
    )
    .unwrap();
    // The faces of two groups, then the line element of the second.
    assert_eq!(scene.meshes.len(), 3);
    let (first, second) = (&scene.meshes[0], &scene.meshes[1]);
    let lines = &scene.meshes[2];
    assert_eq!((lines.name.as_str(), lines.facet_count()), ("second", 0));
    assert_eq!(lines.lines, vec![[0, 1], [1, 2]]);
    assert_eq!(
        lines.positions,
        [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)]
    );
    assert_eq!(
        (first.name.as_str(), second.name.as_str()),
        ("first", "second")
    );
    assert_eq!((first.facets().len(), first.facets()[0].len), (1, 4));
    assert_eq!(
        first.positions,
        [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]
    );
    assert!(first.facets()[0].normal.z > 0.99);
    assert_eq!(second.facet_count(), 1);
    assert_eq!(scene.instances.len(), 3);
    assert!(scene
        .instances
        .iter()
        .all(|i| i.world == glam::Mat4::IDENTITY));
    assert!(first.material.is_none());
    let w = scene.report.warnings.join("\n");
    assert!(
        w.contains("material library not loaded: missing.mtl"),
        "{w}"
    );
    assert!(
        w.contains("dropped 1 face(s) with fewer than 3 vertices"),
        "{w}"
    );
    assert_eq!(
        scene.report.loaded,
        ["object 'second' (from line 14): 0 points, 2 line segments, unlit (no normals)"]
    );
    assert!(
        scene
            .report
            .generated
            .iter()
            .any(|g| g.contains("2 object(s): first, second")),
        "{:?}",
        scene.report.generated
    );
}

#[test]
fn mtl_with_two_kd_numbers_is_a_warning_not_a_panic() {
    let dir = TempDir::new("obj-kd2");
    dir.write("kd2.mtl", "newmtl m\nKd 1 1\nKs 0.5 0.5 0.5\nd 0.5\n");
    let scene = load_obj_text(
        &dir,
        "mtllib kd2.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let w = scene.report.warnings.join("\n");
    assert!(
        w.contains("kd2.mtl:2: `Kd` needs 3 finite numbers, found `1 1`; line ignored"),
        "{w}"
    );
    let m = &scene.materials[scene.meshes[0].material.unwrap()];
    assert_eq!(m.name, "m");
    assert_eq!(m.specular, Vec3::splat(0.5));
    assert_eq!(m.alpha_mode, AlphaMode::Blend);
    assert_eq!(m.base_color.w, 0.5);
}

#[test]
fn materials_textures_and_uv_flip() {
    let dir = TempDir::new("obj-mtl");
    ::image::RgbaImage::from_pixel(2, 2, ::image::Rgba([255, 0, 0, 255]))
        .save(dir.0.join("tex.png"))
        .unwrap();
    dir.write(
        "sub/m.mtl",
        "newmtl a\nKa 0.1 0.1 0.1\nKd 0.5 0.25 1\nKs 1 1 1\nNs 100\nmap_Kd ../tex.png\nmap_Ks ../tex.png\n\
         newmtl b\nKd 1\nmap_Kd -s 1 1 1 ../tex.png\nnewmtl c\nmap_Kd missing.png\n",
    );
    let scene = load_obj_text(
        &dir,
        "mtllib sub/m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nvn 0 0 1\n\
         usemtl a\nf 1/1/1 2/1/1 3/1/1\nusemtl b\nf 1/1 2/1 3/1\nusemtl c\nf 1 2 3\nusemtl nope\nf 3 2 1\n",
    )
    .unwrap();
    assert_eq!(
        scene.textures.len(),
        1,
        "the shared texture is decoded once"
    );
    // OBJ has no sampler: repeat, mipmapped.
    assert_eq!(
        scene.materials[0].base_color_texture.unwrap().sampler,
        crate::texture::Sampler {
            wrap_u: crate::texture::Wrap::Repeat,
            wrap_v: crate::texture::Wrap::Repeat,
            filter: crate::texture::Filter::Trilinear,
        }
    );
    let a = &scene.materials[0];
    assert_eq!(a.base_color, glam::Vec4::new(0.5, 0.25, 1.0, 1.0));
    assert_eq!(
        (a.ambient, a.specular, a.shininess),
        (Vec3::splat(0.1), Vec3::ONE, 100.0)
    );
    assert_eq!(a.base_color_texture.map(|t| t.texture), Some(0));
    // The gloss map is the same file: decoded once, shared.
    assert_eq!(a.specular_texture.map(|t| t.texture), Some(0));
    assert!(scene.materials[1].specular_texture.is_none());
    assert_eq!(
        scene.materials[1].base_color_texture.map(|t| t.texture),
        Some(0)
    );
    assert_eq!(scene.materials[1].base_color.truncate(), Vec3::ONE);
    assert!(scene.materials[2].base_color_texture.is_none());
    let mesh_a = &scene.meshes[0];
    assert_eq!(mesh_a.uvs.first().unwrap().values, [Vec2::new(0.25, 0.25)]);
    assert_eq!(mesh_a.normals.values[0], Vec3::Z);
    let w = scene.report.warnings.join("\n");
    assert!(w.contains("material 'c': texture not loaded"), "{w}");
    assert!(w.contains("`usemtl nope`: no such material"), "{w}");
    assert_eq!(scene.meshes.last().unwrap().material, None);
}

#[test]
fn mtllib_outside_the_folder_and_devices_are_refused() {
    let dir = TempDir::new("obj-escape");
    dir.write("secret.mtl", "newmtl s\nKd 1 0 0\n");
    let inner = TempDir(dir.0.join("model"));
    let scene = load_obj_text(
        &inner,
        "mtllib ../secret.mtl\nmtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    assert!(scene.materials.is_empty());
    let w = scene.report.warnings.join("\n");
    assert_eq!(scene.report.warnings.len(), 2, "{w}");
    assert!(w.contains("outside the model's folder"), "{w}");
}

#[test]
fn non_finite_positions_drop_their_faces() {
    let dir = TempDir::new("obj-nan");
    let scene = load_obj_text(
        &dir,
        "v nan 0 0\nv 1e999 0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 4 5\nf 3 4 5\nf 2 3 4\n",
    )
    .unwrap();
    assert_eq!(scene.meshes[0].facets().len(), 1);
    assert!(
        scene
            .report
            .warnings
            .iter()
            .any(|w| w.contains("dropped 2 face(s) with NaN")),
        "{:?}",
        scene.report.warnings
    );
}

#[test]
fn degenerate_faces_are_dropped_and_reported() {
    let dir = TempDir::new("obj-degenerate");
    let scene = load_obj_text(
        &dir,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 1 2\nf 2 2 2 2\nf 1 2 1 2\nf 2 4 3 3\n",
    )
    .unwrap();
    // `f 2 4 3 3` has three distinct vertices: kept (a triangle with a repeated corner).
    assert_eq!(scene.meshes[0].facets().len(), 2);
    assert!(
        scene
            .report
            .warnings
            .iter()
            .any(|w| w == "OBJ: dropped 3 degenerate face(s) (fewer than 3 distinct vertices)"),
        "{:?}",
        scene.report.warnings
    );
}

#[test]
fn errors_name_file_and_line() {
    let dir = TempDir::new("obj-errors");
    let err = load_obj_text(&dir, "v 0 0 0\nv 1 0 0\nf 1 2 99\n")
        .unwrap_err()
        .to_string();
    let path = dir.0.join("model.obj");
    assert_eq!(
        err,
        format!(
            "{}:3: face refers to vertex 99, but only 2 are defined before this line",
            path.display()
        )
    );
    let err = load_obj_text(&dir, "v 0 0\n").unwrap_err().to_string();
    assert!(
        err.starts_with(&format!("{}:1: `v` needs 3 numbers", path.display())),
        "{err}"
    );
}

#[test]
fn non_utf8_and_empty_files_load() {
    let dir = TempDir::new("obj-utf8");
    let path = dir.write(
        "model.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\no \xff\xfe\nf 1 2 3\n",
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(scene.meshes.len(), 1);
    assert!(scene.report.warnings[0].contains("not valid UTF-8"));
    let scene = load_obj_text(&dir, "").unwrap();
    assert!(scene.meshes.is_empty());
}

#[test]
fn large_generated_cases() {
    let dir = TempDir::new("obj-large");
    // One face with 200k corners, 100k objects, a 16 MiB comment, a v line with 1M numbers.
    let n = 200_000;
    let mut big_face = String::new();
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        big_face.push_str(&format!("v {} {} 0\n", libm::cosf(a), libm::sinf(a)));
    }
    big_face.push('f');
    for i in 1..=n {
        big_face.push_str(&format!(" {i}"));
    }
    let scene = load_obj_text(&dir, &big_face).unwrap();
    assert_eq!(scene.meshes[0].facets()[0].len as usize, n);

    let mut objects = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for i in 0..100_000 {
        objects.push_str(&format!("o o{i}\nf 1 2 3\n"));
    }
    assert_eq!(
        load_obj_text(&dir, &objects).unwrap().instances.len(),
        100_000
    );

    let comment = format!(
        "#{}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "x".repeat(16 << 20)
    );
    assert_eq!(load_obj_text(&dir, &comment).unwrap().meshes.len(), 1);

    let many = format!("v{}\n", " 1".repeat(1_000_000));
    let err = load_obj_text(&dir, &many).unwrap_err().to_string();
    assert!(
        err.contains(":1: `v` needs 3 numbers (4 with w, 6 with a colour), found more than 6"),
        "{err}"
    );
}
