//! UI tests of the viewer: `ViewerApp::ui_contents` driven by egui_kittest in synchronous
//! mode (loads and renders happen in the calling thread, so no test sleeps), asserting on the
//! app's state, the accessibility tree and the renderer's own buffers (no screenshots).
//!
//! Each test keeps its recent-files list in a temporary folder of its own, so nothing touches
//! the user's configuration.
#![cfg(feature = "viewer")]

mod common;

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use eframe::egui::{self, accesskit::Role, ColorImage, Key, Modifiers, Pos2, Vec2};
use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use glam::Vec3;

use realist::load::{self, LoadOptions};
use realist::render::{Environment, PreparedScene, Renderer, Settings};
use realist::scene::Play;
use realist::shade::Shading;
use realist::viewer::keys::{self, BINDINGS, MOUSE};
use realist::viewer::navigate::{UpAxis, ORBIT_RADIANS_PER_HEIGHT};
use realist::viewer::panels::{
    Cx, Dock, EnvironmentPanel, Installed, LightsPanel, Panel, SavePanel, ScreenshotPanel,
    ShadingPanel,
};
use realist::viewer::timeline::Clock;
use realist::viewer::{ViewerApp, ViewerOptions};

/// The window, in points (one pixel per point).
const SIZE: Vec2 = Vec2::new(1100.0, 640.0);

type App = Harness<'static, ViewerApp>;

/// The fog checkbox's label.
const FOG: &str = "fog (linear, the textbook's pipeline chapter, §5.1)";

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
    viewer_with(model, dir, samples, |_| {})
}

/// [`viewer`], with `setup` applied to the app before its first UI pass.
fn viewer_with(
    model: Option<PathBuf>,
    dir: &Path,
    samples: u32,
    setup: impl FnOnce(&mut ViewerApp),
) -> App {
    let options = ViewerOptions {
        model,
        synchronous: true,
        recent_file: Some(dir.join("recent.json")),
        ..ViewerOptions::default()
    };
    viewer_from(options, samples, setup)
}

/// A viewer made from `options` (e.g. with the render thread a user has), `setup` applied
/// before its first UI pass.
fn viewer_from(options: ViewerOptions, samples: u32, setup: impl FnOnce(&mut ViewerApp)) -> App {
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
    let mut app = ViewerApp::new(options, repaint).expect("viewer");
    app.max_samples = samples;
    setup(&mut app);
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
    (libm::atan2f(d.x, d.z), libm::asinf(d.y))
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
    assert!(
        !h.state().shared.moved,
        "the hint on moving the camera shows"
    );
    drag_through(&mut h, &points);
    let app = h.state();
    assert!(app.shared.moved, "the hint goes once the camera moves");
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
    assert!(app.shared.probe.is_none(), "a drag is not a click");
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
    assert!(h.state().shared.cheat_sheet);
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
    assert!(!h.state().shared.panels_visible);
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
    assert!(
        h.state().shared.panels_visible,
        "Tab shows the panels again"
    );
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
        // The frame stays: the error's line in the status bar takes no room from the
        // viewport.
        let s = app.shown.as_ref().expect("a frame is shown");
        assert!(s.job == job && Arc::ptr_eq(&s.a, &image), "the same frame");
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
        let pv = app.shared.probe.as_ref().expect("the probe panel");
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

    // Another shading mode: the probe is read again at the same pixel from the new frame.
    let before = h.state().shared.probe.clone().expect("a probe");
    let [x, y] = before.pixel;
    assert_ne!(before.probe.as_ref().unwrap().mode, Shading::Flat);
    h.state_mut().settings.shading = Some(Shading::Flat);
    h.run();
    let app = h.state();
    let pv = app.shared.probe.as_ref().expect("still a probe");
    assert_eq!(pv.pixel, [x, y]);
    assert_eq!(pv.probe.as_ref().unwrap().mode, Shading::Flat, "read again");
    let s = app.shown.as_ref().unwrap();
    let c = s.a.pixels[(y * s.view.width + x) as usize];
    assert_eq!(
        pv.shown_rgb,
        Some([c.r(), c.g(), c.b()]),
        "from the new frame"
    );
    h.state_mut().settings.shading = None;
    h.run();

    // The background: a probe that meets nothing.
    let corner = rect.min + Vec2::new(1.5, 1.5) / ppp;
    assert_eq!(at(1, 1), 0.0, "nothing drawn in the corner");
    click_at(&mut h, corner);
    let pv = h.state().shared.probe.as_ref().expect("the probe panel");
    assert_eq!(pv.pixel, [1, 1]);
    assert!(pv.probe.is_none() && pv.buffer_depth.is_none());
}

// ---------------------------------------------------------------------------------------
// Lights, gizmos, environment, materials and the probe's light shares (issue 12).

use realist::render::{Lights, ToneMap};
use realist::scene::{Attenuation, Light, LightKind};
use realist::shade::FogDistance;
use realist::viewer::gizmos::{clip_2d, Projector, NEAR_FRACTION};

/// Activates the widget labelled `label` (through accessibility, so it need not be
/// scrolled into view) and lets the viewer settle.
fn activate(h: &mut App, label: &str) {
    h.get_by_label(label).click_accesskit();
    h.run();
}

/// Sets the drag value or slider named `label` as a screen reader would.
fn set_value(h: &mut App, label: &str, value: f64) {
    h.get_by_label(label).set_value_accesskit(value);
    h.run();
}

/// Picks `entry` in the combo box named `combo`. (A click through accessibility does not
/// close the popup as a mouse click does: Escape does.)
fn choose(h: &mut App, combo: &str, entry: &str) {
    h.get_by_role_and_label(Role::ComboBox, combo)
        .click_accesskit();
    h.run();
    activate(h, entry);
    h.key_press(Key::Escape);
    h.run();
    assert!(
        !egui::Popup::is_any_open(&h.ctx),
        "{combo}: the popup closed"
    );
}

/// The custom light list the editor made.
fn custom_lights(app: &ViewerApp) -> (Vec<Light>, bool) {
    match &app.settings.lights {
        Lights::Custom {
            lights,
            follow_camera,
        } => (lights.clone(), *follow_camera),
        Lights::Auto => panic!("the editor left the lights on Auto"),
    }
}

fn degrees(radians: f32) -> f32 {
    radians.to_degrees()
}

#[test]
fn a_light_turned_into_a_spot_keeps_its_values_and_its_cone_follows_the_editor() {
    let dir = temp_dir("spot");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    // The torus has no lights: the default rig, attached to the camera.
    activate(&mut h, "Lights");
    activate(&mut h, "1: key (directional)");
    assert_eq!(
        h.state().settings.lights,
        Lights::Auto,
        "opening the editor changes nothing"
    );
    let rig_key = Light::default_rig(glam::Mat3::IDENTITY)[1].clone();
    let directional = shown_image(&h);

    choose(&mut h, "light 1 kind", "spot");
    let (lights, follow) = custom_lights(h.state());
    assert!(follow, "the rig follows the camera");
    assert_eq!(lights.len(), 4);
    let key = &lights[1];
    assert_eq!(key.kind, LightKind::Spot);
    assert_eq!(
        Light {
            kind: LightKind::Directional,
            ..key.clone()
        },
        rig_key,
        "only the kind changed"
    );
    assert_current_frame(h.state());
    assert_frame_changed(h.state(), &directional, "directional -> spot");
    h.get_by_label("1: key (spot)");

    // Aimed from the eye at the torus, the 30-degree falloff takes it all in.
    activate(&mut h, "aim at the centre");
    let key = custom_lights(h.state()).0[1].clone();
    assert_eq!(key.position, Vec3::ZERO, "at the eye (camera space)");
    let centre = h
        .state()
        .current_view()
        .camera
        .view()
        .transform_point3(h.state().scene.bounding_sphere().0);
    assert!(key.direction.angle_between(centre).abs() < 1e-4);
    // The falloff below the hotspot pulls the hotspot in with it.
    // Half the angle the scene's bounding sphere subtends from the eye: the torus's outer
    // part falls outside the cone.
    let wide = shown_image(&h);
    let (radius, distance) = (h.state().scene.bounding_sphere().1, centre.length());
    let narrow = f64::from(libm::asinf(radius / distance).to_degrees() * 0.5);
    assert!(f64::from(degrees(key.inner)) > narrow);
    set_value(&mut h, "light 1 outer", narrow);
    let key = custom_lights(h.state()).0[1].clone();
    let close = |a: f32| (f64::from(degrees(a)) - narrow).abs() < 1e-3;
    assert!(close(key.outer), "outer {}", degrees(key.outer));
    assert!(close(key.inner), "inner {}", degrees(key.inner));
    assert_current_frame(h.state());
    assert_frame_changed(h.state(), &wide, "a narrower cone");

    // A hotspot beyond the falloff pushes the falloff out.
    set_value(&mut h, "light 1 inner", 40.0);
    let key = custom_lights(h.state()).0[1].clone();
    assert!((degrees(key.inner) - 40.0).abs() < 1e-3);
    assert!((degrees(key.outer) - 40.0).abs() < 1e-3);
    // Beyond what the renderer accepts: held at its limit.
    set_value(&mut h, "light 1 outer", 150.0);
    let key = custom_lights(h.state()).0[1].clone();
    assert!(key.outer <= realist::shade::MAX_HALF_ANGLE + 1e-6);
    assert!(key.inner <= key.outer);

    // To a point light and back: the cone is still there.
    let cone = (key.inner, key.outer);
    choose(&mut h, "light 1 kind", "point");
    assert_eq!(custom_lights(h.state()).0[1].kind, LightKind::Point);
    assert!(
        h.query_by_label("light 1 outer").is_none(),
        "a point light has no cone"
    );
    choose(&mut h, "light 1 kind", "spot");
    let key = custom_lights(h.state()).0[1].clone();
    assert_eq!((key.inner, key.outer), cone);

    // Attenuation: linear with its two distances kept in order.
    choose(&mut h, "light 1 attenuation", "linear");
    let Attenuation::Linear { near, far } = custom_lights(h.state()).0[1].attenuation else {
        panic!("linear attenuation expected");
    };
    assert!(near < far && far > 0.0, "near {near} far {far}");
    set_value(&mut h, "light 1 near", f64::from(far) * 2.0);
    let a = custom_lights(h.state()).0[1].attenuation;
    assert!(a.is_valid(), "{a:?}");
    let Attenuation::Linear { near: n2, far: f2 } = a else {
        panic!("still linear");
    };
    assert!((n2 - far * 2.0).abs() < 1e-3 * far && n2 <= f2);
    choose(&mut h, "light 1 attenuation", "range");
    assert!(matches!(custom_lights(h.state()).0[1].attenuation, Attenuation::Range(r) if r > 0.0));

    // Shadows: a spot can cast them.
    activate(&mut h, "light 1 shadows");
    assert!(custom_lights(h.state()).0[1].shadow);

    // Back to the rig.
    activate(&mut h, "back to the scene's lights (or the default rig)");
    assert_eq!(h.state().settings.lights, Lights::Auto);
    assert_eq!(differing(&shown_image(&h), &directional), 0);
}

#[test]
fn lights_are_added_duplicated_removed_and_follow_the_camera_or_not() {
    let dir = temp_dir("light-list");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    activate(&mut h, "Lights");
    let before = shown_image(&h);
    activate(&mut h, "+ point");
    let added = shown_image(&h);
    let (lights, follow) = custom_lights(h.state());
    assert_eq!(lights.len(), 5);
    assert_eq!(lights[4].kind, LightKind::Point);
    assert!(follow);
    assert_frame_changed(h.state(), &before, "a point light added");

    // Out of camera space: the lights stay where they are in the world.
    let camera = h.state().current_view().camera;
    let world_before = camera.view().inverse().transform_point3(lights[4].position);
    activate(
        &mut h,
        "follow the camera (positions and directions in camera space)",
    );
    let (lights, follow) = custom_lights(h.state());
    assert!(!follow);
    assert!(
        (lights[4].position - world_before).length() < 1e-4,
        "{} vs {world_before}",
        lights[4].position
    );
    // The same lights in the world: the same frame, but for rounding in a few pixels.
    let moved = differing(&shown_image(&h), &added);
    assert!(moved * 1000 < added.pixels.len(), "{moved} pixels changed");

    activate(&mut h, "4: point 4 (point)");
    activate(&mut h, "light 4 duplicate");
    let lights = custom_lights(h.state()).0;
    assert_eq!(lights.len(), 6);
    assert_eq!(lights[5].position, lights[4].position);
    assert_eq!(lights[5].name, "point 4 copy");
    activate(&mut h, "light 4 remove");
    let lights = custom_lights(h.state()).0;
    assert_eq!(lights.len(), 5);
    assert_eq!(lights[4].name, "point 4 copy");
}

