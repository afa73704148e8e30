//! The interactive viewer (feature `viewer`): an egui/eframe window around the CPU renderer.
//! The renderer draws every pixel; egui shows the frame as a texture and hosts the panels.
//!
//! | module | owns |
//! |---|---|
//! | [`app`] | [`ViewerApp`]: the session (scene, render worker, loads, files) and the UI pass ([`ViewerApp::ui_contents`]) that eframe and the UI tests both drive; it lends the panels a [`panels::Cx`] and carries out the [`panels::Command`]s they queue |
//! | [`worker`] | the render thread: coalesced jobs, abandoned stale frames, progressive quality |
//! | [`loader`] | loading and preparing a model or a scene file off the UI thread, with progress and cancel |
//! | [`viewport`] | the image, mouse navigation, picking, the probe click, overlays (tile grid and cost, split divider) |
//! | [`keys`] | the key bindings table behind both the dispatcher and the cheat sheet, and what each action does (one exhaustive match) |
//! | [`panels`] | the [`panels::Panel`] trait and the panel list: shading and split view (with the texture lab), lights, environment / fog / tone map / shadows / ground, materials, stats, probe, scene file, scene, colour, screenshot; the menu and status bars |
//! | [`gizmos`] | each light's position and cone drawn over the view |
//! | [`slide`] | reading a rectangular spotlight's projected image off the UI thread |
//! | [`lab`] | the texture lab's work off the UI thread: a slot's image file read, a model's UVs generated |
//! | [`navigate`] | the camera controller (turntable / trackball, pan, dolly to cursor, framing, named views) |
//! | [`files`] | recent files, previous / next model in a folder, reload on change |
//! | [`timeline`] | animation playback: play / pause, scrub, speed, loop, which animation; posing a spare copy of the scene while the render thread draws |
//!
//! Repaints happen only on input, on a finished frame (the worker asks for one) and while a
//! load shows its progress, and while an animation plays: an idle or paused window uses no
//! CPU.

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_color as color;
use realist_geom as geom;
use realist_load as load;
use realist_mesh as mesh;
use realist_overlay as overlay;
use realist_quality as quality;
use realist_raster as raster;
use realist_render as render;
use realist_scene as scene;
use realist_scenefile as scenefile;
use realist_shade as shade;
use realist_texture as texture;

pub mod app;
pub mod files;
pub mod gizmos;
pub mod keys;
pub mod lab;
pub mod loader;
pub mod navigate;
pub mod panels;
pub mod same;
pub mod slide;
pub mod timeline;
pub mod viewport;
pub mod worker;

pub use app::{ViewerApp, ViewerOptions};

/// Whether a display server is announced (`DISPLAY` or `WAYLAND_DISPLAY`); the window may
/// still fail to open, which [`run`] reports.
#[must_use]
pub fn display_available() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

static LAUNCH: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();

/// Records the moment the process started (call first thing in `main`), for the time from
/// launch to the first frame.
pub fn mark_launch() {
    LAUNCH.get_or_init(std::time::Instant::now);
}

/// Milliseconds since [`mark_launch`] (or since the first call of this function).
#[must_use]
pub fn since_launch_ms() -> f64 {
    LAUNCH
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
        * 1e3
}

/// Opens the viewer window as `opts` asks (a model or a scene file, else the built-in demo;
/// side panels hidden; animations paused), with an inner size of `window` points, and runs
/// until it is closed.
///
/// # Errors
/// If the window cannot be created (no display, no OpenGL).
pub fn run(opts: ViewerOptions, window: (u32, u32)) -> Result<(), String> {
    let options = eframe::NativeOptions {
        viewport: eframe::egui::ViewportBuilder::default()
            .with_title("realist")
            .with_inner_size([window.0 as f32, window.1 as f32])
            .with_min_inner_size([480.0, 320.0])
            .with_drag_and_drop(true),
        // The renderer already shows what it has; vsync would only add latency.
        glow_options: eframe::egui_glow::GlowConfiguration {
            vsync: false,
            ..Default::default()
        },
        ..eframe::NativeOptions::default()
    };
    eframe::run_native(
        "realist",
        options,
        Box::new(move |cc| {
            let ctx = cc.egui_ctx.clone();
            let repaint = std::sync::Arc::new(move || ctx.request_repaint());
            let app = ViewerApp::new(opts, repaint)
                .map_err(|e| -> Box<dyn std::error::Error + Send + Sync> { e.into() })?;
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| e.to_string())
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut eframe::egui::Ui, _frame: &mut eframe::Frame) {
        self.ui_contents(ui);
    }

    fn on_exit(&mut self, _gl: Option<&eframe::glow::Context>) {
        self.save_state();
    }
}
