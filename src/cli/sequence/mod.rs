//! Image sequences and animated images from `realist render`: `--turntable N` turns the
//! camera around the model, `{}` in the output name numbers the frames, an `.apng` output
//! (or `--animated PATH`) holds every frame in one animated PNG.
//!
//! The work is a list of [`SeqFrame`]s built from the flags ([`frames`]) and one loop
//! ([`run`]) that renders each frame and writes it. A single render is the list of one frame.
//!
//! Animation: `--time T` poses the scene at T seconds, `--frames START:END:STEP` (or
//! `--frames N`, N frames over one loop of the animation) makes one frame per time, and
//! `--animation NAME|N|all` chooses what plays (all animations together by default). With
//! `--turntable N` as well, the camera turns once around over the frames. The default camera
//! then frames the union of every frame's posed bounds, so the framing stays fixed.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::color::png::Apng;
use realist::raster::Stats;
use realist::render::{PreparedScene, View};
use realist::scene::{Camera, Play, Scene, Up};

mod animation;
mod cameras;
mod outputs;

pub(crate) use animation::play;
use animation::times;
pub(crate) use cameras::frame_animation;
use cameras::{frame_every_azimuth, turntable};
pub(crate) use outputs::{check_animated, frame_name, Names, Outputs};
// Used only by the tests (`tests.rs`, through `use super::*`).
#[cfg(test)]
use {cameras::orbit_of, glam::Vec3, outputs::Animated};

/// Most frames `--turntable` makes.
pub(crate) const MAX_FRAMES: u32 = 100_000;
/// Most frames of an animated image.
pub(crate) const MAX_ANIMATED_FRAMES: usize = 10_000;
/// Most pixel bytes (8-bit RGB, every frame) of an animated image: what a viewer decoding it
/// may have to hold.
pub(crate) const MAX_ANIMATED_BYTES: u64 = 2 << 30;
/// `--fps` range.
const FPS_RANGE: std::ops::RangeInclusive<f32> = 0.01..=600.0;

#[derive(Args, Default)]
pub(crate) struct SequenceArgs {
    /// Render N views around the model: the camera turns 360°/N per frame around the
    /// vertical axis through the scene's centre, from the view it would otherwise have, at
    /// one elevation and distance (without a given distance, the one that frames the scene
    /// from every side). Needs `{}` in a PNG output name (replaced by the frame number) or an
    /// .apng output.
    #[arg(long, value_name = "N")]
    pub turntable: Option<u32>,
    /// Also write every frame into one looping animated PNG (APNG) at PATH (.apng or .png);
    /// without -o, only the animated image is written.
    #[arg(long, value_name = "PATH")]
    pub animated: Option<PathBuf>,
    /// Frames per second of the animated image (default 12 for --turntable, else 24).
    #[arg(long, value_name = "F")]
    pub fps: Option<f32>,
    /// Which animation plays (glTF): its name or number (`realist info` lists them), or
    /// all of them together (the default once --time or --frames is given).
    #[arg(long, value_name = "NAME|N|all")]
    pub animation: Option<String>,
    /// Pose the scene at this time in seconds (past an animation's end, its last pose).
    #[arg(
        long,
        value_name = "SECONDS",
        conflicts_with = "frames",
        allow_hyphen_values = true
    )]
    pub time: Option<f32>,
    /// An animated sequence: START:END:STEP seconds (END included when a step lands on it),
    /// or N frames spread over one loop of the animation. Needs `{}` in a PNG output name or
    /// an .apng output.
    #[arg(long, value_name = "START:END:STEP|N")]
    pub frames: Option<String>,
}

/// One frame of a sequence: where the camera is and the animation time.
#[derive(Clone, Debug)]
pub(crate) struct SeqFrame {
    pub camera: Camera,
    /// Animation time in seconds at which the scene is posed (`None`: as loaded).
    pub time: Option<f32>,
    /// What plays at `time`.
    pub play: Play,
    /// The file's camera of this index, which follows its node as the scene is posed
    /// (`--camera gltf:N`); `camera` then gives the projection, unless `follow_fov`.
    pub follow: Option<usize>,
    /// The followed camera's posed field of view is used too (an animated yfov,
    /// `KHR_animation_pointer`), as when neither `--fov` nor `--zoom` sets one.
    pub follow_fov: bool,
}

