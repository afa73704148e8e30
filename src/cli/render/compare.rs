//! `realist render --compare REFERENCE.png [--tolerance LEVELS[,PIXELS]]`: the rendered image
//! against a reference, for other people's CI. Identical bytes by default (realist's images
//! are the same on every machine: README, "The same image on every machine"); the exit
//! status says whether they match, the message counts the differing pixels, and a heat map
//! is written beside the rendered image when any pixel differs.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// How far the rendered image may be from the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Tolerance {
    /// Largest per-channel difference (8-bit codes) that does not count as differing.
    pub levels: u8,
    /// How many pixels may differ by more than `levels`.
    pub pixels: Allowed,
}

/// The differing pixels allowed: a count or a percentage of the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Allowed {
    Count(u64),
    Percent(f64),
}

impl Default for Tolerance {
    /// Identical bytes.
    fn default() -> Self {
        Self {
            levels: 0,
            pixels: Allowed::Count(0),
        }
    }
}

impl Allowed {
    fn of(self, total: u64) -> u64 {
        match self {
            Allowed::Count(n) => n,
            Allowed::Percent(p) => (p / 100.0 * total as f64).floor() as u64,
        }
    }
}

/// `--tolerance LEVELS[,PIXELS]`: e.g. `1` (a level per channel, no pixel beyond it, as
/// resvg's tests allow), `2,10` (ten pixels may differ by more) or `2,0.1%`.
pub(crate) fn parse_tolerance(s: &str) -> Result<Tolerance, String> {
    let (levels, pixels) = match s.split_once(',') {
        Some((l, p)) => (l, Some(p)),
        None => (s, None),
    };
    let levels: u8 = levels
        .trim()
        .parse()
        .map_err(|_| format!("--tolerance: bad level '{levels}' (a whole number, 0 to 255)"))?;
    let pixels = match pixels.map(str::trim) {
        None => Allowed::Count(0),
        Some(p) => match p.strip_suffix('%') {
            Some(pct) => match pct.trim().parse::<f64>() {
                Ok(v) if (0.0..=100.0).contains(&v) => Allowed::Percent(v),
                _ => return Err(format!("--tolerance: bad percentage '{p}' (0% to 100%)")),
            },
            None => Allowed::Count(p.parse().map_err(|_| {
                format!("--tolerance: bad pixel count '{p}' (a whole number, or a percentage)")
            })?),
        },
    };
    Ok(Tolerance { levels, pixels })
}

/// What a comparison found.
#[derive(Debug, PartialEq)]
pub(crate) struct Comparison {
    pub total: u64,
    /// Pixels that differ at all.
    pub differing: u64,
    /// Pixels that differ by more than the tolerance's levels.
    pub over: u64,
    /// The largest difference of any channel.
    pub worst: u8,
    /// The differing pixels the tolerance allows.
    pub allowed: u64,
}

impl Comparison {
    pub fn passed(&self) -> bool {
        self.over <= self.allowed
    }
}

/// Compares RGB8 `got` (`w` x `h`) with `reference` (RGB8, the same size) and returns the
/// counts and a heat map: the reference in dim grey where a pixel is identical, blue where
/// it differs within the tolerance's levels, yellow to red (1 to 32 or more levels) beyond.
pub(crate) fn compare(got: &[u8], reference: &[u8], tol: Tolerance) -> (Comparison, Vec<u8>) {
    let total = (got.len() / 3) as u64;
    let (mut differing, mut over, mut worst) = (0u64, 0u64, 0u8);
    let mut heat = Vec::with_capacity(got.len());
    for (a, b) in got.chunks_exact(3).zip(reference.chunks_exact(3)) {
        let d = a
            .iter()
            .zip(b)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        worst = worst.max(d);
        let pixel = if d == 0 {
            // Rec. 709 luma of the reference, at a third: the picture, out of the way.
            let y =
                (0.2126 * f32::from(b[0]) + 0.7152 * f32::from(b[1]) + 0.0722 * f32::from(b[2]))
                    / 3.0;
            [y as u8; 3]
        } else if d <= tol.levels {
            differing += 1;
            [40, 90, 255]
        } else {
            differing += 1;
            over += 1;
            let t = (f32::from(d) / 32.0).min(1.0);
            [255, (255.0 * (1.0 - t)) as u8, 0]
        };
        heat.extend_from_slice(&pixel);
    }
    let allowed = tol.pixels.of(total);
    (
        Comparison {
            total,
            differing,
            over,
            worst,
            allowed,
        },
        heat,
    )
}

/// Reads the reference image as RGB8 (its alpha, if any, is not compared).
pub(crate) fn read_reference(path: &Path) -> Result<(u32, u32, Vec<u8>)> {
    let img = image::open(path)
        .with_context(|| format!("--compare: cannot read the reference {}", path.display()))?
        .to_rgb8();
    Ok((img.width(), img.height(), img.into_raw()))
}

