//! Animation playback in the viewer: the timeline's state (play / pause, time, speed, loop,
//! which animation) and the bar that shows it under the viewport.
//!
//! **Posing without stopping the renderer.** The render thread draws from an
//! `Arc<PreparedScene>` while the UI poses the next frame, so an animated scene is kept twice:
//! the one on screen and a spare. Each step poses the spare once the render thread has let
//! go of it, swaps the two and submits the posed one. Only one frame is in flight at a time,
//! so playback runs as fast as frames finish (at most [`MAX_FPS`]) and, when a frame takes
//! longer than the frame budget, the render thread's progressive levels show it at a reduced
//! resolution first (playback jobs are interactive). Paused, nothing asks for a repaint: the
//! window uses no CPU, and the last pose is refined to full quality as any still view is.
//!
//! A scene without animations shows no bar and keeps one copy.

use std::sync::{Arc, Weak};
use std::time::{Duration, Instant};

use eframe::egui;

use crate::render::PreparedScene;
use crate::scene::Play;

/// Playback asks for at most this many frames a second.
pub const MAX_FPS: f64 = 60.0;

/// Playback speeds offered, as factors of real time.
pub const SPEEDS: [f32; 6] = [0.1, 0.25, 0.5, 1.0, 2.0, 4.0];

/// Where playback time comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Clock {
    /// The wall clock.
    Wall,
    /// A time set by hand, in seconds (UI tests step it).
    Manual(f64),
}

/// The timeline's state.
#[derive(Debug)]
pub struct Timeline {
    /// Which animations play ([`Play::All`] at first: files often split one motion into an
    /// animation per node).
    pub play: Play,
    /// Playback time in seconds (within `[0, duration]`).
    pub time: f32,
    pub playing: bool,
    /// A factor of real time.
    pub speed: f32,
    pub looping: bool,
    /// Start playing when a file with animations opens.
    pub autoplay: bool,
    pub clock: Clock,
    /// The clock reading and playback time when playback last (re)started.
    anchor: Option<(f64, f32)>,
    /// What the scene on screen is posed at.
    shown: Option<(Play, f32)>,
    /// The second copy of the scene, posed while the render thread draws the first.
    spare: Option<Arc<PreparedScene>>,
    /// When the last posed frame was submitted (clock seconds), for [`MAX_FPS`].
    submitted_at: Option<f64>,
    /// The scene as loaded that this state belongs to (a new file starts over). Weak
    /// references keep the allocations, so an address is never taken for another scene's.
    base: Option<Weak<crate::scene::Scene>>,
    /// The prepared scene on screen that the spare is a copy of.
    prepared: Option<Weak<PreparedScene>>,
    /// Wall-clock origin of [`Clock::Wall`].
    origin: Instant,
}

impl Default for Timeline {
    fn default() -> Self {
        Self {
            play: Play::All,
            time: 0.0,
            playing: false,
            speed: 1.0,
            looping: true,
            autoplay: true,
            clock: Clock::Wall,
            anchor: None,
            shown: None,
            spare: None,
            submitted_at: None,
            base: None,
            prepared: None,
            origin: Instant::now(),
        }
    }
}

/// Whether `weak` refers to what `arc` holds.
fn same<T>(weak: Option<&Weak<T>>, arc: &Arc<T>) -> bool {
    weak.is_some_and(|w| std::ptr::eq(w.as_ptr(), Arc::as_ptr(arc)))
}

impl Timeline {
    fn now(&self) -> f64 {
        match self.clock {
            Clock::Wall => self.origin.elapsed().as_secs_f64(),
            Clock::Manual(t) => t,
        }
    }

    /// Starts playback from the current time (from the start if it stands at the end of a
    /// non-looping animation).
    pub fn play(&mut self, duration: f32) {
        if !self.looping && self.time >= duration {
            self.time = 0.0;
        }
        self.playing = true;
        self.anchor = Some((self.now(), self.time));
    }

    pub fn pause(&mut self) {
        self.playing = false;
        self.anchor = None;
    }

    pub fn toggle(&mut self, duration: f32) {
        if self.playing {
            self.pause();
        } else {
            self.play(duration);
        }
    }

    /// Moves to `t` seconds (playback goes on from there if playing).
    pub fn seek(&mut self, t: f32, duration: f32) {
        self.time = if t.is_finite() {
            t.clamp(0.0, duration.max(0.0))
        } else {
            0.0
        };
        if self.playing {
            self.anchor = Some((self.now(), self.time));
        }
    }

    /// Sets the speed (playback goes on from the current time).
    pub fn set_speed(&mut self, speed: f32) {
        self.speed = speed;
        if self.playing {
            self.anchor = Some((self.now(), self.time));
        }
    }

    /// Chooses what plays (the time stays, within the new duration).
    pub fn choose(&mut self, play: Play, duration: f32) {
        self.play = play;
        self.seek(self.time, duration);
    }