#[test]
fn odd_light_values_show_without_panicking_and_unchanged() {
    let dir = temp_dir("odd-lights");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    h.state_mut().shared.light_gizmos = true;
    let nan = f32::NAN;
    let odd = vec![
        Light::spot(Vec3::splat(nan), Vec3::ZERO, Vec3::ONE, 1.0, 0.2),
        Light {
            inner: nan,
            outer: f32::INFINITY,
            ..Light::spot(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z, Vec3::ONE, 0.0, 0.0)
        },
        Light::rect(
            Vec3::new(0.0, 3.0, 0.0),
            Vec3::NEG_Y,
            Vec3::NEG_Y,
            glam::Vec2::new(nan, -1.0),
            Vec3::splat(f32::INFINITY),
        )
        .with_attenuation(Attenuation::Linear {
            near: 5.0,
            far: 1.0,
        }),
        Light::directional(Vec3::splat(nan), Vec3::ONE).with_intensity(nan),
        Light::point(Vec3::new(1e30, 0.0, 0.0), Vec3::ONE),
        // Valid but odd: the renderer holds the hotspot at the falloff.
        Light::spot(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z, Vec3::ONE, 1.0, 0.2)
            .with_attenuation(Attenuation::Range(nan)),
        Light::spot(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z, Vec3::ONE, 1.0, 0.2),
    ];
    let custom = Lights::Custom {
        lights: odd,
        follow_camera: false,
    };
    h.state_mut().settings.lights = custom;
    // The viewer settles although these settings never equal themselves (NaN).
    h.run();
    let settings = h.state().settings.clone();
    activate(&mut h, "Lights");
    for i in 0..7 {
        let prefix = format!("{i}: ");
        let header = h
            .query_all_by(|n| text_of(n).is_some_and(|l| l.starts_with(&prefix)))
            .next()
            .and_then(|n| text_of(&n.accesskit_node()))
            .expect("a header per light");
        activate(&mut h, &header);
    }
    h.run();
    assert!(
        realist::viewer::same::same(&h.state().settings, &settings),
        "showing odd values changes nothing"
    );
    // Every gizmo point is finite; the lights that cannot shine are not drawn at all.
    let gizmos = &h.state().viewport.gizmos;
    assert_eq!(
        gizmos.iter().map(|g| g.index).collect::<Vec<_>>(),
        [4, 6],
        "{gizmos:?}"
    );
    for g in gizmos {
        for p in g.lines.iter().chain(&g.faint).flatten().chain(&g.anchor) {
            assert!(p.x.is_finite() && p.y.is_finite(), "{g:?}");
        }
    }
    // Editing one odd value writes a sane one.
    set_value(&mut h, "light 1 outer", 20.0);
    let l = &custom_lights(h.state()).0[1];
    assert!(l.inner.is_finite() && l.inner <= l.outer, "{l:?}");
}

#[test]
fn gizmos_show_each_light_where_the_camera_sees_it_and_toggle() {
    let dir = temp_dir("gizmos");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    // Off until asked for: a model opens on a clean view.
    assert!(!h.state().shared.light_gizmos);
    assert!(h.state().viewport.gizmos.is_empty());
    h.key_press(Key::L);
    h.run();
    // The rig's key, fill and rim lights are arrows; ambient light is not drawn.
    let g = h.state().viewport.gizmos.clone();
    assert_eq!(
        g.iter().map(|g| g.index).collect::<Vec<_>>(),
        [1, 2, 3],
        "{g:?}"
    );
    assert!(g
        .iter()
        .all(|g| g.kind == LightKind::Directional && g.lines.len() == 3));
    h.key_press(Key::L);
    h.run();
    assert!(!h.state().shared.light_gizmos);
    assert!(h.state().viewport.gizmos.is_empty(), "L hides them");
    h.key_press(Key::L);
    h.run();
    assert_eq!(h.state().viewport.gizmos.len(), 3, "L shows them again");

    // A spot placed by the editor: its apex where the camera projects it, a cone around it.
    activate(&mut h, "Lights");
    activate(&mut h, "+ spot");
    let app = h.state();
    let spot = custom_lights(app).0[4].clone();
    let view = app.shown.as_ref().unwrap().view.clone();
    let world = view.camera.view().inverse().transform_point3(spot.position);
    let expected = Projector::new(&view, app.viewport.rect)
        .point(world)
        .expect("in front of the camera");
    let g = app
        .viewport
        .gizmos
        .iter()
        .find(|g| g.index == 4)
        .expect("the spot's gizmo");
    assert_eq!(g.kind, LightKind::Spot);
    let apex = g.anchor.expect("the apex is in view");
    assert!((apex - expected).length() < 1e-3);
    assert!(app.viewport.rect.contains(apex), "the apex is on screen");
    // 48 segments of the falloff circle and 4 generators, all on screen here.
    assert_eq!(g.lines.len(), 52);
    assert!(g.faint.len() > 48, "axis and hotspot circle");

    activate(&mut h, "show the lights and their cones in the view (L)");
    assert!(
        h.state().viewport.gizmos.is_empty(),
        "the checkbox hides them"
    );
}

#[test]
fn gizmo_segments_are_clipped_at_the_near_plane() {
    let camera = realist::scene::Camera {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        near: 0.5,
        far: 100.0,
        ..realist::scene::Camera::default()
    };
    let view = realist::render::View {
        camera,
        width: 800,
        height: 600,
    };
    let rect = egui::Rect::from_min_size(Pos2::new(10.0, 20.0), Vec2::new(400.0, 300.0));
    let p = Projector::new(&view, rect);
    // The target projects to the centre.
    assert!((p.point(Vec3::ZERO).unwrap() - rect.center()).length() < 1e-3);
    // Behind the eye: no point; a segment entirely behind: nothing.
    assert_eq!(p.point(Vec3::new(0.0, 0.0, 6.0)), None);
    assert_eq!(
        p.segment(Vec3::new(0.0, 0.0, 6.0), Vec3::new(1.0, 0.0, 7.0)),
        None
    );
    // From behind the camera to the origin, off the axis: cut where it crosses the clipping
    // plane just in front of the eye, which projects to where that point would.
    let near = NEAR_FRACTION * 5.0;
    let (a, b) = (Vec3::new(1.0, 0.5, 8.0), Vec3::ZERO);
    let seg = p.segment(a, b).expect("the front part");
    let t = (8.0 - (5.0 - near)) / 8.0;
    let crossing = a + (b - a) * t;
    assert!((p.depth(crossing) - near).abs() < 1e-5);
    let expected = p.point(crossing + (b - a) * 1e-6).unwrap();
    // That is far off screen (next to the eye): the segment is cut again where it leaves the
    // viewport grown by its size (400 x 300 points) on every side, on the same line.
    let outer = rect.expand(400.0);
    assert!(!outer.contains(expected), "{expected:?}");
    let (got, want) = (
        (seg[0] - rect.center()).normalized(),
        (expected - rect.center()).normalized(),
    );
    assert!((got - want).length() < 1e-3, "{seg:?} vs {expected:?}");
    assert!(
        (seg[0].x - outer.right()).abs() < 1e-3 || (seg[0].y - outer.top()).abs() < 1e-3,
        "on the grown viewport's edge: {seg:?}"
    );
    assert!((seg[1] - rect.center()).length() < 1e-3);
    for q in seg {
        assert!(q.x.is_finite() && q.y.is_finite());
    }
    // Non-finite points draw nothing.
    assert_eq!(p.segment(Vec3::splat(f32::NAN), Vec3::ZERO), None);
    assert_eq!(p.point(Vec3::new(f32::INFINITY, 0.0, 0.0)), None);
    // 2-D: a segment crossing the rectangle is cut at its sides; one outside is dropped.
    let r = egui::Rect::from_min_max(Pos2::ZERO, Pos2::new(10.0, 10.0));
    let c = clip_2d(Pos2::new(-10.0, 5.0), Pos2::new(20.0, 5.0), r).unwrap();
    assert_eq!(c, [Pos2::new(0.0, 5.0), Pos2::new(10.0, 5.0)]);
    assert_eq!(
        clip_2d(Pos2::new(-5.0, -5.0), Pos2::new(-1.0, 20.0), r),
        None
    );
}

#[test]
fn fog_tone_map_shadows_and_ground_from_the_panel() {
    let dir = temp_dir("environment");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    activate(&mut h, "Environment, exposure, fog, tone map, shadows");
    let clear = shown_image(&h);
    assert_eq!(h.state().settings.fog, None);
    activate(&mut h, FOG);
    let fog = h.state().settings.fog.expect("fog is on");
    assert!(fog.is_valid(), "{fog:?}");
    assert_eq!(h.state().split.b.fog, Some(fog), "B follows A's fog");
    assert_current_frame(h.state());
    assert_frame_changed(h.state(), &clear, "fog on");

    // near past far: far moves out of the way.
    set_value(&mut h, "fog near", f64::from(fog.far) + 1.0);
    let f = h.state().settings.fog.unwrap();
    assert!(
        (f.near - (fog.far + 1.0)).abs() < 1e-3 && f.near < f.far,
        "{f:?}"
    );
    // far before near: near moves.
    set_value(&mut h, "fog far", 0.5);
    let f = h.state().settings.fog.unwrap();
    assert!(
        (f.far - 0.5).abs() < 1e-4 && f.near < f.far && f.near >= 0.0,
        "{f:?}"
    );
    activate(&mut h, "camera depth");
    assert_eq!(h.state().settings.fog.unwrap().distance, FogDistance::Depth);
    // Off and on again: the same fog comes back.
    let kept = h.state().settings.fog;
    activate(&mut h, FOG);
    assert_eq!(h.state().settings.fog, None);
    assert_eq!(differing(&shown_image(&h), &clear), 0, "fog off again");
    activate(&mut h, FOG);
    assert_eq!(h.state().settings.fog, kept);

    // Tone maps: with the key light ten times as strong, much of the torus is above 1.
    activate(&mut h, FOG);
    activate(&mut h, "Lights");
    activate(&mut h, "1: key (directional)");
    set_value(&mut h, "light 1 intensity", 10.0);
    let clamped = shown_image(&h);
    choose(&mut h, "tone map A", "scale-max");
    assert_eq!(h.state().settings.tone, ToneMap::ScaleMax);
    assert_eq!(h.state().split.b.tone, ToneMap::Auto, "B keeps its own");
    assert_frame_changed(h.state(), &clamped, "clamp -> scale by the largest");
    let scaled = shown_image(&h);
    choose(&mut h, "tone map A", "reinhard");
    assert_frame_changed(h.state(), &scaled, "scale-max -> Reinhard");

    choose(&mut h, "shadow map size", "512x512");
    assert_eq!(h.state().settings.shadow.size, 512);
    set_value(&mut h, "shadow PCF radius", 3.0);
    assert_eq!(h.state().settings.shadow.pcf, 3);
    set_value(&mut h, "shadow slope bias", 4.0);
    assert!((h.state().settings.shadow.slope - 4.0).abs() < 1e-6);
    assert_eq!(h.state().split.b.shadow, h.state().settings.shadow);

    assert_eq!(h.state().settings.ground, None);
    let bare = shown_image(&h);
    activate(&mut h, "ground plane under the scene (catches shadows)");
    let g = h.state().settings.ground.expect("a ground plane");
    assert_current_frame(h.state());
    assert_frame_changed(h.state(), &bare, "a ground plane");
    set_value(&mut h, "ground extent", 2.0);
    assert_eq!(
        h.state().settings.ground.unwrap().extent,
        2.0,
        "was {}",
        g.extent
    );
}

