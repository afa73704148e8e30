//! What a sequence animates and when: the animation `--animation` names among the
//! scene's, and the times `--time` or `--frames` ask for.

use anyhow::{bail, Context, Result};

use realist::scene::{Play, Scene};

use super::SequenceArgs;

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
pub(super) fn times(args: &SequenceArgs, scene: &Scene, play: Play) -> Result<Vec<Option<f32>>> {
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
