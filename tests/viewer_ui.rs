//! UI tests of the viewer: `ViewerApp::ui_contents` driven by egui_kittest in synchronous
//! mode (loads and renders happen in the calling thread, so no test sleeps), asserting on the
//! app's state, the accessibility tree and the renderer's own buffers (no screenshots).
//!
//! Each test keeps its recent-files list in a temporary folder of its own, so nothing touches
//! the user's configuration.
#![cfg(feature = "viewer")]

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use eframe::egui::{self, accesskit::Role, ColorImage, Key, Modifiers, Pos2, Vec2};
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use glam::Vec3;

use realist::load::{self, LoadOptions};
use realist::render::{PreparedScene, Renderer, Settings};
use realist::shade::Shading;
use realist::viewer::keys::{self, BINDINGS, MOUSE};
use realist::viewer::navigate::{UpAxis, ORBIT_RADIANS_PER_HEIGHT};
use realist::viewer::{ViewerApp, ViewerOptions};

/// The window, in points (one pixel per point).
const SIZE: Vec2 = Vec2::new(1100.0, 640.0);

type App = Harness<'static, ViewerApp>;

/// A model of the repository.
fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models")
        .join(name)
}

/// An empty folder of this test's own.
fn temp_dir(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("viewer_ui")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temporary folder");
    dir
}

/// A synchronous viewer on `model` (else the demo) whose recent-files list lives in `dir`,
/// refining still frames up to `samples` per axis, run until it settles.
fn viewer(model: Option<PathBuf>, dir: &Path, samples: u32) -> App {
    // The app asks for a repaint when a frame is ready: it must reach the harness's context.
    let context: Arc<OnceLock<egui::Context>> = Arc::default();
    let repaint = {
        let context = Arc::clone(&context);
        Arc::new(move || {
            if let Some(ctx) = context.get() {
                ctx.request_repaint();
            }
        })
    };
    let mut app = ViewerApp::new(
        ViewerOptions {
            model,
            synchronous: true,
            recent_file: Some(dir.join("recent.json")),
            ..ViewerOptions::default()
        },
        repaint,
    )
    .expect("synchronous viewer");
    app.max_samples = samples;
    let mut h = Harness::builder()
        .with_size(SIZE)
        .with_context_setup(move |ctx| {
            let _ = context.set(ctx.clone());
        })
        .build_ui_state(|ui, app: &mut ViewerApp| app.ui_contents(ui), app);
    h.run();
    h
}

#[derive(Debug)]
struct Dropped(PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// Drops a file on the window and lets the viewer settle.
fn drop_file(h: &mut App, path: &Path) {
    h.input_mut()
        .dropped_files
        .push(Arc::new(Dropped(path.to_owned())));
    h.run();
}

/// A primary click at a point on the screen (points).
fn click_at(h: &mut App, p: Pos2) {
    h.hover_at(p);
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: p,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        });
    }
    h.run();
}

/// A primary drag through `points` (the first is where the button goes down).
fn drag_through(h: &mut App, points: &[Pos2]) {
    let (first, last) = (points[0], points[points.len() - 1]);
    h.hover_at(first);
    h.drag_at(first);
    for &p in &points[1..] {
        h.hover_at(p);
    }
    h.drop_at(last);
    h.run();
}

/// Ctrl as a Linux keyboard reports it (egui sets `command` along with `ctrl`).
const CTRL: Modifiers = Modifiers {
    ctrl: true,
    command: true,
    ..Modifiers::NONE
};

fn triangles(path: &Path) -> u64 {
    let scene = load::load(path, &LoadOptions::default()).expect("model loads");
    PreparedScene::new(scene).triangle_count()
}

fn demo_triangles() -> u64 {
    PreparedScene::new(realist::scene::demo()).triangle_count()
}

/// The frame on screen is the final one of the newest job, for the view as it is now, at
/// the viewport's size in pixels.
fn assert_current_frame(app: &ViewerApp) {
    let s = app.shown.as_ref().expect("a frame is shown");
    let [w, h] = app.viewport.size_px;
    assert!(w > 100 && h > 100, "viewport {w}x{h}");
    assert_eq!([s.view.width, s.view.height], [w, h], "frame size");
    assert_eq!(s.a.size, [w as usize, h as usize], "image size");
    assert_eq!(s.depth.len(), (w * h) as usize, "depth buffer size");
    assert_eq!(s.tex_a.size(), [w as usize, h as usize], "texture size");
    assert_eq!(
        s.view,
        app.current_view(),
        "the frame shows the current view"
    );
    assert_eq!(s.job, app.host.submitted(), "the frame is the newest job's");
    assert!(s.last && app.settled(), "the frame is final");
}