#[test]
fn material_editor_sets_the_new_parameters() {
    let dir = temp_dir("materials");
    let mut h = viewer(Some(model("checker-cube.glb")), &dir, 1);
    activate(&mut h, "Materials");
    assert_eq!(
        h.state().settings.materials,
        None,
        "opening the editor changes nothing"
    );
    let before = shown_image(&h);
    activate(&mut h, "alpha mode mask");
    let m = h.state().settings.materials.clone().expect("an override")[0].clone();
    assert_eq!(m.alpha_mode, realist::scene::AlphaMode::Mask(0.5));
    set_value(&mut h, "material alpha cutoff", 0.8);
    let m = h.state().settings.materials.clone().unwrap()[0].clone();
    assert_eq!(m.alpha_mode, realist::scene::AlphaMode::Mask(0.8));
    activate(&mut h, "alpha mode blend");
    set_value(&mut h, "material alpha", 0.4);
    let m = h.state().settings.materials.clone().unwrap()[0].clone();
    assert_eq!(m.alpha_mode, realist::scene::AlphaMode::Blend);
    assert!((m.base_color.w - 0.4).abs() < 1e-6);
    assert_frame_changed(h.state(), &before, "a see-through cube");
    set_value(&mut h, "material shininess", 500.0);
    let m = h.state().settings.materials.clone().unwrap()[0].clone();
    assert!((m.shininess - 500.0).abs() < 1e-3);
    activate(&mut h, "lit on both sides, not culled");
    assert!(h.state().settings.materials.clone().unwrap()[0].double_sided);
    // The metallic-roughness rows of a glTF material (issue 20).
    let dielectric = shown_image(&h);
    set_value(&mut h, "material metallic", 1.0);
    set_value(&mut h, "material roughness", 0.3);
    set_value(&mut h, "material ior", 2.0);
    set_value(&mut h, "material emissive strength", 3.0);
    let m = h.state().settings.materials.clone().unwrap()[0].clone();
    let p = m.pbr.expect("a glTF material");
    assert_eq!((m.metallic, m.roughness), (1.0, 0.3));
    assert_eq!((p.ior, p.emissive_strength), (2.0, 3.0));
    assert_frame_changed(h.state(), &dielectric, "metal");
    // The layers (issue 37): a clear coat and a sheen over the metal.
    let metal = shown_image(&h);
    set_value(&mut h, "material clearcoat", 1.0);
    set_value(&mut h, "material clearcoat roughness", 0.2);
    set_value(&mut h, "material sheen roughness", 0.5);
    let p = h.state().settings.materials.clone().unwrap()[0]
        .pbr
        .expect("a glTF material");
    assert_eq!(
        (p.clearcoat, p.clearcoat_roughness, p.sheen_roughness),
        (1.0, 0.2, 0.5)
    );
    assert_frame_changed(h.state(), &metal, "a clear coat");
    activate(&mut h, "restore the file's materials");
    assert_eq!(h.state().settings.materials, None);
    assert_eq!(differing(&shown_image(&h), &before), 0);
}

/// The text a node shows: a label's value, any other widget's label.
fn text_of(n: &egui_kittest::kittest::AccessKitNode<'_>) -> Option<String> {
    if n.role() == Role::Label {
        n.value()
    } else {
        n.label()
    }
}

/// Probe rows of the lights: "light N: KIND ...".
fn probe_light_rows(h: &App) -> Vec<String> {
    h.query_all_by(|n| text_of(n).is_some_and(|l| l.starts_with("light ") && l.contains(": ")))
        .filter_map(|n| text_of(&n.accesskit_node()))
        .collect()
}

#[test]
fn the_probe_lists_every_light_with_its_share() {
    let dir = temp_dir("probe-lights");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    let centre_of_torus_ring = |app: &ViewerApp| {
        // A pixel on the torus: the nearest drawn pixel left of the centre.
        let s = app.shown.as_ref().unwrap();
        let (w, hh) = (s.view.width, s.view.height);
        let y = hh / 2;
        let x = (0..w / 2)
            .rev()
            .find(|&x| s.depth[(y * w + x) as usize] > 0.0)
            .expect("the torus crosses the middle row");
        let x = x.saturating_sub(10);
        app.viewport.rect.min
            + Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / app.viewport.pixels_per_point
    };
    let at = centre_of_torus_ring(h.state());
    click_at(&mut h, at);
    let probe = h
        .state()
        .shared
        .probe
        .clone()
        .unwrap()
        .probe
        .expect("a hit");
    assert_eq!(probe.lights.len(), 3, "key, fill and rim");
    assert_eq!(
        probe_light_rows(&h),
        [
            "light 1: directional 'key'",
            "light 2: directional 'fill'",
            "light 3: directional 'rim'"
        ]
    );
    h.get_by_label("ambient");
    assert!(h.query_by_label("fog factor").is_none());

    // One more light, and fog: a row each.
    activate(&mut h, "Lights");
    activate(&mut h, "+ spot");
    activate(&mut h, "Environment, exposure, fog, tone map, shadows");
    activate(&mut h, FOG);
    let at = centre_of_torus_ring(h.state());
    click_at(&mut h, at);
    let probe = h
        .state()
        .shared
        .probe
        .clone()
        .unwrap()
        .probe
        .expect("a hit");
    assert_eq!(probe.lights.len(), 4);
    let rows = probe_light_rows(&h);
    assert_eq!(rows.len(), 4, "{rows:?}");
    assert_eq!(rows[3], "light 4: spot 'spot 4'");
    let f = probe.fog.expect("a fog factor");
    h.get_by_label(&format!("{f:.4}"));
    h.get_by_label("fog factor");
    // The shares add up to the colour before fog.
    let sum = probe
        .lights
        .iter()
        .fold(probe.ambient, |a, s| a + s.diffuse + s.specular);
    let fog = h.state().settings.fog.unwrap();
    let fogged = sum + (fog.color - sum) * f;
    assert!(
        (fogged - probe.color).length() < 1e-4,
        "{fogged} vs {}",
        probe.color
    );
}

/// A PNG of one colour.
fn write_png(path: &Path, rgb: [u8; 3]) {
    let img = image::RgbaImage::from_pixel(8, 6, image::Rgba([rgb[0], rgb[1], rgb[2], 255]));
    img.save(path).expect("PNG written");
}

#[test]
fn a_rect_light_projects_a_chosen_image_and_a_bad_file_shows_its_error() {
    let dir = temp_dir("slide");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    activate(&mut h, "Lights");
    activate(&mut h, "+ rect");
    let white = shown_image(&h);
    let rect = custom_lights(h.state()).0[4].clone();
    assert_eq!(rect.kind, LightKind::Rect);
    assert!(rect.image.is_none());
    activate(&mut h, "4: rect 4 (rect)");

    // The picker opens (an egui window, so it works anywhere). Its icons are emoji that
    // egui's default fonts lack: drawn as boxes, which the harness would take for a bug;
    // and its text fields have no accessible names, which `run` would: one step, then shut.
    h.ctx
        .set_missing_glyph_policy(egui::MissingGlyphPolicy::Tofu);
    h.get_by_label("light 4 choose image").click_accesskit();
    h.run_steps(4);
    assert!(matches!(
        h.state().panel::<LightsPanel>().unwrap().slide_picker,
        Some((4, _))
    ));
    h.get_by_label_contains("Image for the rectangular spotlight");
    h.state_mut()
        .panels
        .get_mut::<LightsPanel>()
        .unwrap()
        .slide_picker = None;
    h.run();

    // A file that is not an image: the error, one line, and nothing else changes.
    let bad = dir.join("bad.png");
    std::fs::write(&bad, b"not a png at all").unwrap();
    h.state_mut()
        .with_panel(|p: &mut LightsPanel, cx| p.read_image(cx, 4, bad.clone()))
        .unwrap();
    h.run();
    let e = h
        .state()
        .panel::<LightsPanel>()
        .unwrap()
        .slide_error
        .clone()
        .expect("an error");
    assert!(
        e.starts_with(&bad.display().to_string()) && !e.contains('\n'),
        "{e}"
    );
    // In the light editor and in the status bar.
    assert_eq!(h.get_all_by_label(&e).count(), 2, "{e}");
    assert!(custom_lights(h.state()).0[4].image.is_none());
    let missing = dir.join("missing.png");
    h.state_mut()
        .with_panel(|p: &mut LightsPanel, cx| p.read_image(cx, 4, missing))
        .unwrap();
    h.run();
    assert!(h
        .state()
        .panel::<LightsPanel>()
        .unwrap()
        .slide_error
        .clone()
        .unwrap()
        .contains("missing.png"));
    assert_eq!(differing(&shown_image(&h), &white), 0);

    // A red slide: the light's patch turns red.
    let red = dir.join("red.png");
    write_png(&red, [255, 0, 0]);
    h.state_mut()
        .with_panel(|p: &mut LightsPanel, cx| p.read_image(cx, 4, red))
        .unwrap();
    h.run();
    assert_eq!(h.state().panel::<LightsPanel>().unwrap().slide_error, None);
    let image = custom_lights(h.state()).0[4]
        .image
        .clone()
        .expect("an image");
    assert_eq!((image.width, image.height), (8, 6));
    h.get_by_label("red.png (8x6)");
    assert_current_frame(h.state());
    let now = shown_image(&h);
    assert_frame_changed(h.state(), &white, "a red slide");
    // Changed pixels lost green and blue (the slide multiplies the light's colour).
    let redder = now
        .pixels
        .iter()
        .zip(&white.pixels)
        .filter(|(a, b)| a != b)
        .all(|(a, b)| a.g() <= b.g() && a.b() <= b.b());
    assert!(
        redder,
        "the slide only takes light away from green and blue"
    );
    activate(&mut h, "light 4 clear image");
    assert!(custom_lights(h.state()).0[4].image.is_none());
    assert_eq!(differing(&shown_image(&h), &white), 0);
}

#[test]
fn the_demo_spotlight_shadow_follows_the_editor_and_the_shadow_settings() {
    let dir = temp_dir("shadows");
    let mut h = viewer(None, &dir, 1);
    activate(&mut h, "Lights");
    activate(&mut h, "2: spotlight (spot)");
    let shadowed = shown_image(&h);
    assert_eq!(h.state().settings.lights, Lights::Auto);
    // The demo's spotlight casts shadows: off, the frame changes; on again, it is back.
    activate(&mut h, "light 2 shadows");
    let (lights, follow) = custom_lights(h.state());
    assert!(!follow, "the scene's lights are in the world");
    assert!(!lights[2].shadow);
    assert_current_frame(h.state());
    let lit = shown_image(&h);
    let n = differing(&lit, &shadowed);
    assert!(n > 100, "only {n} pixels changed without the shadow");
    activate(&mut h, "light 2 shadows");
    assert_eq!(differing(&shown_image(&h), &shadowed), 0);

    // Hard edges (one tap) and a coarse map move the shadow's edge pixels.
    activate(&mut h, "Environment, exposure, fog, tone map, shadows");
    h.get_by_label("Shadows cast by: 2 spotlight");
    set_value(&mut h, "shadow PCF radius", 0.0);
    assert_eq!(h.state().settings.shadow.pcf, 0);
    assert!(differing(&shown_image(&h), &shadowed) > 0, "PCF 1 -> 0");
    let hard = shown_image(&h);
    choose(&mut h, "shadow map size", "256x256");
    assert_eq!(h.state().settings.shadow.size, 256);
    assert!(differing(&shown_image(&h), &hard) > 0, "1024 -> 256 texels");
}

use realist::scenefile::{ModelSource, SceneFile};

/// Two cameras agree to `tol` (relative to the larger of 1 and the eye's distance); their
/// `up` is compared as the screen's up (a file's need not be perpendicular to the view).
fn assert_same_camera(a: &realist::scene::Camera, b: &realist::scene::Camera, tol: f32) {
    let scale = (a.eye - a.target).length().max(1.0);
    let close = |x: Vec3, y: Vec3| (x - y).length() <= tol * scale;
    let screen_up = |c: &realist::scene::Camera| {
        let back = (c.eye - c.target).normalize();
        (c.up - back * c.up.dot(back)).normalize()
    };
    assert!(
        close(a.eye, b.eye)
            && close(a.target, b.target)
            && (screen_up(a) - screen_up(b)).length() <= tol,
        "eye, target, up: {a:?} vs {b:?}"
    );
    assert!(
        (a.yfov - b.yfov).abs() <= 1e-5,
        "yfov {} vs {}",
        a.yfov,
        b.yfov
    );
    assert_eq!(a.ortho.is_some(), b.ortho.is_some(), "projection");
    assert!(
        (a.near - b.near).abs() <= tol * scale && (a.far - b.far).abs() <= tol * scale,
        "near/far {}..{} vs {}..{}",
        a.near,
        a.far,
        b.near,
        b.far
    );
}

/// Pixels whose colour differs by more than `levels` in some channel.
/// A folder inside `dir` whose path is over 200 characters long, with spaces in its names.
fn long_folder(dir: &Path) -> PathBuf {
    let mut p = dir.to_owned();
    while p.as_os_str().len() < 240 {
        p.push("a folder with a long name and spaces in it");
    }
    std::fs::create_dir_all(&p).expect("long folder");
    p
}

/// The viewport's rectangle (points) and size (pixels), which must not move.
fn viewport_of(h: &App) -> (egui::Rect, [u32; 2]) {
    let v = &h.state().viewport;
    (v.rect, v.size_px)
}

