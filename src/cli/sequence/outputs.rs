//! Where a sequence's frames go: one image, numbered images, an animated PNG, checked
//! before anything is rendered.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};

use super::{SequenceArgs, FPS_RANGE, MAX_ANIMATED_BYTES, MAX_ANIMATED_FRAMES};

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