/// Pixels that differ between two frames of the same size.
fn differing(a: &ColorImage, b: &ColorImage) -> usize {
    assert_eq!(a.size, b.size, "frames of one size");
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| p != q)
        .count()
}

/// The frame on screen differs from `before` in at least 1% of its pixels.
fn assert_frame_changed(app: &ViewerApp, before: &ColorImage, what: &str) {
    let now = &app.shown.as_ref().expect("frame").a;
    let n = differing(now, before);
    assert!(
        n * 100 > now.pixels.len(),
        "{what}: only {n} of {} pixels changed",
        now.pixels.len()
    );
}

fn shown_image(h: &App) -> Arc<ColorImage> {
    Arc::clone(&h.state().shown.as_ref().expect("frame").a)
}

/// The recent-files list as saved in `dir`.
fn recent_list(dir: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(dir.join("recent.json")) else {
        return Vec::new();
    };
    let json: serde_json::Value = serde_json::from_str(&text).expect("recent.json is JSON");
    json["files"]
        .as_array()
        .expect("a list of files")
        .iter()
        .map(|f| f.as_str().expect("a path").to_owned())
        .collect()
}

fn canonical(path: &Path) -> String {
    std::fs::canonicalize(path)
        .expect("file exists")
        .to_str()
        .expect("UTF-8 path")
        .to_owned()
}

/// The torus is on screen: file, triangle count, status bar, frame, recent files.
fn assert_torus_open(h: &App, dir: &Path) {
    let torus = model("torus.obj");
    let app = h.state();
    assert_eq!(app.model.as_deref(), Some(torus.as_path()));
    assert_eq!(app.error, None);
    let n = triangles(&torus);
    assert_ne!(n, demo_triangles(), "the torus is not the demo");
    assert_eq!(app.scene.triangle_count(), n);
    h.get_by_label("torus.obj");
    h.get_by_label(&format!("{n} triangles"));
    assert_current_frame(app);
    assert_eq!(recent_list(dir).first(), Some(&canonical(&torus)));
}

#[test]
fn load_a_model_from_the_command_line_and_by_dropping_it() {
    // On the command line.
    let dir = temp_dir("load-cli");
    let h = viewer(Some(model("torus.obj")), &dir, 4);
    assert_torus_open(&h, &dir);
    assert_eq!(
        h.state().shown.as_ref().unwrap().level,
        realist::viewer::worker::Level::Supersampled(4),
        "a still frame is refined to the final level"
    );

    // Dropped on a viewer showing the demo.
    let dir = temp_dir("load-drop");
    let mut h = viewer(None, &dir, 1);
    let (demo_scene, demo_frame, demo_job) = {
        let app = h.state();
        assert_eq!(app.model, None);
        assert_eq!(app.scene.triangle_count(), demo_triangles());
        assert_current_frame(app);
        let s = app.shown.as_ref().unwrap();
        (Arc::clone(&app.scene), Arc::clone(&s.a), s.job)
    };
    assert!(recent_list(&dir).is_empty());
    drop_file(&mut h, &model("torus.obj"));
    assert_torus_open(&h, &dir);
    let app = h.state();
    assert!(!Arc::ptr_eq(&app.scene, &demo_scene), "a new scene");
    assert!(app.shown.as_ref().unwrap().job > demo_job, "a new frame");
    assert_frame_changed(app, &demo_frame, "the torus replaced the demo");
}

/// Opens the shading mode combo box of the A side, which shows `current`.
fn click_shading_combo(h: &mut App, current: &str) {
    let combo = h.get_by_role_and_label(Role::ComboBox, "shading mode A");
    assert_eq!(combo.value().as_deref(), Some(current));
    combo.click();
    h.run();
}