#[test]
fn the_viewport_keeps_its_size_whatever_the_length_of_the_paths_and_names_shown() {
    let dir = temp_dir("long-paths");
    let short = dir.join("s");
    std::fs::create_dir_all(&short).unwrap();
    let long = long_folder(&dir);
    assert!(long.as_os_str().len() > 200);
    let short_model = short.join("t.obj");
    std::fs::copy(model("torus.obj"), &short_model).unwrap();
    let long_model = long.join(
        "a torus with a file name long enough to be cut in every panel of the viewer, \
         and a folder to match.obj",
    );
    std::fs::copy(model("torus.obj"), &long_model).unwrap();
    // Names from inside a file: an object and a material far wider than any panel.
    let long_name = "a_name_without_any_space_in_it_so_nothing_can_wrap_it_".repeat(5);
    let named = short.join("named.obj");
    std::fs::write(
        short.join("named.mtl"),
        format!("newmtl {long_name}\nKd 0.8 0.3 0.2\n"),
    )
    .unwrap();
    std::fs::write(
        &named,
        format!(
            "mtllib named.mtl\no {long_name}\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\
             usemtl {long_name}\nf 1 2 3\n"
        ),
    )
    .unwrap();

    let mut h = viewer(Some(short_model.clone()), &dir, 1);
    // Every section that can show a path or a name is open.
    for section in ["Materials", "Lights", "Stats"] {
        activate(&mut h, section);
    }
    let start = viewport_of(&h);
    // Opening sections full of names does not widen the panels either.
    let plain = viewer(None, &temp_dir("long-paths-plain"), 1);
    assert_eq!(viewport_of(&plain), start, "the sections opened");
    assert_current_frame(h.state());
    let check = |h: &App, what: &str| {
        assert_eq!(viewport_of(h), start, "{what}: the viewport moved");
        assert_current_frame(h.state());
    };

    drop_file(&mut h, &long_model);
    assert_eq!(h.state().model.as_deref(), Some(long_model.as_path()));
    check(&h, "a model at a long path");
    // The status bar names it, cut to fit, with the whole name for whoever asks.
    let name = long_model.file_name().unwrap().to_str().unwrap();
    h.get_by_label(name);

    let scene = long.join("a scene file with a long name of its own.toml");
    save_scene_to(&mut h, &scene);
    assert_eq!(h.state().error, None);
    let notice = h.state().notice.clone().expect("the save is reported");
    assert!(notice.contains(scene.to_str().unwrap()), "{notice}");
    check(&h, "a scene saved to a long path");
    drop_file(&mut h, &scene);
    assert_eq!(
        h.state().scene_file.as_ref().map(|f| &f.file.path),
        Some(&scene)
    );
    check(&h, "the scene file reopened");

    let bad = long.join("a broken model.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nf 1 2 99\n").unwrap();
    drop_file(&mut h, &bad);
    let e = h.state().error.clone().expect("the error is shown");
    assert!(e.starts_with(bad.to_str().unwrap()), "{e}");
    h.get_by_label(&e);
    check(&h, "an error naming a long path");

    drop_file(&mut h, &named);
    assert_eq!(h.state().error, None, "the named model opens");
    assert_eq!(h.state().model.as_deref(), Some(named.as_path()));
    check(&h, "an object and a material with long names");

    // A viewer started on the long path is laid out as one started on the short path.
    let g = viewer(Some(long_model), &temp_dir("long-paths-cli"), 1);
    let opened = viewport_of(&g);
    let s = viewer(Some(short_model), &temp_dir("short-path-cli"), 1);
    assert_eq!(opened, viewport_of(&s), "the long path's window");
}

fn differing_by_more_than(a: &ColorImage, b: &ColorImage, levels: u8) -> usize {
    assert_eq!(a.size, b.size, "frames of one size");
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| {
            p.to_array()
                .iter()
                .zip(q.to_array())
                .any(|(x, y)| x.abs_diff(y) > levels)
        })
        .count()
}

/// Types `path` into the scene file section's path field and presses its Save button.
fn save_scene_to(h: &mut App, path: &Path) {
    h.get_by_label("scene file path")
        .set_text_value_accesskit(path.to_str().expect("UTF-8 path"));
    h.run();
    assert_eq!(
        h.state().panel::<SavePanel>().unwrap().path,
        path.to_str().unwrap()
    );
    activate(h, "Save scene");
}

#[test]
fn a_scene_saved_by_the_viewer_opens_again_with_its_settings_camera_and_frame() {
    let dir = temp_dir("scene-save");
    let mut h = viewer(None, &dir, 1);
    // Change what shows: the spotlight's intensity, fog, the tone map, and the camera.
    activate(&mut h, "Lights");
    activate(&mut h, "2: spotlight (spot)");
    set_value(&mut h, "light 2 intensity", 2.5);
    activate(&mut h, "Environment, exposure, fog, tone map, shadows");
    activate(&mut h, FOG);
    choose(&mut h, "tone map A", "reinhard");
    h.key_press(Key::Num9);
    h.run();
    let before = h.state().settings.clone();
    assert!(before.fog.is_some() && before.tone == ToneMap::Reinhard);
    assert_eq!(custom_lights(h.state()).0[2].intensity, 2.5);
    assert_eq!(h.state().scene_file.as_ref().map(|f| &f.file.path), None);
    assert_eq!(
        h.state().panel::<SavePanel>().unwrap().path,
        "scene.toml",
        "the demo's default"
    );

    let path = dir.join("saved.toml");
    save_scene_to(&mut h, &path);
    let app = h.state();
    assert_eq!(app.error, None);
    let notice = app.notice.clone().expect("the save is reported");
    assert!(
        notice.starts_with("saved scene file") && notice.contains(path.to_str().unwrap()),
        "{notice}"
    );
    // The saved file is the one open now.
    let open = app.scene_file.as_ref().expect("a scene file is open");
    assert_eq!(open.file.path, path);
    assert_eq!(open.model, ModelSource::Demo);
    assert_eq!(app.model.as_deref(), Some(path.as_path()));
    assert_eq!(app.scene_name(), "saved.toml (demo)");
    h.get_by_label("saved.toml (demo)");
    assert_eq!(recent_list(&dir).first(), Some(&canonical(&path)));
    let text = std::fs::read_to_string(&path).expect("the file is written");
    assert!(
        text.contains("model = \"demo\"") && text.contains("[fog]"),
        "{text}"
    );
    assert!(text.contains("intensity = 2.5"), "{text}");
    // The library reads it back to the same settings (the viewer's refinement as samples).
    let loaded = SceneFile::load(&path).expect("the saved file loads");
    assert_eq!(
        loaded.settings,
        Settings {
            samples: app.max_samples,
            ..before.clone()
        }
    );
    assert_current_frame(h.state());
    let view = h.state().current_view();
    let frame = shown_image(&h);

    // A fresh viewer on the file: the same settings, camera and frame.
    let dir2 = temp_dir("scene-open");
    let mut g = viewer(Some(path.clone()), &dir2, 1);
    let app = g.state();
    assert_eq!(app.error, None);
    assert!(
        app.notice
            .as_deref()
            .is_some_and(|n| n.contains("saved.toml")),
        "{:?}",
        app.notice
    );
    assert_eq!(app.model.as_deref(), Some(path.as_path()));
    assert_eq!(
        app.scene_file.as_ref().map(|f| (&f.file.path, &f.model)),
        Some((&path, &ModelSource::Demo))
    );
    assert_eq!(app.scene.triangle_count(), demo_triangles());
    assert_eq!(app.settings.samples, 1);
    assert_eq!(app.settings, before, "the settings came back");
    assert_eq!(app.split.b.fog, before.fog, "B follows A's fog");
    assert_current_frame(app);
    let view2 = app.current_view();
    assert_eq!([view2.width, view2.height], [view.width, view.height]);
    assert_same_camera(&view.camera, &view2.camera, 1e-4);
    let frame2 = shown_image(&g);
    let off = differing_by_more_than(&frame, &frame2, 2);
    assert!(
        off * 1000 < frame.pixels.len(),
        "{off} of {} pixels differ by more than 2 levels",
        frame.pixels.len()
    );
    // And the frame is not the demo as it starts (the test can tell them apart).
    let plain = viewer(None, &temp_dir("scene-plain"), 1);
    let demo = shown_image(&plain);
    assert!(differing_by_more_than(&demo, &frame2, 2) * 100 > frame2.pixels.len());

    // Saved again (as JSON) from the opened file: still the demo, same settings.
    let json = dir2.join("again.json");
    save_scene_to(&mut g, &json);
    assert_eq!(g.state().error, None);
    let again = SceneFile::load(&json).expect("the JSON loads");
    assert_eq!(again.model, ModelSource::Demo);
    assert_eq!(
        again.settings,
        Settings {
            samples: 1,
            ..before
        }
    );
}

#[test]
fn a_scene_file_sets_model_settings_and_camera_and_reloads() {
    let dir = temp_dir("scene-file");
    let torus = model("torus.obj");
    let path = dir.join("torus.toml");
    let write = |extra: &str| {
        std::fs::write(
            &path,
            format!(
                "model = {:?}\nshading = \"gouraud\"\nbackground = [0.2, 0.1, 0.05]\n\
                 [camera]\neye = [0.5, 3.0, 2.0]\ntarget = [0, 0, 0]\nyfov = 30\n{extra}",
                torus.to_str().unwrap()
            ),
        )
        .unwrap();
    };
    write("[fog]\nnear = 1\nfar = 6\n");
    // Dropped on the demo.
    let mut h = viewer(None, &dir, 1);
    drop_file(&mut h, &path);
    let app = h.state();
    assert_eq!(app.error, None);
    assert_eq!(app.scene.triangle_count(), triangles(&torus));
    let loaded = SceneFile::load(&path).unwrap();
    assert_eq!(app.settings, loaded.settings);
    assert_eq!(app.settings.shading, Some(Shading::Gouraud));
    assert!(app.settings.fog.is_some());
    assert_eq!(
        app.scene_file.as_ref().map(|f| &f.model),
        Some(&ModelSource::File(torus.clone()))
    );
    h.get_by_label("torus.toml (torus.obj)");
    // The file's camera at the viewport's aspect (not the file's 16:9).
    let view = app.current_view();
    let want = loaded
        .file
        .camera(app.scene.scene(), view.width as f32 / view.height as f32)
        .unwrap()
        .unwrap();
    assert_same_camera(&want, &view.camera, 1e-4);
    assert_ne!(view.width * 9, view.height * 16, "the viewport is not 16:9");
    assert_current_frame(app);
    assert_eq!(
        app.panel::<SavePanel>().unwrap().path,
        path.to_str().unwrap(),
        "saves over it"
    );
    let fogged = shown_image(&h);

    // Reloading (the watcher does the same on a change) reads the file again.
    write("");
    h.key_press(Key::ArrowUp);
    h.run();
    let app = h.state();
    assert_eq!(app.error, None);
    assert_eq!(app.settings.fog, None, "the file's fog is gone");
    assert_current_frame(app);
    assert_frame_changed(app, &fogged, "reloaded without fog");

    // A model opened next: the scene file is closed.
    drop_file(&mut h, &torus);
    assert!(h.state().scene_file.is_none());
    assert_torus_open(&h, &dir);
}

#[test]
fn a_bad_scene_file_or_save_path_shows_its_error_and_keeps_the_scene() {
    let dir = temp_dir("scene-bad");
    let good = dir.join("good.toml");
    std::fs::write(&good, "model = \"demo\"\nshading = \"flat\"\n").unwrap();
    let cases = [
        ("unknown.toml", "model = \"demo\"\nbogus = 1\n", "bogus"),
        ("syntax.toml", "model = \"demo\"\n[fog\n", "line 2"),
        (
            "range.toml",
            "model = \"demo\"\n[fog]\nnear = 5\nfar = 1\n",
            "fog",
        ),
        ("missing.toml", "model = \"nowhere.obj\"\n", "nowhere.obj"),
        ("bad.json", "{\"model\": \"demo\", \"msaa\": 3}", "msaa"),
    ];
    let mut h = viewer(Some(good.clone()), &dir, 1);
    assert_eq!(h.state().error, None);
    assert_eq!(h.state().settings.shading, Some(Shading::Flat));
    // Without a [camera], the demo's own camera (as `realist render` takes it).
    let demo_camera = realist::scene::demo().cameras[0].clone();
    let camera = h.state().current_view().camera;
    assert!(
        (camera.eye - demo_camera.eye).length() < 1e-4
            && (camera.target - demo_camera.target).length() < 1e-4,
        "{camera:?} vs {demo_camera:?}"
    );
    let scene = Arc::clone(&h.state().scene);
    let settings = h.state().settings.clone();
    let nav = h.state().nav.clone();
    for (name, text, key) in cases {
        let bad = dir.join(name);
        std::fs::write(&bad, text).unwrap();
        drop_file(&mut h, &bad);
        let app = h.state();
        let e = app.error.clone().expect("an error is shown");
        assert!(e.starts_with(bad.to_str().unwrap()), "names the file: {e}");
        assert!(e.contains(key), "names the key ({key}): {e}");
        assert!(!e.contains('\n'), "one line: {e}");
        h.get_by_label(&e);
        assert!(Arc::ptr_eq(&app.scene, &scene), "{name}: the scene stays");
        assert_eq!(app.settings, settings, "{name}: the settings stay");
        assert_eq!(app.nav, nav, "{name}: the camera stays");
        assert_eq!(app.model.as_deref(), Some(good.as_path()));
        assert_eq!(app.scene_file.as_ref().map(|f| &f.file.path), Some(&good));
        assert_current_frame(app);
    }
    assert_eq!(
        recent_list(&dir),
        [canonical(&good)],
        "failures are not recent"
    );

    // Saving where it cannot: the error, and nothing changes (the file stays open).
    for (target, problem) in [
        (dir.join("scene.txt"), "must end in .toml or .json"),
        (dir.join("no-such-folder").join("s.toml"), "s.toml"),
    ] {
        save_scene_to(&mut h, &target);
        let app = h.state();
        let e = app.error.clone().expect("a save error");
        assert!(
            e.starts_with(target.to_str().unwrap()) && e.contains(problem),
            "{e}"
        );
        assert!(!target.exists());
        assert_eq!(app.model.as_deref(), Some(good.as_path()));
        assert_eq!(app.scene_file.as_ref().map(|f| &f.file.path), Some(&good));
        // In the section and in the status bar.
        assert_eq!(h.get_all_by_label(&e).count(), 2, "{e}");
    }

    // A bad scene file on the command line: the demo, with the error.
    let bad = dir.join("unknown.toml");
    let h = viewer(Some(bad.clone()), &temp_dir("scene-bad-cli"), 1);
    let app = h.state();
    assert!(app.scene_file.is_none() && app.model.is_none());
    assert_eq!(app.scene.triangle_count(), demo_triangles());
    let e = app.error.clone().expect("the error is shown");
    assert!(
        e.starts_with(bad.to_str().unwrap()) && e.contains("bogus"),
        "{e}"
    );
    assert_current_frame(app);
}

