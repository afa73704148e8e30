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
use glam::{Mat3, Vec3};

use realist::color::png::Apng;
use realist::raster::Stats;
use realist::render::{PreparedScene, View};
use realist::scene::{Camera, Play, Scene, Up};

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

/// Most frames `--frames` makes.
const MAX_TIMES: usize = 100_000;

/// What `--animation` names, among `scene`'s animations.
pub(crate) fn play(args: &SequenceArgs, scene: &Scene) -> Result<Play> {
    let names = || {
        let list: Vec<String> = scene
            .animations
            .iter()
            .enumerate()
            .map(|(i, a)| format!("{i} '{}'", a.name))
            .collect();
        if list.is_empty() {
            "the model has no animations".to_string()
        } else {
            format!("the model has {}", list.join(", "))
        }
    };
    let Some(a) = &args.animation else {
        let timed = args.time.is_some() || args.frames.is_some();
        return Ok(if timed { Play::All } else { Play::Rest });
    };
    if scene.animations.is_empty() {
        bail!("--animation {a}: {}", names());
    }
    if a.eq_ignore_ascii_case("all") {
        return Ok(Play::All);
    }
    if let Some(i) = scene.animations.iter().position(|x| x.name == *a) {
        return Ok(Play::One(i));
    }
    match a.trim().parse::<usize>() {
        Ok(i) if i < scene.animations.len() => Ok(Play::One(i)),
        _ => bail!("--animation {a}: no such animation; {}", names()),
    }
}