#[test]
fn switch_shading_modes_with_the_panel_and_the_m_key() {
    let dir = temp_dir("modes");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    assert_eq!(h.state().settings.shading, None);
    let per_model = shown_image(&h);

    // With the panel: open the combo box and pick an entry by its label.
    click_shading_combo(&mut h, "per model");
    h.get_by_label("normals").click();
    h.run();
    assert_eq!(h.state().settings.shading, Some(Shading::Normals));
    assert_current_frame(h.state());
    assert_frame_changed(h.state(), &per_model, "per model -> normals");
    assert!(h.query_by_label("normals").is_none(), "the popup closed");
    let combo = h.get_by_role_and_label(Role::ComboBox, "shading mode A");
    assert_eq!(combo.value().as_deref(), Some("normals"));
    let normals = shown_image(&h);

    // With the keyboard: M is the next mode, Shift+M the previous one.
    h.key_press(Key::M);
    h.run();
    assert_eq!(h.state().settings.shading, Some(Shading::Depth));
    assert_current_frame(h.state());
    assert_frame_changed(h.state(), &normals, "normals -> depth (M)");
    h.key_press_modifiers(Modifiers::SHIFT, Key::M);
    h.run();
    assert_eq!(h.state().settings.shading, Some(Shading::Normals));
    assert_current_frame(h.state());
    assert_eq!(
        differing(&shown_image(&h), &normals),
        0,
        "the same mode draws the same frame"
    );

    // From "per model", M goes to the mode after Phong (what per model draws here).
    click_shading_combo(&mut h, "normals");
    h.get_by_label("per model (textured if it has a texture, else Phong)")
        .click();
    h.run();
    assert_eq!(h.state().settings.shading, None);
    assert_eq!(differing(&shown_image(&h), &per_model), 0);
    h.key_press(Key::M);
    h.run();
    assert_eq!(h.state().settings.shading, Some(Shading::Blinn));
    assert_frame_changed(h.state(), &per_model, "per model -> blinn (M)");
}

/// The turntable angles of a camera about +Y: (yaw, pitch) of the eye seen from the target.
fn yaw_pitch(eye: Vec3, target: Vec3) -> (f32, f32) {
    let d = (eye - target).normalize();
    (d.x.atan2(d.z), d.y.asin())
}

/// The camera's right vector is horizontal (a turntable never rolls).
fn assert_level(camera: &realist::scene::Camera) {
    let forward = (camera.target - camera.eye).normalize();
    let right = forward.cross(camera.up).normalize();
    assert!(right.y.abs() < 1e-5, "rolled: right {right}");
    assert!(camera.up.y > 0.0, "upside down: up {}", camera.up);
}

#[test]
fn orbit_with_a_drag() {
    let dir = temp_dir("orbit");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    let before = h.state().current_view().camera;
    let (job, image) = (h.state().shown.as_ref().unwrap().job, shown_image(&h));
    let height = h.state().viewport.size_px[1] as f32;
    let centre = h.state().viewport.rect.center();
    assert_level(&before);

    // Right by 8 x 20 points, in eight moves.
    let points: Vec<Pos2> = (0..=8)
        .map(|i| centre + Vec2::new(20.0 * i as f32, 0.0))
        .collect();
    drag_through(&mut h, &points);
    let app = h.state();
    let after = app.current_view().camera;
    assert_eq!(after.target, before.target, "the target stays");
    let (d0, d1) = (
        (before.eye - before.target).length(),
        (after.eye - after.target).length(),
    );
    assert!((d1 - d0).abs() <= 1e-4 * d0, "distance {d0} -> {d1}");
    assert_level(&after);
    let (yaw0, pitch0) = yaw_pitch(before.eye, before.target);
    let (yaw1, pitch1) = yaw_pitch(after.eye, after.target);
    assert!(
        (pitch1 - pitch0).abs() < 1e-4,
        "a level drag keeps the pitch"
    );
    // Dragging right turns the model right: the eye goes to its left (yaw decreases), by
    // pi per viewport height of drag; the move that starts the drag may be lost.
    let turned = (yaw0 - yaw1).rem_euclid(std::f32::consts::TAU);
    let per_px = ORBIT_RADIANS_PER_HEIGHT / height;
    assert!(
        turned > 140.0 * per_px - 1e-4 && turned < 160.0 * per_px + 1e-4,
        "turned {turned} rad for a 160 px drag ({per_px} rad/px)"
    );
    assert!(app.panels.probe.is_none(), "a drag is not a click");
    assert_current_frame(app);
    assert!(app.shown.as_ref().unwrap().job > job, "a new frame");
    assert_frame_changed(app, &image, "orbit right");

    // Down by 100 points: the eye rises, still at the same distance, still level.
    let points: Vec<Pos2> = (0..=5)
        .map(|i| centre + Vec2::new(0.0, 20.0 * i as f32))
        .collect();
    drag_through(&mut h, &points);
    let app = h.state();
    let up = app.current_view().camera;
    let (yaw2, pitch2) = yaw_pitch(up.eye, up.target);
    assert!((yaw2 - yaw1).abs() < 1e-4, "a vertical drag keeps the yaw");
    assert!(
        pitch2 > pitch1 + 80.0 * per_px - 1e-4,
        "pitch {pitch1} -> {pitch2}"
    );
    assert!(((up.eye - up.target).length() - d0).abs() <= 1e-4 * d0);
    assert_level(&up);
    assert_current_frame(app);
}