// The texture lab: procedural and image sources per slot, and the UV map.

use realist::scene::{Slot, SlotOverride, TextureSource};
use realist::texture::{Axis, UvGenerator, Wrap};

/// What side A's `slot` reads, in the settings.
fn slot_source(app: &ViewerApp, slot: Slot) -> Option<TextureSource> {
    match app.settings.slots.get(slot) {
        Some(SlotOverride::Source { source, .. }) => Some(source.clone()),
        _ => None,
    }
}

/// A latitude/longitude sphere of radius 1 without texture coordinates (nor normals), as
/// an OBJ file in `dir`.
fn sphere_without_uvs(dir: &Path) -> PathBuf {
    let (slices, stacks) = (32, 16);
    let mut obj = String::from("# a sphere without vt\n");
    obj += "v 0 1 0\n";
    for i in 1..stacks {
        let theta = std::f32::consts::PI * i as f32 / stacks as f32;
        for j in 0..slices {
            let phi = std::f32::consts::TAU * j as f32 / slices as f32;
            let (x, y, z) = (
                libm::sinf(theta) * libm::cosf(phi),
                libm::cosf(theta),
                libm::sinf(theta) * libm::sinf(phi),
            );
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    obj += "v 0 -1 0\n";
    let ring = |i: usize, j: usize| 2 + (i - 1) * slices + j % slices;
    let bottom = 2 + (stacks - 1) * slices;
    for j in 0..slices {
        obj += &format!("f 1 {} {}\n", ring(1, j + 1), ring(1, j));
        obj += &format!(
            "f {bottom} {} {}\n",
            ring(stacks - 1, j),
            ring(stacks - 1, j + 1)
        );
        for i in 1..stacks - 1 {
            obj += &format!(
                "f {} {} {} {}\n",
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j + 1),
                ring(i + 1, j)
            );
        }
    }
    let path = dir.join("sphere-without-uvs.obj");
    std::fs::write(&path, obj).expect("OBJ written");
    path
}

/// Luminance of an sRGB pixel, roughly.
fn luma(c: egui::Color32) -> f32 {
    0.3 * f32::from(c.r()) + 0.59 * f32::from(c.g()) + 0.11 * f32::from(c.b())
}

/// Along the middle row, where both frames show the model (differ from the background),
/// how often the ratio `now / before` crosses the middle of its range: a pattern that
/// multiplies the shading (a checker) crosses it at every square's edge, plain shading
/// never.
fn pattern_edges_on_middle_row(now: &ColorImage, before: &ColorImage) -> usize {
    let [w, h] = now.size;
    let y = h / 2;
    let background = before.pixels[y * w];
    let ratios: Vec<f32> = (0..w)
        .map(|x| (now.pixels[y * w + x], before.pixels[y * w + x]))
        .filter(|(n, b)| *b != background && luma(*b) > 20.0 && *n != background)
        .map(|(n, b)| luma(n) / luma(b))
        .collect();
    let (lo, hi) = ratios
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    if ratios.len() < 20 || hi - lo < 0.3 {
        return 0;
    }
    let mid = 0.5 * (lo + hi);
    ratios
        .windows(2)
        .filter(|p| (p[0] > mid) != (p[1] > mid))
        .count()
}

#[test]
fn a_procedural_base_colour_from_the_texture_lab_changes_the_frame() {
    let dir = temp_dir("lab-procedural");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    let plain = shown_image(&h);
    activate(&mut h, "texture lab");
    choose(&mut h, "base colour", "wood");
    let app = h.state();
    assert!(
        matches!(slot_source(app, Slot::BaseColor), Some(TextureSource::Procedural(p)) if p.source().name() == "wood"),
        "{:?}",
        app.settings.slots
    );
    assert_current_frame(app);
    assert_frame_changed(app, &plain, "wood as the base colour");
    let wood = shown_image(&h);
    choose(&mut h, "base colour", "checker");
    assert_frame_changed(h.state(), &wood, "the checker after the wood");
    // Back to the model's: the first frame again.
    choose(&mut h, "base colour", "the model's");
    assert!(h.state().settings.slots.is_empty());
    assert_eq!(differing(&shown_image(&h), &plain), 0);
}

#[test]
fn a_uv_map_makes_a_model_without_uvs_texturable_and_keeps_the_camera() {
    let dir = temp_dir("lab-uv-map");
    let sphere = sphere_without_uvs(&dir);
    let mut h = viewer(Some(sphere.clone()), &dir, 1);
    assert_eq!(h.state().scene.scene().meshes[0].uvs.len(), 0, "no UVs");
    // A slight orbit, so the camera is not just the framing a reload would give.
    let (rect, _) = viewport_of(&h);
    let c = rect.center();
    drag_through(
        &mut h,
        &[c, c + Vec2::new(30.0, 0.0), c + Vec2::new(40.0, 12.0)],
    );
    let plain = shown_image(&h);
    let nav = h.state().nav.clone();

    // A checker needs texture coordinates: without them, nothing changes.
    activate(&mut h, "texture lab");
    choose(&mut h, "base colour", "checker");
    assert!(slot_source(h.state(), Slot::BaseColor).is_some());
    assert_eq!(differing(&shown_image(&h), &plain), 0, "no UVs, no checker");

    // The spherical map: UV set 0 for the mesh, and the checker shows.
    choose(&mut h, "UV map", "spherical");
    let app = h.state();
    let spherical = UvGenerator::Spherical { axis: Axis::Y };
    assert_eq!((app.uv, app.shown_uv), (Some(spherical), Some(spherical)));
    assert_eq!(app.scene.scene().meshes[0].uvs.len(), 1, "set 0 added");
    assert!(
        app.scene
            .scene()
            .report
            .generated
            .iter()
            .any(|g| g.contains("spherical") && g.contains("the file has none")),
        "{:?}",
        app.scene.scene().report.generated
    );
    assert_current_frame(app);
    assert_frame_changed(app, &plain, "the checker on spherical UVs");
    let edges = pattern_edges_on_middle_row(&app.shown.as_ref().unwrap().a, &plain);
    assert!(edges >= 3, "the checker's squares along a row: {edges}");
    // What the user had stays: camera, file, settings.
    assert_eq!(app.nav, nav, "the camera stays");
    assert_eq!(app.model.as_deref(), Some(sphere.as_path()));
    assert!(slot_source(app, Slot::BaseColor).is_some());
    let notice = app.notice.clone().unwrap_or_default();
    assert!(notice.contains("the spherical map"), "{notice}");
    assert!(h.query_all_by_label_contains("the spherical map").count() >= 1);

    // Another map, then the file's own again (no UVs: the plain frame).
    let spherical_frame = shown_image(&h);
    choose(&mut h, "UV map", "planar:y");
    assert_eq!(h.state().uv, Some(UvGenerator::Planar { axis: Axis::Y }));
    assert_frame_changed(h.state(), &spherical_frame, "planar:y after spherical");
    choose(&mut h, "UV map", "mesh (the file's UVs)");
    let app = h.state();
    assert_eq!((app.uv, app.shown_uv), (None, None));
    assert_eq!(app.scene.scene().meshes[0].uvs.len(), 0);
    assert_eq!(differing(&shown_image(&h), &plain), 0);
    assert_eq!(app.nav, nav);

    // A reload keeps the map; a scene saved with it names it, and opens with it.
    choose(&mut h, "UV map", "box");
    let boxed = h.state().scene.scene().meshes[0].uvs.clone();
    h.key_press(Key::ArrowUp);
    h.run();
    let app = h.state();
    assert_eq!(app.uv, Some(UvGenerator::Box), "kept on reload");
    assert_eq!(app.shown_uv, Some(UvGenerator::Box));
    assert!(
        app.scene
            .scene()
            .report
            .generated
            .iter()
            .any(|g| g.contains("box")),
        "{:?}",
        app.scene.scene().report.generated
    );
    // (A reload frames the model anew, so the frame is not compared; the coordinates are.)
    assert_eq!(app.scene.scene().meshes[0].uvs, boxed, "the same box map");
    assert_current_frame(app);
    let saved = dir.join("boxed.toml");
    save_scene_to(&mut h, &saved);
    let text = std::fs::read_to_string(&saved).expect("saved");
    assert!(text.contains("uv = \"box\""), "{text}");
    let h2 = viewer(Some(saved), &temp_dir("lab-uv-map-reopen"), 1);
    assert_eq!(h2.state().uv, Some(UvGenerator::Box));
    assert_eq!(h2.state().scene.scene().meshes[0].uvs.len(), 1);
}

/// Types `path` into the image field of side A's `slot` and presses its load button.
fn load_slot_image(h: &mut App, slot: &str, path: &Path) {
    h.get_by_label(&format!("A {slot} image path"))
        .set_text_value_accesskit(path.to_str().expect("UTF-8 path"));
    h.run();
    activate(h, &format!("A {slot} image load"));
}

#[test]
fn a_missing_or_broken_image_file_shows_its_error_and_changes_nothing() {
    let dir = temp_dir("lab-image");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    activate(&mut h, "texture lab");
    choose(&mut h, "base colour", "marble");
    let before = shown_image(&h);
    let settings = h.state().settings.clone();
    let (scene, nav) = (Arc::clone(&h.state().scene), h.state().nav.clone());
    choose(&mut h, "base colour", "image file…");

    let missing = dir.join("no-such-image.png");
    let broken = dir.join("broken.png");
    std::fs::write(&broken, b"\x89PNG but not really").unwrap();
    for (file, name) in [(&missing, "no-such-image.png"), (&broken, "broken.png")] {
        load_slot_image(&mut h, "base colour", file);
        let app = h.state();
        let e = app
            .panel::<ShadingPanel>()
            .unwrap()
            .lab
            .errors
            .get(&(realist::viewer::panels::Side::A, Slot::BaseColor))
            .map(|e| e.message.clone())
            .expect("an error for the slot");
        assert!(
            e.starts_with(file.to_str().unwrap()) && e.contains(name) && !e.contains('\n'),
            "names the file, one line: {e}"
        );
        assert!(e.len() > file.to_str().unwrap().len() + 3, "says why: {e}");
        // Under the slot and in the status bar.
        assert_eq!(h.get_all_by_label(&e).count(), 2, "{e}");
        assert_eq!(app.settings, settings, "the marble stays");
        assert!(Arc::ptr_eq(&app.scene, &scene) && app.nav == nav);
        assert_current_frame(app);
        assert_eq!(
            differing(&shown_image(&h), &before),
            0,
            "the frame is unchanged"
        );
    }

    // A real image works through the same field (and the error goes).
    let red = dir.join("red.png");
    write_png(&red, [255, 0, 0]);
    load_slot_image(&mut h, "base colour", &red);
    let app = h.state();
    assert!(
        app.panel::<ShadingPanel>().unwrap().lab.errors.is_empty(),
        "{:?}",
        app.panel::<ShadingPanel>().unwrap().lab.errors
    );
    match slot_source(app, Slot::BaseColor) {
        Some(TextureSource::Image(t)) => {
            assert_eq!((t.width, t.height), (8, 6));
            assert!(t.name.ends_with("red.png"), "{}", t.name);
        }
        other => panic!("an image in the slot: {other:?}"),
    }
    assert_frame_changed(app, &before, "a red image after the marble");
    let reds = app.shown.as_ref().unwrap().a.pixels.iter();
    assert!(
        reds.filter(|c| c.r() > 40 && c.g() < 10 && c.b() < 10)
            .count()
            > 1000,
        "the torus is red"
    );
}

/// A slot's image takes a wrap mode from the texture lab: with the UVs scaled by 3 (so they
/// run past 1), clamp-to-edge and mirrored repeat each change the frame from the texture's
/// own repeat, and "the texture's" gives the first frame back.
#[test]
fn the_wrap_mode_of_a_slot_image_changes_the_frame_where_uvs_leave_the_image() {
    let dir = temp_dir("lab-wrap");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    activate(&mut h, "texture lab");
    choose(&mut h, "base colour", "image file…");
    // Red on the left half, blue on the right: every wrap mode reads it differently.
    let halves = dir.join("halves.png");
    image::RgbaImage::from_fn(8, 8, |x, _| {
        if x < 4 {
            image::Rgba([255, 0, 0, 255])
        } else {
            image::Rgba([0, 0, 255, 255])
        }
    })
    .save(&halves)
    .expect("PNG written");
    load_slot_image(&mut h, "base colour", &halves);
    if let Some(SlotOverride::Source { transform, .. }) =
        h.state_mut().settings.slots.get_mut(Slot::BaseColor)
    {
        transform.scale = glam::Vec2::splat(3.0);
    } else {
        panic!("an image in the base-colour slot");
    }
    h.run();
    let repeat = shown_image(&h);
    let mut seen = vec![repeat.clone()];
    for (entry, wrap) in [
        ("clamp to edge", Wrap::ClampToEdge),
        ("mirrored repeat", Wrap::MirroredRepeat),
    ] {
        choose(&mut h, "wrap", entry);
        let app = h.state();
        match app.settings.slots.get(Slot::BaseColor) {
            Some(SlotOverride::Source {
                sampler: Some(s), ..
            }) => assert_eq!((s.wrap_u, s.wrap_v), (wrap, wrap)),
            other => panic!("{entry}: a sampler in the slot: {other:?}"),
        }
        assert_current_frame(app);
        let now = shown_image(&h);
        for before in &seen {
            assert!(differing(&now, before) > 100, "{entry} changes the frame");
        }
        seen.push(now);
    }
    choose(&mut h, "wrap", "the texture's");
    assert!(matches!(
        h.state().settings.slots.get(Slot::BaseColor),
        Some(SlotOverride::Source { sampler: None, .. })
    ));
    assert_eq!(differing(&shown_image(&h), &repeat), 0);
}

/// The environment picker, rotation, intensity, background and exposure (issue 20): each
/// changes the pbr sphere grid's frame, and a file that is not an environment shows its
/// error while the scene and the lighting stay as they were.
#[test]
fn environment_rotation_exposure_and_a_bad_file() {
    let dir = temp_dir("image-lighting");
    let mut h = viewer(Some(model("pbr/sphere-grid.glb")), &dir, 1);
    activate(&mut h, "Environment, exposure, fog, tone map, shadows");
    assert_eq!(h.state().settings.environment, Environment::Auto);
    let studio = shown_image(&h);

    choose(&mut h, "environment", "sky");
    let sky = h
        .state()
        .settings
        .environment
        .view()
        .expect("an environment");
    assert_eq!(sky.env.name(), "sky");
    assert_frame_changed(h.state(), &studio, "studio -> sky");
    let lit = shown_image(&h);

    set_value(&mut h, "environment rotation", 200.0);
    let turned = h.state().settings.environment.view().unwrap();
    assert_eq!(turned.rotation_deg, 200.0);
    assert_eq!(turned.env.name(), "sky");
    assert_frame_changed(h.state(), &lit, "the sky turned");

    set_value(&mut h, "environment intensity", 2.0);
    assert_eq!(
        h.state().settings.environment.view().unwrap().intensity,
        2.0
    );
    let bright = shown_image(&h);
    set_value(&mut h, "exposure in stops", -1.0);
    assert_eq!(h.state().settings.exposure, -1.0);
    assert_frame_changed(h.state(), &bright, "one stop down");

    let plain = shown_image(&h);
    activate(&mut h, "shown behind the model");
    assert_eq!(h.state().settings.env_background, Some(0.0));
    assert_frame_changed(h.state(), &plain, "the sky behind the grid");

    // A bad file: one line naming it, in the section and the status bar; nothing changes.
    let before = h.state().settings.clone();
    let frame = shown_image(&h);
    let bad = dir.join("bad.hdr");
    std::fs::write(&bad, b"#?RADIANCE\nnot really\n").unwrap();
    h.state_mut()
        .with_panel(|p: &mut EnvironmentPanel, cx| p.read_environment(cx, &bad))
        .unwrap();
    h.run();
    let e = h
        .state()
        .panel::<EnvironmentPanel>()
        .unwrap()
        .env_error
        .clone()
        .expect("an error");
    assert!(
        e.starts_with(&bad.display().to_string()) && !e.contains('\n'),
        "{e}"
    );
    assert_eq!(h.get_all_by_label(&e).count(), 2, "{e}");
    assert_eq!(h.state().settings, before);
    assert_eq!(differing(&shown_image(&h), &frame), 0);

    // Rotation and intensity stay when the environment changes; none turns it off.
    choose(&mut h, "environment", "studio");
    let v = h.state().settings.environment.view().unwrap();
    assert_eq!(
        (v.env.name(), v.rotation_deg, v.intensity),
        ("studio", 200.0, 2.0)
    );
    assert!(h
        .state()
        .panel::<EnvironmentPanel>()
        .unwrap()
        .env_error
        .is_none());
    choose(&mut h, "environment", "none");
    assert_eq!(h.state().settings.environment, Environment::Off);
}

/// The probe on a `pbr` pixel (issue 20): the image-based diffuse and specular and the
/// BRDF terms per light are listed, and the probe's re-shaded colour is the renderer's.
#[test]
fn the_probe_lists_the_brdf_terms_of_a_pbr_pixel() {
    let dir = temp_dir("probe-pbr");
    // The file has no lights, and the glTF look lights it by the environment alone: the
    // rig, so that the probe has punctual lights' BRDF terms to list.
    // The frame compared in linear light, as the probe reports it: no tone map.
    let mut h = viewer_with(Some(model("pbr/sphere-grid.glb")), &dir, 1, |app| {
        app.settings.lights = Lights::Custom {
            lights: Light::default_rig(glam::Mat3::IDENTITY),
            follow_camera: true,
        };
        app.settings.tone = ToneMap::Clamp;
    });
    let (view, depth, rect, ppp) = {
        let app = h.state();
        let s = app.shown.as_ref().unwrap();
        (
            s.view.clone(),
            s.depth.clone(),
            app.viewport.rect,
            app.viewport.pixels_per_point,
        )
    };
    let w = view.width;
    let mut frame = Renderer::new();
    frame.render(&h.state().scene, &h.state().settings, &view);
    let frame = frame.target().expect("a frame");
    // The middle sphere's centre: the first drawn pixel right of the image centre.
    let y = view.height / 2;
    let x = (w / 2..w)
        .find(|&x| depth[(y * w + x) as usize] > 0.0)
        .expect("a sphere on the middle row");
    let x = x + 2;
    click_at(
        &mut h,
        rect.min + Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / ppp,
    );
    let probe = h
        .state()
        .shared
        .probe
        .clone()
        .unwrap()
        .probe
        .expect("a hit");
    let (diffuse, specular) = probe.image_based.expect("a pbr pixel");
    assert!(diffuse.max_element() > 0.0 && specular.max_element() > 0.0);
    assert!(probe.lights.iter().any(|l| l.d > 0.0 && l.vis > 0.0));
    let (c, _) = frame.pixel(x, y).expect("pixel");
    let c = c.truncate();
    assert!(
        (c - probe.color).abs().max_element() <= 0.02 * c.max_element().max(0.05),
        "renderer {c} vs probe {}",
        probe.color
    );
    h.get_by_label("image-based");
    h.get_by_label_contains("BRDF terms per light");
}

/// The posed world positions of `path` with `play` at time `t` (looping), as the command
/// line's renderer poses it.
fn posed(path: &Path, play: Play, t: f32) -> Vec<Vec<Vec3>> {
    let mut p = PreparedScene::new(load::load(path, &LoadOptions::default()).expect("loads"));
    p.pose_at(play, t, true);
    p.world_positions()
}

fn assert_pose(app: &ViewerApp, path: &Path, play: Play, t: f32, what: &str) {
    assert_eq!(app.timeline.play, play, "{what}: what plays");
    assert!(
        (app.timeline.time - t).abs() < 1e-5,
        "{what}: time {} not {t}",
        app.timeline.time
    );
    assert_eq!(
        app.scene.world_positions(),
        posed(path, play, t),
        "{what}: the pose on screen"
    );
}

fn set_clock(h: &mut App, seconds: f64) {
    h.state_mut().timeline.clock = Clock::Manual(seconds);
    h.run();
}

/// Playing an animation whose full frame is cheap (`skin8.glb`, a skinned bar, well under
/// 10 ms a frame) with the render thread a user has and the wall clock: every frame shown
/// during playback is at full resolution (playback is motion, and motion picks its
/// resolution from the frame time).
#[test]
fn an_animation_with_cheap_frames_plays_at_full_resolution_in_the_viewer() {
    let dir = temp_dir("playback");
    let options = ViewerOptions {
        model: Some(model("anim/skin8.glb")),
        synchronous: false,
        recent_file: Some(dir.join("recent.json")),
        threads: 2,
        ..ViewerOptions::default()
    };
    let mut h = viewer_from(options, 1, |_| {});
    // The file loads on a thread: wait for it (at most 20 s).
    let start = std::time::Instant::now();
    while h.state().scene.scene().animations.is_empty() && start.elapsed().as_secs() < 20 {
        std::thread::sleep(std::time::Duration::from_millis(10));
        h.step();
    }
    assert!(h.state().timeline.playing, "an animated file plays at once");
    let (mut levels, mut times, mut last_job) = (Vec::new(), Vec::new(), 0);
    let mut poses = std::collections::BTreeSet::new();
    let start = std::time::Instant::now();
    while start.elapsed().as_secs_f64() < 2.0 {
        std::thread::sleep(std::time::Duration::from_millis(8));
        h.step();
        let app = h.state();
        if let Some(s) = app.shown.as_ref().filter(|s| s.job != last_job) {
            last_job = s.job;
            levels.push(s.level);
            times.push(s.report_a.times.total);
            poses.insert(s.a.pixels.iter().map(|c| u64::from(c.r())).sum::<u64>());
        }
    }
    times.sort_by(f64::total_cmp);
    let median = times.get(times.len() / 2).copied().unwrap_or(f64::NAN);
    eprintln!(
        "{} frames in 2 s, median {median:.2} ms, {} distinct images; levels {levels:?}",
        levels.len(),
        poses.len()
    );
    assert!(
        median < 10.0,
        "the premise: a full frame costs under 10 ms ({median} ms)"
    );
    assert!(levels.len() >= 20, "{} frames in 2 s", levels.len());
    assert!(
        poses.len() >= 10,
        "the animation moves: {} distinct images",
        poses.len()
    );
    // Full resolution throughout, but for a frame right after one that a busy machine
    // slowed past the budget (the next is planned smaller, and the one after is full
    // again): at most one in ten, never two in a row.
    let full = realist::viewer::worker::Level::Full;
    let reduced = levels.iter().filter(|l| **l != full).count();
    assert!(
        reduced * 10 <= levels.len(),
        "{reduced} reduced: {levels:?}"
    );
    assert!(
        levels.windows(2).all(|w| w[0] == full || w[1] == full),
        "two reduced frames in a row: {levels:?}"
    );
}

#[test]
fn play_pause_scrub_speed_and_pick_an_animation() {
    let dir = temp_dir("timeline");
    let path = model("anim/samplers.glb");
    let n = load::load(&path, &LoadOptions::default())
        .unwrap()
        .animations
        .len();
    assert!(n > 2, "samplers.glb has {n} animations");
    let mut h = viewer_with(Some(path.clone()), &dir, 1, |app| {
        app.timeline.clock = Clock::Manual(0.0);
    });
    // An animated file plays at once, all its animations together.
    assert!(h.state().timeline.playing, "autoplay");
    h.get_by_label("Pause");
    assert_pose(h.state(), &path, Play::All, 0.0, "opened");
    assert_current_frame(h.state());
    let start = shown_image(&h);
    set_clock(&mut h, 0.5);
    assert_pose(h.state(), &path, Play::All, 0.5, "playing 0.5 s");
    assert_current_frame(h.state());
    let moved = differing(&shown_image(&h), &start);
    assert!(
        moved > 100,
        "half a second later only {moved} pixels changed"
    );

    // Paused, the clock moves on but the pose and the frame do not, and nothing repaints.
    h.get_by_label("Pause").click();
    h.run();
    assert!(!h.state().timeline.playing);
    h.get_by_label("Play");
    let (job, image) = (h.state().host.submitted(), shown_image(&h));
    set_clock(&mut h, 3.0);
    assert_pose(h.state(), &path, Play::All, 0.5, "paused");
    assert_eq!(h.state().host.submitted(), job, "no frame while paused");
    assert!(Arc::ptr_eq(&shown_image(&h), &image));
    assert!(
        !h.ctx.has_requested_repaint(),
        "a paused window does not repaint"
    );

    // Scrubbing moves the pose, paused or playing.
    h.get_by_role_and_label(Role::Slider, "time")
        .set_value_accesskit(0.25);
    h.run();
    assert_pose(h.state(), &path, Play::All, 0.25, "scrubbed");
    assert_current_frame(h.state());
    h.get_by_label("0.25 / 3.00 s");

    // Space plays from there, at the speed chosen; Space again pauses.
    choose(&mut h, "speed", "2x");
    h.key_press(Key::Space);
    h.run();
    assert!(h.state().timeline.playing, "Space plays");
    set_clock(&mut h, 3.1);
    assert_pose(h.state(), &path, Play::All, 0.45, "0.1 s at 2x");
    h.key_press(Key::Space);
    h.run();
    assert!(!h.state().timeline.playing, "Space pauses");

    // Picking one animation poses only it, at the same time.
    let name = {
        let scene = Arc::clone(h.state().scene.scene());
        format!("2: {}", scene.animations[2].name)
    };
    choose(&mut h, "animation", &name);
    assert_pose(h.state(), &path, Play::One(2), 0.45, "one animation");
    assert_ne!(
        posed(&path, Play::One(2), 0.45),
        posed(&path, Play::All, 0.45)
    );
    assert_current_frame(h.state());

    // A file that fails to load leaves the animated scene, its pose and its timeline.
    let glb = std::fs::read(&path).unwrap();
    let truncated = dir.join("truncated.glb");
    std::fs::write(&truncated, &glb[..glb.len() * 2 / 3]).unwrap();
    let scene = Arc::clone(&h.state().scene);
    drop_file(&mut h, &truncated);
    let e = h.state().error.clone().expect("an error is shown");
    assert!(e.starts_with(&truncated.display().to_string()), "{e}");
    assert!(Arc::ptr_eq(&h.state().scene, &scene), "the scene stays");
    assert_eq!(h.state().model.as_deref(), Some(path.as_path()));
    assert_pose(
        h.state(),
        &path,
        Play::One(2),
        0.45,
        "after the failed load",
    );
    // So does a compressed file whose meshopt stream fails to decode (its header byte
    // inverted).
    let torus = model("compressed/torus-meshopt-khr.glb");
    let stream = common::meshopt_range(&std::fs::read(&torus).unwrap(), 1);
    let undecodable = dir.join("undecodable-meshopt.glb");
    common::write_inverted_glb(&torus, stream.start..stream.start + 1, &undecodable);
    drop_file(&mut h, &undecodable);
    let e = h.state().error.clone().expect("an error is shown");
    assert!(e.starts_with(&undecodable.display().to_string()), "{e}");
    assert!(e.contains("bufferView 1"), "{e}");
    assert!(Arc::ptr_eq(&h.state().scene, &scene), "the scene stays");
    assert_eq!(h.state().model.as_deref(), Some(path.as_path()));
    h.key_press(Key::Space);
    h.run();
    set_clock(&mut h, 3.2);
    assert_pose(
        h.state(),
        &path,
        Play::One(2),
        0.65,
        "playing on after the failed loads",
    );

    // Opening a still model hides the timeline.
    drop_file(&mut h, &model("torus.obj"));
    assert!(h.query_by_label("Play").is_none() && h.query_by_label("Pause").is_none());
    assert!(!h.state().timeline.has_spare(), "no copy of a still scene");
}

#[test]
fn the_node_tree_lists_scenes_and_nodes_and_frames_a_node() {
    let dir = temp_dir("nodes");
    let path = model("anim/skin8.glb");
    let mut h = viewer_with(Some(path), &dir, 1, |app| app.timeline.autoplay = false);
    assert!(!h.state().timeline.playing, "opened paused");
    h.get_by_label("Play");
    // skin8.glb: the scene's roots are the skinned bar (node 9) and the armature (node 0)
    // holding the chain of joints 1..8.
    activate(&mut h, "Nodes (10)");
    // The drawn scene is open at first.
    h.get_by_label("scene 0 scene (2 roots, drawn)");
    activate(&mut h, "0: armature");
    h.get_by_label("1: joint-0");
    assert!(
        h.query_by_label("2: joint-1").is_none(),
        "joint-0 is closed"
    );
    activate(&mut h, "1: joint-0");
    h.get_by_label("2: joint-1");
    h.get_by_label("9: bar (1 primitives, skin 0)");
    let before = h.state().nav.clone();
    activate(&mut h, "frame");
    assert_ne!(h.state().nav, before, "framing moved the camera");
    assert_eq!(h.state().notice.as_deref(), Some("framed node 9: bar"));
    assert_current_frame(h.state());
}

/// The node tree and the instances list hide, isolate and show parts: `lit-stage.glb` is a
/// ball (node 1) over a floor (node 0).
#[test]
fn parts_are_hidden_isolated_and_shown_again_from_the_node_tree_and_the_instances() {
    use realist::render::Hidden;
    let dir = temp_dir("hide");
    let mut h = viewer(Some(model("lit-stage.glb")), &dir, 1);
    let before = shown_image(&h);
    activate(&mut h, "Nodes (6)");
    h.get_by_label("0: floor (1 primitives)");
    h.get_by_label("1: ball (1 primitives)");
    // Lights and the camera draw nothing: only the two mesh nodes have buttons.
    assert_eq!(h.get_all_by_label("hide").count(), 2);
    h.get_all_by_label("hide")
        .nth(1)
        .expect("the ball's")
        .click_accesskit();
    h.run();
    {
        let app = h.state();
        let mut want = Hidden::default();
        want.set(1, true);
        assert_eq!(app.settings.hidden, want);
        assert_eq!(app.split.b.hidden, want, "side B follows");
        assert_current_frame(app);
    }
    h.get_by_label("1: ball (1 primitives, hidden)");
    h.get_by_label("1 of 2 parts hidden");
    assert_frame_changed(h.state(), &before, "hiding the ball");
    let no_ball = shown_image(&h);
    // The hidden ball's button shows it again: the first frame, exactly.
    activate(&mut h, "show");
    assert!(h.state().settings.hidden.is_empty());
    assert_eq!(differing(&shown_image(&h), &before), 0);
    // Isolating the floor hides the ball: the same frame as hiding it.
    h.get_all_by_label("isolate")
        .next()
        .expect("the floor's")
        .click_accesskit();
    h.run();
    assert_eq!(h.state().settings.hidden, Hidden::all_but(2, [0]));
    assert_eq!(differing(&shown_image(&h), &no_ball), 0);
    assert_eq!(
        h.state().notice.as_deref(),
        Some("showing only node 0: floor")
    );
    activate(&mut h, "show all");
    assert!(h.state().settings.hidden.is_empty());
    assert!(h.query_by_label("show all").is_none());
    // The instances list: untick the ball.
    activate(&mut h, "Instances (2)");
    activate(&mut h, "1: ball (mesh 1, 960 triangles, Inherit)");
    assert!(h.state().settings.hidden.contains(1));
    assert_eq!(differing(&shown_image(&h), &no_ball), 0);
    // A saved scene keeps the hidden part, and opening it hides it again.
    let saved = dir.join("hidden.toml");
    save_scene_to(&mut h, &saved);
    let text = std::fs::read_to_string(&saved).expect("saved");
    assert!(text.contains("hidden = [1]"), "{text}");
    activate(&mut h, "show all");
    drop_file(&mut h, &saved);
    assert!(
        h.state().settings.hidden.contains(1),
        "the file's hidden part"
    );
    assert_eq!(h.state().split.b.hidden, h.state().settings.hidden);
    // Another file starts with every part shown.
    drop_file(&mut h, &model("torus.obj"));
    assert!(h.state().settings.hidden.is_empty());
}

/// A file with material variants (`models/pbr/variants.glb`) offers them in the scene panel:
/// choosing one changes the frame as the variant says, the file's default restores it, and
/// another file starts from its own default.
#[test]
fn a_material_variant_is_chosen_in_the_scene_panel() {
    let dir = temp_dir("variants");
    let mut h = viewer(Some(model("pbr/variants.glb")), &dir, 1);
    let before = shown_image(&h);
    choose(&mut h, "material variant", "blue");
    assert_eq!(h.state().settings.variant.as_deref(), Some("blue"));
    assert_current_frame(h.state());
    assert_frame_changed(h.state(), &before, "the blue variant");
    // The left sphere turned blue: more blue than green in the frame than before.
    let blueness = |img: &ColorImage| {
        img.pixels
            .iter()
            .map(|c| i64::from(c.b()) - i64::from(c.g()))
            .sum::<i64>()
    };
    assert!(blueness(&shown_image(&h)) > blueness(&before) + 1000);
    choose(&mut h, "material variant", "file's default");
    assert_eq!(h.state().settings.variant, None);
    assert_eq!(differing(&shown_image(&h), &before), 0);
    choose(&mut h, "material variant", "red");
    // A saved scene keeps the variant by name; opening it draws that variant again.
    let saved = dir.join("variant.toml");
    save_scene_to(&mut h, &saved);
    let text = std::fs::read_to_string(&saved).expect("saved");
    assert!(text.contains("material_variant = \"red\""), "{text}");
    choose(&mut h, "material variant", "file's default");
    drop_file(&mut h, &saved);
    assert_eq!(h.state().settings.variant.as_deref(), Some("red"));
    drop_file(&mut h, &model("torus.obj"));
    assert_eq!(
        h.state().settings.variant,
        None,
        "another file, its own look"
    );
    assert!(h.query_by_label("material variant").is_none());
}

/// A panel from outside the viewer crate, added with `Panels::add` and nothing else: it
/// counts what the dispatch tells it, edits a setting through its context and asks the
/// session for a notice.
#[derive(Default)]
struct Tally {
    passes: usize,
    polls: usize,
    actions: Vec<keys::Action>,
    installed: Vec<bool>,
}

impl Panel for Tally {
    fn dock(&self) -> Dock {
        Dock::Right
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        self.passes += 1;
        egui::CollapsingHeader::new("Tally")
            .default_open(true)
            .show(ui, |ui| {
                if ui.button("tally: wireframe on").clicked() {
                    cx.settings.wireframe_overlay = true;
                    cx.notice("tally turned the wireframe on");
                }
            });
    }

    fn poll(&mut self, _cx: &mut Cx<'_>) {
        self.polls += 1;
    }

    fn file_menu(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        if ui.button("Tally from the menu").clicked() {
            cx.notice("tally's menu entry");
            ui.close();
        }
    }

    fn act(&mut self, action: keys::Action, _cx: &mut Cx<'_>) {
        self.actions.push(action);
    }

    fn installed(&mut self, what: &Installed<'_>) {
        self.installed.push(what.fresh);
    }
}

#[test]
fn a_panel_added_to_the_list_is_laid_out_and_told_of_keys_scenes_and_its_menu() {
    let dir = temp_dir("added-panel");
    let mut h = viewer_with(None, &dir, 1, |app| app.panels.add(Box::<Tally>::default()));
    let tally = |h: &App| -> (usize, usize, Vec<keys::Action>, Vec<bool>) {
        let t = h.state().panel::<Tally>().expect("the added panel");
        (t.passes, t.polls, t.actions.clone(), t.installed.clone())
    };
    // Laid out in its dock every pass, polled every pass.
    h.get_by_label("Tally");
    let (passes, polls, _, _) = tally(&h);
    assert!(
        passes > 0 && polls >= passes,
        "{passes} passes, {polls} polls"
    );

    // Its button edits the settings through the context: the frame follows, and the
    // notice it asked for is in the status bar.
    let plain = shown_image(&h);
    h.get_by_label("tally: wireframe on").click();
    h.run();
    assert!(h.state().settings.wireframe_overlay);
    assert_frame_changed(h.state(), &plain, "the added panel's setting");
    h.get_by_label("tally turned the wireframe on");

    // Every key's action reaches it after the viewer's own.
    h.key_press_modifiers(Modifiers::NONE, Key::E);
    h.run();
    assert!(!h.state().settings.wireframe_overlay);
    assert_eq!(tally(&h).2, vec![keys::Action::ToggleWireOverlay]);

    // A new scene: told it is fresh.
    drop_file(&mut h, &model("torus.obj"));
    assert_eq!(tally(&h).3.last(), Some(&true));

    // Its File menu entry.
    h.get_by_label("File").click();
    h.run();
    h.get_by_label("Tally from the menu").click();
    h.run();
    h.get_by_label("tally's menu entry");
}

/// The PNG files in `dir`, sorted.
fn pngs(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    v.sort();
    v
}

#[test]
fn f12_saves_the_frame_on_screen_and_the_screenshot_window_renders_its_own_size() {
    let dir = temp_dir("screenshot");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    let shots = dir.join("shots");
    std::fs::create_dir_all(&shots).unwrap();
    h.state_mut()
        .panels
        .get_mut::<ScreenshotPanel>()
        .unwrap()
        .folder = shots.display().to_string();

    // F12: the frame on screen, as it is, at its size.
    h.key_press(Key::F12);
    h.run();
    let notice = h.state().notice.clone().unwrap_or_default();
    assert!(notice.starts_with("saved "), "{notice}");
    let files = pngs(&shots);
    assert_eq!(files.len(), 1, "{files:?}");
    let saved = image::open(&files[0]).unwrap().to_rgba8();
    let shown = shown_image(&h);
    assert_eq!(
        [saved.width() as usize, saved.height() as usize],
        shown.size
    );
    let same = saved
        .pixels()
        .zip(shown.pixels.iter())
        .all(|(a, b)| a.0 == [b.r(), b.g(), b.b(), 255]);
    assert!(same, "the file holds the frame on screen");

    // File > Screenshot...: the window renders the view at the size asked for.
    h.get_by_label("File").click();
    h.run();
    h.get_by_label("Screenshot...  (F12 saves at once)").click();
    h.run();
    {
        let p = h.state_mut().panels.get_mut::<ScreenshotPanel>().unwrap();
        assert!(p.open, "the menu entry opens the window");
        (p.width, p.height, p.samples) = (64, 48, 1);
    }
    h.run();
    h.get_by_label("render and save").click();
    // Rendered on a thread of its own: look until its file is there.
    for _ in 0..2000 {
        h.run();
        if pngs(&shots).len() == 2 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let files = pngs(&shots);
    assert_eq!(files.len(), 2, "{files:?}");
    let big = files
        .iter()
        .map(|f| image::open(f).unwrap())
        .find(|i| i.width() == 64)
        .expect("a 64x48 render");
    assert_eq!(big.height(), 48);
}

#[test]
fn a_text_file_named_obj_is_an_error_and_the_scene_and_recent_list_stay() {
    let dir = temp_dir("text-as-obj");
    let mut h = viewer(Some(model("torus.obj")), &dir, 1);
    assert_torus_open(&h, &dir);
    let (scene, frame, recent) = {
        let app = h.state();
        let s = app.shown.as_ref().unwrap();
        (Arc::clone(&app.scene), Arc::clone(&s.a), recent_list(&dir))
    };
    let notes = dir.join("notes.obj");
    std::fs::write(&notes, "Shopping list\nmilk\nbread\n").unwrap();
    drop_file(&mut h, &notes);
    let app = h.state();
    let e = app.error.clone().expect("an error");
    assert!(
        e.starts_with(&notes.display().to_string())
            && e.contains("nothing to draw")
            && !e.contains('\n'),
        "{e}"
    );
    h.get_by_label(&e);
    assert!(Arc::ptr_eq(&app.scene, &scene), "the scene stays");
    assert_eq!(app.model.as_deref(), Some(model("torus.obj").as_path()));
    assert_eq!(recent_list(&dir), recent, "not in Recent");
    assert_eq!(differing(&shown_image(&h), &frame), 0, "the frame stays");
}

// Measurement and section planes (issue 36).

/// A cube of side 2 centred at the origin, as an OBJ.
const CUBE: &str =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

/// The cube's corners.
fn cube_corners() -> Vec<Vec3> {
    (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            )
        })
        .collect()
}