    /// Advances the time by the clock while playing.
    fn advance(&mut self, duration: f32) {
        let Some((t0, time0)) = self.anchor.filter(|_| self.playing) else {
            return;
        };
        let t = time0 as f64 + (self.now() - t0) * f64::from(self.speed);
        let d = f64::from(duration);
        self.time = if d <= 0.0 {
            0.0
        } else if self.looping {
            t.rem_euclid(d) as f32
        } else if t >= d {
            self.pause();
            duration
        } else {
            t as f32
        };
    }

    /// Whether a copy of the scene is kept for posing (for tests and the memory figure).
    #[must_use]
    pub fn has_spare(&self) -> bool {
        self.spare.is_some()
    }
}

/// The playback length of `play` in `scene`: the longest animation it plays.
#[must_use]
pub fn duration(scene: &crate::scene::Scene, play: Play) -> f32 {
    let a = &scene.animations;
    match play {
        Play::Rest => 0.0,
        Play::One(i) => a.get(i).map_or(0.0, |a| a.duration()),
        Play::All => a.iter().map(|a| a.duration()).fold(0.0, f32::max),
    }
}

/// Poses sampled over the animations' length (all of them together) at which
/// [`motion_sphere`] measures the scene.
pub const MOTION_SAMPLES: usize = 24;