/// The direction the camera looks along.
fn forward(app: &ViewerApp) -> Vec3 {
    let c = app.current_view().camera;
    (c.target - c.eye).normalize()
}

fn assert_near(a: Vec3, b: Vec3, what: &str) {
    assert!((a - b).length() < 1e-4, "{what}: {a} vs {b}");
}

#[test]
fn keys_change_the_view_the_overlays_and_the_panels() {
    let dir = temp_dir("keys");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    let shown_ortho = |h: &App| h.state().shown.as_ref().expect("frame").view.camera.ortho;
    let press = |h: &mut App, mods: Modifiers, key: Key| {
        h.key_press_modifiers(mods, key);
        h.run();
        assert_current_frame(h.state());
    };

    // 5: orthographic and back.
    assert!(shown_ortho(&h).is_none());
    press(&mut h, Modifiers::NONE, Key::Num5);
    assert!(h.state().nav.is_ortho());
    assert!(shown_ortho(&h).is_some());
    press(&mut h, Modifiers::NONE, Key::Num5);
    assert!(shown_ortho(&h).is_none());

    // 1: front view, looking along -Z with +Y up.
    press(&mut h, Modifiers::NONE, Key::Num1);
    assert_near(forward(h.state()), Vec3::NEG_Z, "front, Y up");
    assert_near(h.state().current_view().camera.up, Vec3::Y, "up");

    // Ctrl+Z: Z is up; the front view then looks along +Y with +Z up. Ctrl+Y goes back.
    press(&mut h, CTRL, Key::Z);
    assert_eq!(h.state().nav.up_axis(), UpAxis::Z);
    press(&mut h, Modifiers::NONE, Key::Num1);
    assert_near(forward(h.state()), Vec3::Y, "front, Z up");
    assert_near(h.state().current_view().camera.up, Vec3::Z, "up");
    press(&mut h, CTRL, Key::Y);
    assert_eq!(h.state().nav.up_axis(), UpAxis::Y);

    // E: the wireframe overlay, on and off again.
    let plain = shown_image(&h);
    press(&mut h, Modifiers::NONE, Key::E);
    assert!(h.state().settings.wireframe_overlay);
    assert_frame_changed(h.state(), &plain, "wireframe overlay");
    press(&mut h, Modifiers::NONE, Key::E);
    assert!(!h.state().settings.wireframe_overlay);
    assert_eq!(differing(&shown_image(&h), &plain), 0);

    // Shift+A: 4x multisampling (the torus's silhouette changes), and off again; plain A is
    // still the supersampling level.
    let max_samples = h.state().max_samples;
    press(&mut h, Modifiers::SHIFT, Key::A);
    assert_eq!(h.state().settings.msaa, 4);
    assert_eq!(h.state().max_samples, max_samples);
    // Only edge pixels change (1,138 of 216,398 measured): the interior is shaded as before.
    let edges = differing(&shown_image(&h), &plain);
    assert!(edges > 300, "multisampling changed {edges} pixels");
    press(&mut h, Modifiers::SHIFT, Key::A);
    assert_eq!(h.state().settings.msaa, 1);
    assert_eq!(differing(&shown_image(&h), &plain), 0);

    // H: the cheat sheet lists every binding, with the toggles' states.
    assert!(h.query_by_label("Keys and mouse").is_none());
    press(&mut h, Modifiers::NONE, Key::H);
    assert!(h.state().panels.cheat_sheet);
    h.get_by_label("Keys and mouse");
    for b in BINDINGS {
        let key = keys::describe(b);
        assert!(
            h.query_all_by_label(&key).next().is_some(),
            "the sheet shows {key}"
        );
        assert!(
            h.query_all_by_label(b.what).next().is_some(),
            "the sheet says what {key} does: {}",
            b.what
        );
    }
    for (gesture, what) in MOUSE {
        h.get_by_label(gesture);
        h.get_by_label(what);
    }
    h.get_by_label("perspective");
    press(&mut h, Modifiers::NONE, Key::Num5);
    h.get_by_label("orthographic");
    press(&mut h, Modifiers::NONE, Key::H);
    assert!(h.query_by_label("Keys and mouse").is_none(), "H closes it");

    // Tab: the panels go and the viewport takes the whole width; Tab brings them back.
    let narrow = h.state().viewport.size_px;
    h.get_by_label("Shading");
    press(&mut h, Modifiers::NONE, Key::Tab);
    assert!(!h.state().panels.visible);
    assert!(
        h.query_by_label("Shading").is_none(),
        "the side panel is gone"
    );
    let wide = h.state().viewport.size_px;
    // The harness puts a margin of 8 points around the UI.
    assert_eq!(wide[0], SIZE.x as u32 - 16, "the viewport spans the window");
    assert!(wide[0] > narrow[0]);
    let focused = |h: &App| h.ctx.memory(|m| m.focused());
    assert_eq!(focused(&h), None, "Tab does not move egui's focus");
    press(&mut h, Modifiers::NONE, Key::Tab);
    assert!(h.state().panels.visible, "Tab shows the panels again");
    h.get_by_label("Shading");
    assert_eq!(h.state().viewport.size_px, narrow);
    // A focused widget (Shift+Tab is egui's) does not keep the keys from the viewer.
    press(&mut h, Modifiers::SHIFT, Key::Tab);
    assert!(focused(&h).is_some(), "Shift+Tab focuses a widget");
    press(&mut h, Modifiers::NONE, Key::M);
    assert_eq!(h.state().settings.shading, Some(Shading::Blinn));
}

