//! Key and mouse bindings, in the spirit of f3d, as one table, and what each action does
//! ([`act`], one exhaustive match): the dispatcher and the `H` cheat sheet both read the
//! table, so the sheet lists every binding there is with the state of each toggle.

use eframe::egui::{self, Color32, Key, Modifiers};

use crate::navigate::{Mode, UpAxis, View as Named};
use crate::panels::{Command, CostView, Cx};
use crate::render::Output;
use crate::shade::Shading;

/// Something a key does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    ViewFront,
    ViewBack,
    ViewRight,
    ViewLeft,
    ViewTop,
    ViewBottom,
    ViewIso,
    ToggleOrtho,
    Reset,
    FrameAll,
    UpY,
    UpZ,
    ToggleTrackball,
    FovDown,
    FovUp,
    NextShading,
    PrevShading,
    ToggleWireOverlay,
    ToggleOverdraw,
    ToggleTileGrid,
    CycleTileCost,
    CycleAntialias,
    ToggleMultisampling,
    ToggleSplit,
    ToggleLightGizmos,
    ToggleAxes,
    ToggleMeasure,
    ToggleFullscreen,
    CheatSheet,
    Screenshot,
    Open,
    PrevFile,
    NextFile,
    Reload,
    TogglePanels,
    TogglePlay,
}

/// One key binding.
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    pub key: Key,
    /// Ctrl (Cmd on macOS) held.
    pub command: bool,
    pub shift: bool,
    pub action: Action,
    pub what: &'static str,
}

const fn bind(key: Key, action: Action, what: &'static str) -> Binding {
    Binding {
        key,
        command: false,
        shift: false,
        action,
        what,
    }
}

const fn ctrl(key: Key, action: Action, what: &'static str) -> Binding {
    Binding {
        key,
        command: true,
        shift: false,
        action,
        what,
    }
}

const fn shift(key: Key, action: Action, what: &'static str) -> Binding {
    Binding {
        key,
        command: false,
        shift: true,
        action,
        what,
    }
}

/// Every key binding (checked in this order: modified bindings come first).
pub const BINDINGS: &[Binding] = &[
    ctrl(Key::Num1, Action::ViewBack, "back view"),
    ctrl(Key::Num3, Action::ViewLeft, "left view"),
    ctrl(Key::Num7, Action::ViewBottom, "bottom view"),
    ctrl(Key::Y, Action::UpY, "+Y is up"),
    ctrl(Key::Z, Action::UpZ, "+Z is up (scans, CAD)"),
    ctrl(Key::O, Action::Open, "open a model"),
    shift(Key::M, Action::PrevShading, "previous shading mode"),
    bind(Key::Num1, Action::ViewFront, "front view"),
    bind(Key::Num3, Action::ViewRight, "right view"),
    bind(Key::Num7, Action::ViewTop, "top view"),
    bind(Key::Num9, Action::ViewIso, "isometric view"),
    bind(Key::Num5, Action::ToggleOrtho, "orthographic / perspective"),
    bind(Key::Enter, Action::Reset, "reset the camera"),
    bind(Key::F, Action::FrameAll, "frame the whole scene"),
    bind(Key::T, Action::ToggleTrackball, "trackball / turntable"),
    bind(
        Key::OpenBracket,
        Action::FovDown,
        "field of view -5 degrees",
    ),
    bind(Key::CloseBracket, Action::FovUp, "field of view +5 degrees"),
    bind(Key::M, Action::NextShading, "next shading mode"),
    bind(Key::E, Action::ToggleWireOverlay, "wireframe over shaded"),
    bind(Key::O, Action::ToggleOverdraw, "overdraw view"),
    bind(Key::G, Action::ToggleTileGrid, "64x64 tile grid"),
    bind(
        Key::K,
        Action::CycleTileCost,
        "tile cost: off / time / fragments",
    ),
    bind(
        Key::A,
        Action::CycleAntialias,
        "anti-aliasing when still: 1 / 2x2 / 4x4",
    ),
    shift(
        Key::A,
        Action::ToggleMultisampling,
        "multisampling: off / 4x (shaded once per pixel)",
    ),
    bind(Key::S, Action::ToggleSplit, "split view A | B"),
    bind(
        Key::L,
        Action::ToggleLightGizmos,
        "lights and their cones in the view",
    ),
    bind(Key::X, Action::ToggleAxes, "axes in the corner of the view"),
    bind(
        Key::D,
        Action::ToggleMeasure,
        "measure: clicks pick points for distances and angles",
    ),
    bind(Key::F11, Action::ToggleFullscreen, "full screen"),
    bind(Key::H, Action::CheatSheet, "this cheat sheet"),
    bind(Key::F12, Action::Screenshot, "screenshot to PNG"),
    bind(
        Key::ArrowLeft,
        Action::PrevFile,
        "previous model in the folder",
    ),
    bind(
        Key::ArrowRight,
        Action::NextFile,
        "next model in the folder",
    ),
    bind(Key::ArrowUp, Action::Reload, "reload the model"),
    bind(Key::Tab, Action::TogglePanels, "hide / show the panels"),
    bind(Key::Space, Action::TogglePlay, "play / pause the animation"),
];