/// The bounding sphere of `scene` over its animations (all of them, [`MOTION_SAMPLES`] + 1
/// poses from start to end), so the camera frames where the model goes and its near and far
/// planes keep it; `None` for a scene without animations. The scene is left at rest.
pub fn motion_sphere(scene: &mut PreparedScene) -> Option<(glam::Vec3, f32)> {
    let length = duration(scene.scene(), Play::All);
    if scene.scene().animations.is_empty() {
        return None;
    }
    let mut union: Option<(glam::Vec3, glam::Vec3)> = None;
    for k in 0..=MOTION_SAMPLES {
        let t = length * k as f32 / MOTION_SAMPLES as f32;
        scene.pose_at(Play::All, t, false);
        if let Some((lo, hi)) = scene.bounds() {
            union = Some(union.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
        }
    }
    scene.pose_at(Play::Rest, 0.0, false);
    let (lo, hi) = union?;
    Some(((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6)))
}

/// The name of what `play` plays.
#[must_use]
pub fn play_name(scene: &crate::scene::Scene, play: Play) -> String {
    match play {
        Play::Rest => "rest pose".into(),
        Play::All if scene.animations.len() == 1 => animation_name(scene, 0),
        Play::All => format!("all {} animations", scene.animations.len()),
        Play::One(i) => animation_name(scene, i),
    }
}

fn animation_name(scene: &crate::scene::Scene, i: usize) -> String {
    match scene.animations.get(i).map(|a| a.name.as_str()) {
        Some(n) if !n.is_empty() => format!("{i}: {n}"),
        _ => format!("animation {i}"),
    }
}

impl Timeline {
    /// One step of playback, before the UI pass submits its job: follows a new scene, advances
    /// the clock and, when the pose on screen is not the one wanted and the render thread can
    /// take another frame, poses the spare copy and puts it on screen.
    /// `drawn` is what is drawn (replaced by a posed copy), `base` the scene as loaded,
    /// `behind` says the render thread still draws a frame older than the last job.
    /// Returns whether the view moves (a pose was put on screen while playing).
    pub fn step(
        &mut self,
        drawn: &mut Arc<PreparedScene>,
        base: &Arc<crate::scene::Scene>,
        behind: bool,
        synchronous: bool,
        ctx: &egui::Context,
    ) -> bool {
        let scene = Arc::clone(drawn.scene());
        let tl = self;
        if !same(tl.base.as_ref(), base) {
            // Another file (or the same one reloaded): start over, playing if it animates.
            *tl = Timeline {
                speed: tl.speed,
                looping: tl.looping,
                autoplay: tl.autoplay,
                clock: tl.clock,
                origin: tl.origin,
                base: Some(Arc::downgrade(base)),
                ..Timeline::default()
            };
            if tl.autoplay && !scene.animations.is_empty() {
                tl.play(duration(&scene, tl.play));
            }
        }
        if scene.animations.is_empty() {
            tl.spare = None;
            tl.prepared = None;
            return false;
        }
        if !same(tl.prepared.as_ref(), drawn) {
            // A scene prepared anew (opened, or the texture lab's coordinates): its copy is made
            // from it, and it is posed again.
            tl.spare = None;
            tl.shown = None;
        }
        let length = duration(&scene, tl.play);
        tl.advance(length);
        let wanted = (tl.play, tl.time);
        if tl.shown == Some(wanted) {
            return false;
        }
        let now = tl.now();
        if tl.playing {
            // One frame in flight: the next pose waits for the frame on screen to be the last
            // one submitted, and for its turn at MAX_FPS.
            if behind {
                return false; // the render thread repaints when its frame is ready
            }
            if let Some(at) = tl.submitted_at {
                let wait = 1.0 / MAX_FPS - (now - at);
                if wait > 0.0 && tl.clock == Clock::Wall {
                    ctx.request_repaint_after(Duration::from_secs_f64(wait));
                    return false;
                }
            }
        }
        if tl.spare.is_none() {
            tl.spare = Some(Arc::new((**drawn).clone()));
        }
        let Some(spare) = tl.spare.as_mut().and_then(Arc::get_mut) else {
            // The render thread still draws from the spare: look again in a moment.
            ctx.request_repaint_after(Duration::from_millis(2));
            return false;
        };
        spare.pose_at(wanted.0, wanted.1, tl.looping);
        let spare = tl.spare.take().expect("the spare exists");
        tl.spare = Some(std::mem::replace(drawn, spare));
        tl.prepared = Some(Arc::downgrade(drawn));
        tl.shown = Some(wanted);
        tl.submitted_at = Some(now);
        if tl.playing {
            // The next step runs when this frame is shown (the render thread repaints then).
            if synchronous || tl.clock != Clock::Wall {
                ctx.request_repaint();
            }
        }
        tl.playing
    }

    /// The timeline bar (only for a scene with animations): play / pause, the time (drag to
    /// scrub), speed, loop and which animation plays.
    pub fn bar(&mut self, scene: &crate::scene::Scene, ui: &mut egui::Ui) {
        if scene.animations.is_empty() {
            return;
        }
        egui::Panel::bottom("timeline").show(ui, |ui| {
            ui.horizontal(|ui| {
                let tl = &mut *self;
                let length = duration(scene, tl.play);
                let label = if tl.playing { "Pause" } else { "Play" };
                let button = ui
                    .button(label)
                    .on_hover_text("play or pause the animation (Space)");
                if button.clicked() {
                    tl.toggle(length);
                    // Space is the viewer's key: a focused button would take it as a click too.
                    button.surrender_focus();
                }
                let mut t = tl.time;
                let slider = egui::Slider::new(&mut t, 0.0..=length.max(1e-3))
                    .show_value(false)
                    .text("time");
                let r = ui.add(slider);
                if r.changed() {
                    tl.seek(t, length);
                }
                ui.monospace(format!("{:.2} / {:.2} s", tl.time, length));
                let mut speed = tl.speed;
                egui::ComboBox::new("timeline-speed", "speed")
                    .selected_text(format!("{}x", tl.speed))
                    .width(60.0)
                    .show_ui(ui, |ui| {
                        for s in SPEEDS {
                            ui.selectable_value(&mut speed, s, format!("{s}x"));
                        }
                    });
                if speed != tl.speed {
                    tl.set_speed(speed);
                }
                ui.checkbox(&mut tl.looping, "loop");
                let mut play = tl.play;
                egui::ComboBox::new("timeline-animation", "animation")
                    .selected_text(play_name(scene, play))
                    .show_ui(ui, |ui| {
                        if scene.animations.len() > 1 {
                            ui.selectable_value(&mut play, Play::All, play_name(scene, Play::All));
                        }
                        for i in 0..scene.animations.len() {
                            ui.selectable_value(&mut play, Play::One(i), animation_name(scene, i));
                        }
                        ui.selectable_value(&mut play, Play::Rest, "rest pose");
                    });
                if play != tl.play {
                    tl.choose(play, duration(scene, play));
                }
            });
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clock_moves_time_at_the_chosen_speed_and_loops() {
        let mut tl = Timeline {
            clock: Clock::Manual(10.0),
            ..Timeline::default()
        };
        tl.play(2.0);
        tl.clock = Clock::Manual(10.5);
        tl.advance(2.0);
        assert!((tl.time - 0.5).abs() < 1e-6);
        tl.set_speed(2.0);
        tl.clock = Clock::Manual(11.5);
        tl.advance(2.0);
        assert!(
            (tl.time - 0.5).abs() < 1e-6,
            "0.5 + 2 x 1 s wraps to 0.5: {}",
            tl.time
        );
        tl.looping = false;
        tl.clock = Clock::Manual(12.5);
        tl.advance(2.0);
        assert_eq!(tl.time, 2.0);
        assert!(!tl.playing, "stops at the end without looping");
        tl.play(2.0);
        assert_eq!(tl.time, 0.0, "play at the end starts over");
    }

    #[test]
    fn seeking_clamps_and_keeps_playing_from_there() {
        let mut tl = Timeline {
            clock: Clock::Manual(0.0),
            ..Timeline::default()
        };
        tl.seek(5.0, 2.0);
        assert_eq!(tl.time, 2.0);
        tl.seek(f32::NAN, 2.0);
        assert_eq!(tl.time, 0.0);
        tl.play(2.0);
        tl.seek(1.0, 2.0);
        tl.clock = Clock::Manual(0.25);
        tl.advance(2.0);
        assert!((tl.time - 1.25).abs() < 1e-6);
        tl.pause();
        tl.clock = Clock::Manual(9.0);
        tl.advance(2.0);
        assert!((tl.time - 1.25).abs() < 1e-6, "paused time stands still");
    }
}