/// The heat map's name: `NAME.diff.png` beside the rendered `NAME.png`.
pub(crate) fn heat_map_path(output: &Path) -> PathBuf {
    let stem = output
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    output.with_file_name(format!("{stem}.diff.png"))
}

/// The reference image of `--compare`, read and checked before anything is rendered.
pub(crate) struct Reference {
    path: PathBuf,
    rgb: Vec<u8>,
}

/// Whether `a` and `b` name one existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(x), Ok(y)) if x == y
    )
}

impl Reference {
    /// Reads `path` and checks it against the render to come: its size must be `w` x `h`,
    /// and neither the image (`output`) nor its heat map may be written over it (a render
    /// that replaced its own reference would always pass).
    pub(crate) fn load(path: &Path, output: &Path, (w, h): (u32, u32)) -> Result<Self> {
        for (what, target) in [
            ("the image", output.to_owned()),
            ("the heat map", heat_map_path(output)),
        ] {
            if same_file(path, &target) {
                bail!(
                    "--compare: {what} would be written over the reference {} (give -o another name)",
                    path.display()
                );
            }
        }
        let (rw, rh, rgb) = read_reference(path)?;
        if (rw, rh) != (w, h) {
            bail!(
                "--compare: the reference {} is {rw}x{rh}, the render {w}x{h} (give --size {rw}x{rh})",
                path.display()
            );
        }
        Ok(Self {
            path: path.to_owned(),
            rgb,
        })
    }

    /// Compares the rendered image written at `output` with the reference and reports: Ok
    /// with a line to print when it passes, an error (the command's exit status 1) naming
    /// the counts and the heat map when it does not.
    pub(crate) fn check(
        &self,
        output: &Path,
        (w, h): (u32, u32),
        got: &[u8],
        tol: Tolerance,
    ) -> Result<String> {
        let reference = &self.path;
        if got.len() != self.rgb.len() {
            bail!(
                "--compare: the render is {w}x{h}, not the reference's size ({})",
                reference.display()
            );
        }
        let (c, heat) = compare(got, &self.rgb, tol);
        let heat_path = heat_map_path(output);
        let mut line = format!(
            "compare: {} of {} pixels differ from {} (worst {} levels); {} by more than {} (allowed {})",
            c.differing,
            c.total,
            reference.display(),
            c.worst,
            c.over,
            tol.levels,
            c.allowed
        );
        if c.differing > 0 {
            realist::color::png::Png::rgb(w, h, &heat)
                .with_text(
                    "Source",
                    format!("realist render --compare {}", reference.display()),
                )
                .write(&heat_path)
                .map_err(anyhow::Error::msg)
                .with_context(|| format!("--compare: cannot write {}", heat_path.display()))?;
            line += &format!("; heat map {}", heat_path.display());
        } else {
            // A heat map of an earlier, failed comparison would now be out of date.
            let _ = std::fs::remove_file(&heat_path);
            line = format!(
                "compare: identical to {} ({} pixels)",
                reference.display(),
                c.total
            );
        }
        if c.passed() {
            Ok(line)
        } else {
            bail!("{line}: the image differs")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerance_forms() {
        assert_eq!(parse_tolerance("0"), Ok(Tolerance::default()));
        assert_eq!(
            parse_tolerance("2,10"),
            Ok(Tolerance {
                levels: 2,
                pixels: Allowed::Count(10)
            })
        );
        assert_eq!(
            parse_tolerance("1, 0.5%"),
            Ok(Tolerance {
                levels: 1,
                pixels: Allowed::Percent(0.5)
            })
        );
        for bad in ["", "-1", "256", "1,x", "1,101%", "1,-2", "x,1"] {
            assert!(parse_tolerance(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn counts_and_heat_map() {
        // Four pixels: identical, one level off, five levels off, forty levels off.
        let want = [10, 20, 30, 100, 100, 100, 0, 0, 0, 200, 200, 200];
        let got = [10, 20, 30, 101, 100, 100, 0, 5, 0, 200, 160, 200];
        let tol = Tolerance {
            levels: 1,
            pixels: Allowed::Count(1),
        };
        let (c, heat) = compare(&got, &want, tol);
        assert_eq!(
            c,
            Comparison {
                total: 4,
                differing: 3,
                over: 2,
                worst: 40,
                allowed: 1
            }
        );
        assert!(!c.passed());
        assert_eq!(&heat[3..6], &[40, 90, 255], "within the levels: blue");
        assert_eq!(heat[9], 255, "beyond: red");
        assert!(heat[10] < heat[7], "a larger difference is redder");
        assert_eq!(heat[0], heat[1], "identical: grey");
        let half = Tolerance {
            levels: 1,
            pixels: Allowed::Percent(50.0),
        };
        assert!(compare(&got, &want, half).0.passed());
        assert_eq!(compare(&want, &want, Tolerance::default()).0.differing, 0);
    }

    #[test]
    fn heat_map_beside_the_output() {
        assert_eq!(
            heat_map_path(Path::new("out/a.png")),
            Path::new("out/a.diff.png")
        );
    }
}