/// Where world point `p` shows on the screen, moved `inward` points towards where the
/// origin shows (so a click on a silhouette corner lands on the model).
fn on_screen(h: &App, p: Vec3, inward: f32) -> Pos2 {
    let app = h.state();
    let s = app.shown.as_ref().expect("a frame");
    let proj = Projector::new(&s.view, app.viewport.rect);
    let (at, centre) = (proj.point(p).unwrap(), proj.point(Vec3::ZERO).unwrap());
    at + (centre - at).normalized() * inward
}

#[test]
fn measure_distances_and_an_angle_on_a_cube_with_snapping() {
    use realist::render::measure::Snap;
    let dir = temp_dir("measure");
    std::fs::write(dir.join("cube.obj"), CUBE).unwrap();
    let mut h = viewer(Some(dir.join("cube.obj")), &dir, 1);
    activate(&mut h, "Measure");
    activate(&mut h, "pick points with a click");
    assert!(h.state().shared.measure.on);
    // The corner nearest the eye and two of its neighbours (all three in view).
    let eye = h.state().shown.as_ref().unwrap().view.camera.eye;
    let corners = cube_corners();
    let near = *corners
        .iter()
        .min_by(|a, b| a.distance(eye).total_cmp(&b.distance(eye)))
        .unwrap();
    let n1 = near - Vec3::new(2.0 * near.x.signum(), 0.0, 0.0);
    let n2 = near - Vec3::new(0.0, 0.0, 2.0 * near.z.signum());
    for p in [n1, near, n2] {
        // Four points off the corner: the click snaps to it.
        let at = on_screen(&h, p, 4.0);
        click_at(&mut h, at);
    }
    let app = h.state();
    let m = &app.shared.measure;
    assert!(app.shared.probe.is_none(), "measuring does not probe");
    assert_eq!(m.points.len(), 3);
    for (p, want) in m.points.iter().zip([n1, near, n2]) {
        assert_eq!(p.snap, Snap::Vertex, "{p:?}");
        assert_eq!(p.position, want);
    }
    assert_eq!(m.distances(), vec![2.0, 2.0]);
    assert!((m.angle().unwrap() - 90.0).abs() < 1e-9, "{:?}", m.angle());
    let text = m.text(h.state().scene.bounds());
    assert!(
        text.contains("AB = 2\n")
            && text.contains("BC = 2\n")
            && text.contains("angle ABC = 90°")
            && text.contains("bounding box 2 x 2 x 2, diagonal 3.4641"),
        "{text}"
    );
    // A fourth click starts again: near the middle of an edge it snaps onto the edge.
    let mid = (near + n1) * 0.5;
    let at = on_screen(&h, mid, 3.0);
    click_at(&mut h, at);
    let m = &h.state().shared.measure;
    assert_eq!(m.points.len(), 1);
    let p = m.points[0];
    assert_eq!(p.snap, Snap::Edge, "{p:?}");
    // On the edge from near to n1: its other two coordinates are the corner's.
    assert!(
        (p.position.y - near.y).abs() < 1e-4 && (p.position.z - near.z).abs() < 1e-4,
        "{p:?}"
    );
    assert!((p.position.x - mid.x).abs() < 0.1, "{p:?}");
    // Far from any edge (the middle of a face, as drawn): the surface point.
    let face = Vec3::new(0.4 * near.x, near.y, 0.0);
    let at = on_screen(&h, face, 0.0);
    click_at(&mut h, at);
    let p = h.state().shared.measure.points[1];
    assert_eq!(p.snap, Snap::Surface, "{p:?}");
    assert!(
        (p.position.y - near.y).abs() < 1e-4,
        "on the top or bottom face: {p:?}"
    );
    // Measuring off: a click probes again.
    activate(&mut h, "pick points with a click");
    let at = on_screen(&h, face, 0.0);
    click_at(&mut h, at);
    assert!(h.state().shared.probe.is_some());
    assert_eq!(h.state().shared.measure.points.len(), 2, "kept");
}

