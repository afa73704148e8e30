//! Key and mouse bindings, in the spirit of f3d, as one table: the dispatcher and the `H`
//! cheat sheet both read it, so the sheet lists every binding there is.

use eframe::egui::{Key, Modifiers};

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
    ("click", "probe the pixel"),
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
