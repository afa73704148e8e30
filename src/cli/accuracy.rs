//! `realist bench accuracy`: the time-versus-error sweep (see `realist::quality::sweep`).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::quality::sphere::{Shape, SphereSetup};
use realist::quality::sweep;

use super::parse_size;

#[derive(Args)]
pub(crate) struct AccuracyArgs {
    /// Scene with an analytic reference: sphere or cylinder (plane and models come next).
    #[arg(long, default_value = "sphere")]
    scene: String,
    /// Image size WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    size: (u32, u32),
    /// Output folder for results.csv and pareto.png.
    #[arg(long)]
    out: PathBuf,
    /// Timed renders per setting (the median is reported).
    #[arg(long, default_value_t = 7)]
    runs: usize,
}

pub(crate) fn accuracy(args: &AccuracyArgs) -> Result<()> {
    let shape = match args.scene.as_str() {
        "sphere" => Shape::Sphere,
        "cylinder" => Shape::Cylinder,
        s => bail!("--scene {s}: no reference for it yet (expected sphere or cylinder)"),
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let (w, h) = args.size;
    let setup = SphereSetup::standard_shape(shape, w, h);
    let rows = sweep::sweep(&setup, args.runs.max(1))?;
    let front = sweep::pareto(&rows);
    say!(
        "{:<14} {:<24} {:>9} {:>9} {:>8} {:>9} {:>9} {:>9}",
        "knob",
        "setting",
        "ms",
        "rmse",
        "psnr",
        "mean dE",
        "p95 dE",
        "px>1dE"
    );
    for (i, r) in rows.iter().enumerate() {
        let m = &r.metrics;
        say!(
            "{:<14} {:<24} {:>9.2} {:>9.5} {:>8.2} {:>9.4} {:>9.4} {:>9}{}",
            r.knob,
            r.setting.label(),
            r.ms,
            m.rmse,
            m.psnr,
            m.mean_de2000,
            m.p95_de2000,
            m.over_threshold,
            if front.contains(&i) { "  *" } else { "" }
        );
    }
    say!("Pareto-optimal (fastest first; * above):");
    for &i in &front {
        let r = &rows[i];
        say!(
            "  {:<24} {:>8.2} ms  mean dE00 {:.4}",
            r.setting.label(),
            r.ms,
            r.metrics.mean_de2000
        );
    }
    let csv_path = args.out.join("results.csv");
    std::fs::write(&csv_path, sweep::csv(&rows, &front))
        .with_context(|| format!("writing {}", csv_path.display()))?;
    let title = format!(
        "{} at {w}x{h}: time versus error (one knob at a time)",
        args.scene
    );
    let png = sweep::plot(&rows, &front, &title)
        .to_png()
        .map_err(|e| anyhow::anyhow!("encoding plot: {e}"))?;
    let plot_path = args.out.join("pareto.png");
    std::fs::write(&plot_path, png).with_context(|| format!("writing {}", plot_path.display()))?;
    say!("wrote {} and {}", csv_path.display(), plot_path.display());
    Ok(())
}