#[test]
fn a_section_plane_from_the_panel_cuts_the_view_and_follows_the_split() {
    let dir = temp_dir("section");
    std::fs::write(dir.join("cube.obj"), CUBE).unwrap();
    let mut h = viewer(Some(dir.join("cube.obj")), &dir, 1);
    let before = shown_image(&h);
    activate(&mut h, "Section planes");
    activate(&mut h, "add a plane");
    {
        let app = h.state();
        assert_eq!(
            app.settings.sections.planes,
            vec![glam::Vec4::new(1.0, 0.0, 0.0, 0.0)]
        );
        assert_eq!(
            app.split.b.sections, app.settings.sections,
            "side B follows"
        );
        assert_current_frame(app);
    }
    assert_frame_changed(h.state(), &before, "a plane through the middle");
    // Keep the half away from the eye, so the cut faces it: the cap colour shows where the
    // cube's inside is seen.
    if h.state().shown.as_ref().unwrap().view.camera.eye.x > 0.0 {
        activate(&mut h, "flip");
        let planes = &h.state().settings.sections.planes;
        assert_eq!(planes, &vec![glam::Vec4::new(-1.0, 0.0, 0.0, 0.0)]);
    }
    let cap = realist::render::Sections::CAP;
    let enc = realist::color::srgb8;
    let want = [enc(cap.x), enc(cap.y), enc(cap.z)];
    let img = shown_image(&h);
    let caps = img
        .pixels
        .iter()
        .filter(|c| [c.r(), c.g(), c.b()] == want)
        .count();
    assert!(caps > 500, "{caps} cap pixels");
    // The plane's handle in the view: dragging it 40 points along the arrow moves the
    // plane along its normal by 40 points' worth, and does not orbit the camera.
    let (handle, nav, d0, cut) = {
        let app = h.state();
        let s = app.shown.as_ref().expect("a frame");
        let hs = realist::viewer::viewport::handles(
            &app.settings,
            &app.scene,
            &s.view,
            app.viewport.rect,
        );
        assert_eq!(hs.len(), 1, "one handle");
        (
            hs[0],
            app.nav.clone(),
            app.settings.sections.planes[0].w,
            Arc::clone(&s.a),
        )
    };
    let dir = handle.along.normalized();
    let points: Vec<Pos2> = (0..=8)
        .map(|k| handle.at + dir * (5.0 * k as f32))
        .collect();
    drag_through(&mut h, &points);
    {
        let app = h.state();
        let moved = app.settings.sections.planes[0].w - d0;
        let want = -40.0 / handle.along.length();
        assert!(
            (moved - want).abs() < 0.1 * want.abs(),
            "the plane moved {moved}, not {want}"
        );
        assert_eq!(app.nav, nav, "dragging the handle does not move the camera");
        assert_eq!(
            app.split.b.sections, app.settings.sections,
            "side B follows"
        );
        assert_current_frame(app);
    }
    assert_frame_changed(h.state(), &cut, "the plane moved");
    // Removing it restores the first frame.
    activate(&mut h, "remove plane");
    assert!(h.state().settings.sections.is_empty());
    assert_eq!(differing(&shown_image(&h), &before), 0);
}