/// The animation times the flags ask for (`None`: the scene as loaded, one frame).
fn times(args: &SequenceArgs, scene: &Scene, play: Play) -> Result<Vec<Option<f32>>> {
    let duration = match play {
        Play::Rest => 0.0,
        Play::One(i) => scene.animations.get(i).map_or(0.0, |a| a.duration()),
        Play::All => scene
            .animations
            .iter()
            .map(|a| a.duration())
            .fold(0.0, f32::max),
    };
    if let Some(t) = args.time {
        if !t.is_finite() {
            bail!("--time {t}: expected a finite number of seconds");
        }
        return Ok(vec![Some(t)]);
    }
    let Some(f) = &args.frames else {
        return Ok(vec![match play {
            Play::Rest => None,
            _ => Some(0.0),
        }]);
    };
    let parts: Vec<&str> = f.split(':').collect();
    let num = |s: &str| -> Result<f32> {
        s.trim()
            .parse::<f32>()
            .ok()
            .filter(|x| x.is_finite())
            .with_context(|| format!("--frames {f}: '{s}' is not a number"))
    };
    let times: Vec<f32> = match parts.as_slice() {
        [n] => {
            let n: usize = n
                .trim()
                .parse()
                .ok()
                .filter(|n| (1..=MAX_TIMES).contains(n))
                .with_context(|| {
                    format!("--frames {f}: expected 1 to {MAX_TIMES} frames, or START:END:STEP")
                })?;
            (0..n).map(|i| duration * i as f32 / n as f32).collect()
        }
        [a, b, c] => {
            let (start, end, step) = (num(a)?, num(b)?, num(c)?);
            if step <= 0.0 || end < start {
                bail!("--frames {f}: expected START <= END and a positive STEP");
            }
            let count = ((end - start) / step + 1e-4).floor() + 1.0;
            if count > MAX_TIMES as f32 {
                bail!("--frames {f}: {count} frames, more than {MAX_TIMES}");
            }
            (0..count as usize)
                .map(|i| start + step * i as f32)
                .collect()
        }
        _ => bail!("--frames {f}: expected START:END:STEP (seconds) or a number of frames"),
    };
    Ok(times.into_iter().map(Some).collect())
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
                "{flag}: the model has no animations, so every frame would be the same                  (--turntable N turns the camera around it)"
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

/// For an animated sequence whose camera was framed on the scene (`framed`): every
/// camera moved to frame the union of the posed bounds at all the frames' times, at the
/// largest distance any frame's direction needs, so the framing stays fixed.
pub(crate) fn frame_animation(
    frames: &mut [SeqFrame],
    scene: &mut PreparedScene,
    aspect: f32,
    framed: bool,
) {
    if !framed || frames.iter().all(|f| f.time.is_none()) {
        return;
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for f in frames.iter() {
        scene.pose_at(f.play, f.time.unwrap_or(0.0), false);
        if let Some((a, b)) = scene.bounds() {
            (lo, hi) = (lo.min(a), hi.max(b));
        }
    }
    if lo.x > hi.x {
        return;
    }
    let center = (lo + hi) * 0.5;
    let framed: Vec<(Vec3, f32)> = frames
        .iter()
        .map(|f| {
            let (az, el, _) = orbit_of(f.camera.eye, f.camera.target);
            let c = Camera::frame_box_fov(lo, hi, aspect, az, el, f.camera.yfov);
            let d = c.eye - c.target;
            (d.normalize_or_zero(), d.length())
        })
        .collect();
    let far = framed
        .iter()
        .map(|x| x.1)
        .filter(|d| d.is_finite())
        .fold(0.0, f32::max);
    if far <= 0.0 {
        return;
    }
    for (f, (dir, _)) in frames.iter_mut().zip(framed) {
        f.camera.eye = center + dir * far;
        f.camera.target = center;
        f.camera.fit(center, ((hi - lo) * 0.5).length().max(1e-6));
    }
}

/// `n` cameras: `base` turned by 360°·i/n around the vertical axis through `pivot` (eye,
/// target and up turn together; the first is `base`).
pub(crate) fn turntable(base: &Camera, pivot: Vec3, n: u32, up: Up) -> Vec<Camera> {
    (0..n)
        .map(|i| {
            let angle = std::f32::consts::TAU * i as f32 / n as f32;
            let turn = match up {
                Up::Y => Mat3::from_rotation_y(angle),
                Up::Z => Mat3::from_rotation_z(angle),
            };
            Camera {
                eye: pivot + turn * (base.eye - pivot),
                target: pivot + turn * (base.target - pivot),
                up: turn * base.up,
                ..base.clone()
            }
        })
        .collect()
}

/// Azimuth (degrees around +Y, 0 = on +Z), elevation (degrees) and distance of `eye` seen
/// from `pivot`.
pub(crate) fn orbit_of(eye: Vec3, pivot: Vec3) -> (f32, f32, f32) {
    let d = eye - pivot;
    let dist = d.length();
    let az = d.x.atan2(d.z).to_degrees();
    let el = if dist > 0.0 {
        (d.y / dist).clamp(-1.0, 1.0).asin().to_degrees()
    } else {
        0.0
    };
    (az, el, dist)
}

/// `base` (framing the box `lo..hi` from its direction) moved back along its line of sight
/// to the largest of the distances that frame the box from the `n` turntable directions.
fn frame_every_azimuth(base: &Camera, lo: Vec3, hi: Vec3, aspect: f32, n: u32, up: Up) -> Camera {
    if up != Up::Y {
        // In the Y-up frame, and turned back.
        let q = up.to_y_up();
        let (lo, hi) = up.box_to_y_up(lo, hi);
        let c = frame_every_azimuth(&base.clone().turned(q), lo, hi, aspect, n, Up::Y);
        return c.turned(q.inverse());
    }
    let center = (lo + hi) * 0.5;
    let (az, el, dist) = orbit_of(base.eye, center);
    let far = (0..n)
        .map(|i| {
            let a = az + 360.0 * i as f32 / n as f32;
            let c = Camera::frame_box_fov(lo, hi, aspect, a, el, base.yfov);
            (c.eye - c.target).length()
        })
        .filter(|d| d.is_finite())
        .fold(dist, f32::max);
    let mut cam = base.clone();
    if far > dist && dist > 0.0 {
        cam.eye = center + (base.eye - center) * (far / dist);
        cam.fit(center, ((hi - lo) * 0.5).length().max(1e-6));
    }
    cam
}

/// Where the frames go.
#[derive(Debug, PartialEq)]
pub(crate) struct Outputs {
    /// One image per frame.
    pub images: Option<Names>,
    /// One animated PNG holding every frame.
    pub animated: Option<Animated>,
}

/// The per-frame image names.
#[derive(Debug, PartialEq)]
pub(crate) enum Names {
    /// One frame, one name.
    Single(PathBuf),
    /// `{}` replaced by the zero-padded frame number.
    Numbered(String),
}

#[derive(Debug, PartialEq)]
pub(crate) struct Animated {
    pub path: PathBuf,
    pub fps: f32,
}

/// The name of frame `i` of a sequence whose last frame is `last`: every `{}` in `pattern`
/// replaced by `i`, zero-padded to the digits of `last` (frame_00.png to frame_35.png for 36).
pub(crate) fn frame_name(pattern: &str, i: usize, last: usize) -> String {
    let width = last.to_string().len();
    pattern.replace("{}", &format!("{i:0width$}"))
}

fn has_extension(p: &Path, ext: &str) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// `p` as text when it holds a `{}` (an error if it is not UTF-8), else `None`.
fn pattern_of(p: &Path) -> Result<Option<String>> {
    let lossy = p.to_string_lossy();
    if !lossy.contains("{}") {
        return Ok(None);
    }
    match p.to_str() {
        Some(s) => Ok(Some(s.to_owned())),
        None => bail!("{}: a numbered name must be valid UTF-8", lossy),
    }
}

impl Outputs {
    /// Where `count` frames of `size` go: `out` (-o or the default name; `None` when only
    /// `--animated` is given) and `--animated`, checked before anything is rendered.
    pub(crate) fn plan(
        out: Option<PathBuf>,
        args: &SequenceArgs,
        count: usize,
        size: (u32, u32),
    ) -> Result<Self> {
        let fps = match args.fps {
            Some(f) if f.is_finite() && FPS_RANGE.contains(&f) => f,
            Some(f) => bail!(
                "--fps {f}: expected frames per second from {} to {}",
                FPS_RANGE.start(),
                FPS_RANGE.end()
            ),
            None if args.turntable.is_some() => 12.0,
            None => 24.0,
        };
        let mut images = None;
        let mut animated = None;
        if let Some(out) = out {
            if let Some(p) = pattern_of(&out)? {
                images = Some(Names::Numbered(p));
            } else if has_extension(&out, "apng") {
                if let Some(a) = &args.animated {
                    bail!(
                        "{} and --animated {}: give one animated image, not two",
                        out.display(),
                        a.display()
                    );
                }
                animated = Some(Animated { path: out, fps });
            } else if count > 1 {
                bail!(
                    "{}: {count} frames need `{{}}` in the name for the frame number (e.g. \
                     frame_{{}}.png), or an .apng name (or --animated) for one animated image",
                    out.display()
                );
            } else {
                images = Some(Names::Single(out));
            }
        }
        if let Some(a) = &args.animated {
            if pattern_of(a)?.is_some() {
                bail!(
                    "--animated {}: one file holds every frame, so no `{{}}` in its name",
                    a.display()
                );
            }
            if !(has_extension(a, "apng") || has_extension(a, "png")) {
                bail!(
                    "--animated {}: the animated image is a PNG (APNG); name it .apng or .png",
                    a.display()
                );
            }
            animated = Some(Animated {
                path: a.clone(),
                fps,
            });
        }
        match &animated {
            Some(a) => check_animated(&a.path, count, size)?,
            None if args.fps.is_some() => eprintln!(
                "warning: --fps sets the speed of an animated image (an .apng output or \
                 --animated); it is not used here"
            ),
            None => {}
        }
        Ok(Self { images, animated })
    }
}

/// Refuses an animated image of more than [`MAX_ANIMATED_FRAMES`] frames or
/// [`MAX_ANIMATED_BYTES`] of pixels.
pub(crate) fn check_animated(path: &Path, count: usize, (w, h): (u32, u32)) -> Result<()> {
    if count > MAX_ANIMATED_FRAMES {
        bail!(
            "{}: {count} frames is too many for one animated image (at most \
             {MAX_ANIMATED_FRAMES}); write a numbered sequence (-o frame_{{}}.png) instead",
            path.display()
        );
    }
    let bytes = u64::from(w) * u64::from(h) * 3 * count as u64;
    if bytes > MAX_ANIMATED_BYTES {
        let gib = |b: u64| b as f64 / f64::from(1u32 << 30);
        bail!(
            "{}: {count} frames of {w}x{h} are {:.1} GiB of pixels, more than the {:.0} GiB \
             an animated image may hold; use fewer frames or a smaller --size, or write a \
             numbered sequence (-o frame_{{}}.png)",
            path.display(),
            gib(bytes),
            gib(MAX_ANIMATED_BYTES)
        );
    }
    Ok(())
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
