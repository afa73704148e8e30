//! `realist bench diff A.png B.png` (hidden; `benches/peer.sh` uses it): the mean absolute
//! difference in 8-bit units between two RGBA renders of the same view, over interior pixels
//! only. A pixel counts when its whole 3x3 neighbourhood is covered (alpha > 0) in both
//! images, so silhouettes against the background, where one rasterizer's coverage differs
//! from the other's by a pixel, are left out (silhouettes of the mesh over itself are not
//! detected and do count).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;

#[derive(Args)]
pub(crate) struct DiffArgs {
    /// First image (RGBA PNG; alpha 0 = background).
    a: PathBuf,
    /// Second image, the same size.
    b: PathBuf,
}

pub(crate) fn diff(args: &DiffArgs) -> Result<()> {
    let load = |p: &PathBuf| -> Result<image::RgbaImage> {
        Ok(image::open(p)
            .with_context(|| format!("could not read {}", p.display()))?
            .to_rgba8())
    };
    let (a, b) = (load(&args.a)?, load(&args.b)?);
    if a.dimensions() != b.dimensions() {
        bail!(
            "{} is {}x{} but {} is {}x{}",
            args.a.display(),
            a.width(),
            a.height(),
            args.b.display(),
            b.width(),
            b.height()
        );
    }
    let (w, h) = a.dimensions();
    let covered = |img: &image::RgbaImage, x: u32, y: u32| {
        (y.saturating_sub(1)..=(y + 1).min(h - 1))
            .all(|j| (x.saturating_sub(1)..=(x + 1).min(w - 1)).all(|i| img.get_pixel(i, j)[3] > 0))
    };
    let (mut sum, mut count, mut max, mut over_8) = (0u64, 0u64, 0u8, 0u64);
    let mut total_covered = 0u64;
    for y in 0..h {
        for x in 0..w {
            let (pa, pb) = (a.get_pixel(x, y), b.get_pixel(x, y));
            if pa[3] > 0 || pb[3] > 0 {
                total_covered += 1;
            }
            if !(covered(&a, x, y) && covered(&b, x, y)) {
                continue;
            }
            let mut worst = 0;
            for c in 0..3 {
                let d = pa[c].abs_diff(pb[c]);
                sum += u64::from(d);
                worst = worst.max(d);
            }
            max = max.max(worst);
            over_8 += u64::from(worst > 8);
            count += 1;
        }
    }
    let mean = if count > 0 {
        sum as f64 / (3 * count) as f64
    } else {
        f64::NAN
    };
    let json = serde_json::json!({
        "mean_abs_diff": (mean * 1e3).round() / 1e3,
        "max_abs_diff": max,
        "pixels_compared": count,
        "pixels_covered": total_covered,
        "pixels_over_8": over_8,
    });
    say!("{json}");
    Ok(())
}