/// The frames the flags ask for: one with `base`, or a turntable around `scene`'s centre.
/// `framed` says `base`'s distance was chosen to frame the scene from its own direction (the
/// default view, an orbit without a distance): a turntable then moves it to the distance
/// that frames the scene from every frame's direction, so the framing stays fixed.
pub(crate) fn frames(
    args: &SequenceArgs,
    base: Camera,
    scene: &Scene,
    aspect: f32,
    framed: bool,
    up: Up,
) -> Result<Vec<SeqFrame>> {
    if scene.animations.is_empty() && args.turntable.is_none() {
        let flag = match (&args.time, &args.frames) {
            (Some(t), _) => Some(format!("--time {t}")),
            (None, Some(f)) => Some(format!("--frames {f}")),
            (None, None) => None,
        };
        if let Some(flag) = flag {
            bail!(
                "{flag}: the model has no animations, so every frame would be the same \
                 (--turntable N turns the camera around it)"
            );
        }
    }
    let play = play(args, scene)?;
    let mut times = times(args, scene, play)?;
    let cameras = match args.turntable {
        None => vec![base; times.len()],
        Some(n) if !(1..=MAX_FRAMES).contains(&n) => {
            bail!("--turntable {n}: expected 1 to {MAX_FRAMES} frames")
        }
        Some(n) => {
            match (args.frames.is_some(), times.len()) {
                // The camera turns once around over the animated frames.
                (true, k) if k != n as usize => {
                    bail!("--turntable {n} with --frames: {k} animation frames; give as many views")
                }
                // A turntable of an animated model plays one loop of it.
                (false, _) if play != Play::Rest && args.time.is_none() => {
                    let a = SequenceArgs {
                        frames: Some(n.to_string()),
                        time: None,
                        animation: args.animation.clone(),
                        ..SequenceArgs::default()
                    };
                    times = self::times(&a, scene, play)?;
                }
                (false, _) => times = vec![times[0]; n as usize],
                _ => {}
            }
            let bounds = scene.bounds();
            let pivot = bounds.map_or(base.target, |(lo, hi)| (lo + hi) * 0.5);
            let base = match bounds {
                Some((lo, hi)) if framed => frame_every_azimuth(&base, lo, hi, aspect, n, up),
                _ => base,
            };
            turntable(&base, pivot, n, up)
        }
    };
    Ok(cameras
        .into_iter()
        .zip(times)
        .map(|(camera, time)| SeqFrame {
            camera,
            time,
            play,
            follow: None,
            follow_fov: false,
        })
        .collect())
}

/// One rendered frame: 8-bit sRGB RGB rows.
pub(crate) struct Drawn {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
    pub stats: Stats,
}

/// What [`run`] did.
#[derive(Debug, Default)]
pub(crate) struct Done {
    /// Counters summed over the frames.
    pub stats: Stats,
    pub raster: Duration,
    pub encode: Duration,
    /// The per-frame images written, first and last.
    pub images: Vec<PathBuf>,
    /// The animated image and its size in pixels.
    pub animated: Option<(PathBuf, u32, u32)>,
}

/// Poses the scene at a frame's animation time before it is drawn (no wrapping: past an
/// animation's end, its last pose).
fn apply_frame_time(scene: &mut PreparedScene, play: Play, time: Option<f32>) {
    if let Some(t) = time {
        scene.pose_at(play, t, false);
    }
}

/// Renders every frame with `draw` (one renderer and one prepared scene for all of them) and
/// writes it: to its own image and/or into the animated image.
pub(crate) fn run(
    frames: &[SeqFrame],
    (width, height): (u32, u32),
    prepared: PreparedScene,
    outputs: &Outputs,
    mut draw: impl FnMut(&PreparedScene, &View) -> Result<Drawn>,
    write_image: impl Fn(&Path, u32, u32, Vec<u8>) -> Result<()>,
) -> Result<Done> {
    let mut done = Done::default();
    let mut scene = Some(prepared);
    let mut apng: Option<Apng> = None;
    let last = frames.len().saturating_sub(1);
    for (i, frame) in frames.iter().enumerate() {
        let prepared = scene.as_mut().context("the scene was already freed")?;
        apply_frame_time(prepared, frame.play, frame.time);
        let t = Instant::now();
        let mut camera = frame.camera.clone();
        if let Some(posed) = frame.follow.and_then(|n| prepared.cameras().get(n)) {
            (camera.eye, camera.target, camera.up) = (posed.eye, posed.target, posed.up);
            if frame.follow_fov && posed.ortho.is_none() {
                camera.yfov = posed.yfov;
            }
        }
        let view = View {
            camera,
            width,
            height,
        };
        let img = draw(prepared, &view)?;
        done.raster += t.elapsed();
        done.stats.add(&img.stats);
        let t = Instant::now();
        if let Some(a) = &outputs.animated {
            if apng.is_none() {
                check_animated(&a.path, frames.len(), (img.width, img.height))?;
                apng = Some(
                    Apng::create(&a.path, (img.width, img.height), frames.len(), a.fps, &[])
                        .map_err(anyhow::Error::msg)?,
                );
                done.animated = Some((a.path.clone(), img.width, img.height));
            }
            if let Some(w) = apng.as_mut() {
                w.add((img.width, img.height), &img.rgb)
                    .map_err(anyhow::Error::msg)?;
            }
        }
        if let Some(names) = &outputs.images {
            let path = match names {
                Names::Single(p) => p.clone(),
                Names::Numbered(p) => PathBuf::from(frame_name(p, i, last)),
            };
            let (w, h, rgb) = (img.width, img.height, img.rgb);
            let written = if i == last {
                // The scene is freed on another thread while the last image is encoded
                // (freeing its large buffers took about 1 ms; the PNG encoder leaves a core
                // idle).
                let s = scene.take();
                std::thread::scope(|scope| {
                    scope.spawn(move || drop(s));
                    write_image(&path, w, h, rgb)
                })
            } else {
                write_image(&path, w, h, rgb)
            };
            written.with_context(|| format!("could not write {}", path.display()))?;
            if i == 0 || i == last {
                done.images.push(path);
            }
        }
        done.encode += t.elapsed();
    }
    let t = Instant::now();
    if let Some(w) = apng {
        w.finish().map_err(anyhow::Error::msg)?;
    }
    done.encode += t.elapsed();
    Ok(done)
}

#[cfg(test)]
mod tests;