/// Mouse bindings, for the cheat sheet.
pub const MOUSE: &[(&str, &str)] = &[
    (
        "left drag",
        "orbit (turntable about the up axis, or trackball)",
    ),
    ("shift + left drag, middle drag", "pan"),
    ("right drag", "dolly"),
    ("wheel", "dolly towards the cursor"),
    ("ctrl + wheel", "dolly towards the centre"),
    ("click", "probe the pixel (with D: pick a point to measure)"),
    (
        "double-click, middle click",
        "orbit about the point under the cursor",
    ),
    ("drag the split divider", "move the A | B boundary"),
    ("drop a file", "open it"),
];

/// The action of a key press with these modifiers, if any.
#[must_use]
pub fn action_for(key: Key, mods: Modifiers) -> Option<Action> {
    BINDINGS
        .iter()
        .find(|b| b.key == key && b.command == mods.command && b.shift == mods.shift && !mods.alt)
        .map(|b| b.action)
}

/// How a binding is written on the cheat sheet ("Ctrl+Y").
#[must_use]
pub fn describe(b: &Binding) -> String {
    let mut s = String::new();
    if b.command {
        s.push_str("Ctrl+");
    }
    if b.shift {
        s.push_str("Shift+");
    }
    // Names, not symbols: the arrows' symbols are not in egui's monospace font.
    s.push_str(match b.key {
        Key::OpenBracket => "[",
        Key::CloseBracket => "]",
        k => k.name(),
    });
    s
}

/// Shading modes in the order the `M` key cycles them.
const CYCLE: [Shading; Shading::ALL.len()] = Shading::ALL;

/// Does what a key or menu entry asks, as far as the camera, the settings, the shared
/// toggles and the session go; the actions a panel owns (`Screenshot` for the screenshot
/// window, `Open` for the file picker) are its own ([`crate::panels::Panels::act`]).
pub fn act(a: Action, cx: &mut Cx<'_>) {
    let aspect = cx.viewport.aspect();
    let nav = &mut *cx.nav;
    match a {
        Action::ViewFront => nav.set_view(Named::Front),
        Action::ViewBack => nav.set_view(Named::Back),
        Action::ViewRight => nav.set_view(Named::Right),
        Action::ViewLeft => nav.set_view(Named::Left),
        Action::ViewTop => nav.set_view(Named::Top),
        Action::ViewBottom => nav.set_view(Named::Bottom),
        Action::ViewIso => nav.set_view(Named::Isometric),
        Action::ToggleOrtho => nav.toggle_ortho(),
        Action::Reset => nav.reset(),
        Action::FrameAll => {
            let (c, r) = cx.session.scene.bounding_sphere();
            nav.frame(c, r, aspect);
        }
        Action::UpY => nav.set_up_axis(UpAxis::Y, aspect),
        Action::UpZ => nav.set_up_axis(UpAxis::Z, aspect),
        Action::ToggleTrackball => nav.set_mode(match nav.mode() {
            Mode::Turntable => Mode::Trackball,
            Mode::Trackball => Mode::Turntable,
        }),
        Action::FovDown => nav.set_fov_degrees(nav.fov_degrees() - 5.0),
        Action::FovUp => nav.set_fov_degrees(nav.fov_degrees() + 5.0),
        Action::NextShading | Action::PrevShading => {
            let s = &mut *cx.settings;
            let k = s
                .shading
                .and_then(|m| CYCLE.iter().position(|c| *c == m))
                .unwrap_or(3);
            let n = CYCLE.len();
            let next = if a == Action::NextShading {
                (k + 1) % n
            } else {
                (k + n - 1) % n
            };
            s.shading = Some(CYCLE[next]);
        }
        Action::ToggleWireOverlay => {
            cx.settings.wireframe_overlay = !cx.settings.wireframe_overlay;
        }
        Action::ToggleOverdraw => {
            let s = &mut *cx.settings;
            s.output = match s.output {
                Output::Shaded => Output::Overdraw,
                Output::Overdraw => Output::Shaded,
            }
        }
        Action::ToggleTileGrid => cx.shared.tile_grid = !cx.shared.tile_grid,
        Action::CycleTileCost => {
            cx.shared.tile_cost = match cx.shared.tile_cost {
                CostView::Off => CostView::Time,
                CostView::Time => CostView::Fragments,
                CostView::Fragments => CostView::Off,
            }
        }
        Action::CycleAntialias => {
            *cx.max_samples = match *cx.max_samples {
                1 => 2,
                2 => 4,
                _ => 1,
            }
        }
        Action::ToggleMultisampling => {
            cx.settings.msaa = if cx.settings.msaa > 1 { 1 } else { 4 };
        }
        Action::ToggleSplit => cx.split.set_enabled(!cx.split.enabled, cx.settings),
        Action::ToggleLightGizmos => cx.shared.light_gizmos = !cx.shared.light_gizmos,
        Action::ToggleAxes => cx.shared.axes = !cx.shared.axes,
        Action::ToggleMeasure => cx.shared.measure.on = !cx.shared.measure.on,
        Action::ToggleFullscreen => cx.shared.fullscreen = !cx.shared.fullscreen,
        Action::CheatSheet => cx.shared.cheat_sheet = !cx.shared.cheat_sheet,
        Action::PrevFile => cx.ask(Command::StepFile(-1)),
        Action::NextFile => cx.ask(Command::StepFile(1)),
        Action::Reload => cx.ask(Command::Reload),
        Action::TogglePanels => cx.shared.panels_visible = !cx.shared.panels_visible,
        Action::TogglePlay => cx.ask(Command::TogglePlay),
        // A panel's: the screenshot window saves the frame, the panels open the picker.
        Action::Screenshot | Action::Open => {}
    }
}