#[test]
fn keys_toggle_measuring_the_axes_and_full_screen() {
    let dir = temp_dir("keys-measure");
    let mut h = viewer(None, &dir, 1);
    assert!(h.state().shared.axes, "the axes are shown by default");
    let before = shown_image(&h);
    for (key, what) in [
        (Key::D, "measure"),
        (Key::X, "axes"),
        (Key::F11, "full screen"),
    ] {
        h.key_press(key);
        h.run();
        let s = &h.state().shared;
        let on = match what {
            "measure" => s.measure.on,
            "axes" => !s.axes,
            _ => s.fullscreen,
        };
        assert!(on, "{what} toggled");
    }
    assert!(
        h.state().fullscreen_sent,
        "the window was asked to fill the screen"
    );
    // The axes are drawn over the frame, not into it.
    assert_eq!(differing(&shown_image(&h), &before), 0);
    h.key_press(Key::F11);
    h.run();
    assert!(!h.state().shared.fullscreen && !h.state().fullscreen_sent);
}

#[test]
fn the_file_pickers_icons_are_in_the_fonts() {
    // egui_file (the File > Open picker) marks each folder and file with 🗀 and 🗋 and its
    // titles with 📁, 📂 and 💾: all must have glyphs in the viewer's fonts (they showed as
    // empty boxes before egui's monochrome emoji fonts were turned on).
    let dir = temp_dir("picker-icons");
    let h = viewer(None, &dir, 1);
    let font = egui::FontId::proportional(14.0);
    for c in ['🗀', '🗋', '📁', '📂', '💾'] {
        assert!(
            h.ctx.fonts_mut(|f| f.has_glyph(&font, c)),
            "{c} (U+{:04X}) has no glyph",
            u32::from(c)
        );
    }
}

#[test]
fn an_instanced_model_shows_its_copies_and_draws_them() {
    // EXT_mesh_gpu_instancing (issue 37): one instance of one mesh, twelve copies drawn.
    let dir = temp_dir("instanced");
    let h = viewer(Some(model("pbr/instanced.glb")), &dir, 1);
    assert_current_frame(h.state());
    let found = h
        .query_all_by(|n| {
            text_of(n).is_some_and(|l| l.contains("1 instances (12 copies drawn), 144 triangles"))
        })
        .count();
    assert!(found > 0, "the scene summary names the copies");
    let img = shown_image(&h);
    let bg = img.pixels[0];
    let drawn = img.pixels.iter().filter(|p| **p != bg).count();
    assert!(drawn > 2000, "{drawn} pixels of boxes");
}