#[test]
fn a_bad_file_leaves_the_scene_intact() {
    let dir = temp_dir("bad");
    let bad_obj = dir.join("bad.obj");
    std::fs::write(&bad_obj, "v 0 0 0\nv 1 0 0\nf 1 2 99\n").unwrap();
    let glb = std::fs::read(model("checker-cube.glb")).unwrap();
    let truncated = dir.join("truncated.glb");
    std::fs::write(&truncated, &glb[..glb.len() / 2]).unwrap();

    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    let scene = Arc::clone(&h.state().scene);
    let nav = h.state().nav.clone();
    let (job, image) = (h.state().shown.as_ref().unwrap().job, shown_image(&h));
    for (file, problem) in [
        (&bad_obj, "face refers to vertex 99"),
        (&truncated, "truncated"),
    ] {
        drop_file(&mut h, file);
        let app = h.state();
        let e = app.error.clone().expect("an error is shown");
        assert!(
            e.starts_with(&file.display().to_string()),
            "the error names the file: {e}"
        );
        assert!(e.contains(problem), "the error says what is wrong: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
        h.get_by_label(&e);
        assert!(Arc::ptr_eq(&app.scene, &scene), "the scene stays");
        assert_eq!(app.model.as_deref(), Some(model("torus.obj").as_path()));
        assert_eq!(app.nav, nav, "the camera stays");
        // The frame stays; the error's line in the status bar may take room from the
        // viewport, and then the same view is drawn again at the new size.
        let s = app.shown.as_ref().expect("a frame is shown");
        if s.a.size == image.size {
            assert!(s.job == job && Arc::ptr_eq(&s.a, &image), "the same frame");
        }
        assert_current_frame(app);
    }
    assert_eq!(recent_list(&dir), [canonical(&model("torus.obj"))]);
    h.get_by_label("dismiss").click();
    h.run();
    assert_eq!(h.state().error, None);

    // A model on the command line that fails: the demo, with the error.
    let dir = temp_dir("bad-cli");
    let bad = dir.join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nf 1 2 99\n").unwrap();
    let h = viewer(Some(bad.clone()), &dir, 1);
    let app = h.state();
    assert_eq!(app.model, None);
    assert_eq!(app.scene.triangle_count(), demo_triangles());
    let e = app.error.clone().expect("the error is shown");
    assert!(e.starts_with(&bad.display().to_string()), "{e}");
    h.get_by_label(&e);
    assert_current_frame(app);
    assert!(recent_list(&dir).is_empty(), "a failed load is not recent");
}

/// The Normals view stores `srgb_to_linear(n * 0.5 + 0.5)`: the normal back.
fn decode_normal(c: glam::Vec4) -> Vec3 {
    let d = |v: f32| realist::texture::linear_to_srgb(v) * 2.0 - 1.0;
    Vec3::new(d(c.x), d(c.y), d(c.z))
}

#[test]
fn probe_a_pixel_against_the_renderer_buffers() {
    let dir = temp_dir("probe");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    let (view, depth, rect, ppp, job) = {
        let app = h.state();
        let s = app.shown.as_ref().unwrap();
        (
            s.view.clone(),
            s.depth.clone(),
            app.viewport.rect,
            app.viewport.pixels_per_point,
            s.job,
        )
    };
    let (w, hgt) = (view.width, view.height);
    let at = |x: u32, y: u32| depth[(y * w + x) as usize];
    // Pixels well inside the torus (their neighbours two pixels away drawn too).
    let inside: Vec<(u32, u32)> = (2..hgt - 2)
        .flat_map(|y| (2..w - 2).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            [(0, 0), (2, 0), (0, 2), (4, 2), (2, 4)]
                .iter()
                .all(|&(dx, dy)| at(x + dx - 2, y + dy - 2) > 0.0)
        })
        .collect();
    assert!(inside.len() > 1000, "the torus covers the viewport");
    let mut normals = Renderer::new();
    normals.render(
        &h.state().scene,
        &Settings {
            shading: Some(Shading::Normals),
            ..Settings::default()
        },
        &view,
    );
    let normals = normals.target().expect("a frame");
    let target = h.state().nav.target();
    for k in [0, inside.len() / 3, inside.len() / 2, inside.len() - 1] {
        let (x, y) = inside[k];
        let p = rect.min + Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / ppp;
        click_at(&mut h, p);
        let app = h.state();
        assert_eq!(app.nav.target(), target, "a click does not centre");
        // The probed frame stays on screen (with the probe's marker on it): the panel
        // showing the probe does not take room from the viewport.
        assert_eq!(app.viewport.rect, rect, "the viewport keeps its place");
        assert_eq!(app.shown.as_ref().unwrap().job, job, "no new frame");
        let pv = app.panels.probe.as_ref().expect("the probe panel");
        assert_eq!(pv.pixel, [x, y]);
        assert_eq!(pv.frame_size, [w, hgt]);
        let probe = pv.probe.as_ref().expect("the probe hits the torus");
        let d = at(x, y);
        assert!(
            (probe.depth - d).abs() <= 1e-4 * d,
            "({x}, {y}): probe depth {} vs depth buffer {d}",
            probe.depth
        );
        assert_eq!(pv.buffer_depth, Some(d));
        let (colour, _) = normals.pixel(x, y).expect("pixel");
        let n = decode_normal(colour);
        assert!(
            (n - probe.normal).length() < 2e-3,
            "({x}, {y}): probe normal {} vs normal buffer {n}",
            probe.normal
        );
        h.get_by_label_contains(&format!("pixel ({x}, {y}) of {w}x{hgt}"));
    }

    // The background: a probe that meets nothing.
    let corner = rect.min + Vec2::new(1.5, 1.5) / ppp;
    assert_eq!(at(1, 1), 0.0, "nothing drawn in the corner");
    click_at(&mut h, corner);
    let pv = h.state().panels.probe.as_ref().expect("the probe panel");
    assert_eq!(pv.pixel, [1, 1]);
    assert!(pv.probe.is_none() && pv.buffer_depth.is_none());
}