/// The `H` cheat sheet: every binding with the current state of each toggle.
pub fn cheat_sheet(ui: &mut egui::Ui, cx: &Cx<'_>) {
    let on = |b: bool| if b { "on" } else { "off" };
    let state = |a: Action| -> String {
        match a {
            Action::ToggleOrtho => (if cx.nav.is_ortho() {
                "orthographic"
            } else {
                "perspective"
            })
            .into(),
            Action::UpY | Action::UpZ => format!("up: {:?}", cx.nav.up_axis()),
            Action::ToggleTrackball => format!("{:?}", cx.nav.mode()).to_lowercase(),
            Action::FovDown | Action::FovUp => format!("{:.0} degrees", cx.nav.fov_degrees()),
            Action::NextShading | Action::PrevShading => crate::panels::describe(cx.settings),
            Action::ToggleWireOverlay => on(cx.settings.wireframe_overlay).into(),
            Action::ToggleOverdraw => on(cx.settings.output == Output::Overdraw).into(),
            Action::ToggleTileGrid => on(cx.shared.tile_grid).into(),
            Action::CycleTileCost => format!("{:?}", cx.shared.tile_cost).to_lowercase(),
            Action::CycleAntialias => format!("up to {0}x{0}", *cx.max_samples),
            Action::ToggleMultisampling => format!("{}x", cx.settings.msaa),
            Action::ToggleSplit => on(cx.split.enabled).into(),
            Action::ToggleLightGizmos => on(cx.shared.light_gizmos).into(),
            Action::ToggleAxes => on(cx.shared.axes).into(),
            Action::ToggleMeasure => on(cx.shared.measure.on).into(),
            Action::ToggleFullscreen => on(cx.shared.fullscreen).into(),
            Action::TogglePanels => on(cx.shared.panels_visible).into(),
            Action::TogglePlay => on(cx.session.playing).into(),
            Action::CheatSheet => on(cx.shared.cheat_sheet).into(),
            // One-shot actions: nothing to show.
            Action::ViewFront
            | Action::ViewBack
            | Action::ViewRight
            | Action::ViewLeft
            | Action::ViewTop
            | Action::ViewBottom
            | Action::ViewIso
            | Action::Reset
            | Action::FrameAll
            | Action::Screenshot
            | Action::Open
            | Action::PrevFile
            | Action::NextFile
            | Action::Reload => String::new(),
        }
    };
    egui::Grid::new("keys").striped(true).show(ui, |ui| {
        for b in BINDINGS {
            ui.monospace(describe(b));
            ui.label(b.what);
            ui.label(egui::RichText::new(state(b.action)).color(Color32::from_rgb(120, 200, 255)));
            ui.end_row();
        }
        for (m, what) in MOUSE {
            ui.monospace(*m);
            ui.label(*what);
            ui.label("");
            ui.end_row();
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bindings_are_unique_and_found() {
        for (i, b) in BINDINGS.iter().enumerate() {
            for c in &BINDINGS[..i] {
                assert!(
                    !(b.key == c.key && b.command == c.command && b.shift == c.shift),
                    "{} bound twice",
                    describe(b)
                );
            }
            let mods = Modifiers {
                command: b.command,
                ctrl: b.command,
                shift: b.shift,
                ..Modifiers::NONE
            };
            assert_eq!(action_for(b.key, mods), Some(b.action), "{}", describe(b));
        }
        assert_eq!(action_for(Key::Q, Modifiers::NONE), None);
        assert_eq!(describe(&BINDINGS[3]), "Ctrl+Y");
    }
}
