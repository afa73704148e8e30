//! `realist bench accuracy`: the time-versus-error sweep (see `realist::quality::sweep`).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::quality::metrics;
use realist::quality::plane::PlaneSetup;
use realist::quality::sphere::{Shape, SphereSetup};
use realist::quality::sweep::{self, ModelSetup, Subject};

use super::{load_model, parse_size, NormalArgs};

#[derive(Args)]
pub(crate) struct AccuracyArgs {
    /// Scene: sphere, cylinder or plane (textured, at a grazing angle), each with an exact
    /// reference; or a model file (glTF, GLB, OBJ), measured against the general f64
    /// reference.
    #[arg(long, default_value = "sphere")]
    scene: String,
    /// Samples per pixel side of a model's reference (8 = 64 samples per pixel).
    #[arg(long, default_value_t = 8)]
    samples: u32,
    #[command(flatten)]
    normals: NormalArgs,
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
    let (w, h) = args.size;
    let subject = match args.scene.as_str() {
        "sphere" => Subject::Shape(SphereSetup::standard_shape(Shape::Sphere, w, h)),
        "cylinder" => Subject::Shape(SphereSetup::standard_shape(Shape::Cylinder, w, h)),
        "plane" => Subject::Plane(PlaneSetup::standard(w, h)),
        path => {
            let path = Path::new(path);
            if !path.exists() {
                bail!(
                    "--scene {}: not sphere, cylinder or plane, and no such model file",
                    path.display()
                );
            }
            let scene = load_model(path, &args.normals)?;
            Subject::Model(ModelSetup::new(scene, w, h, args.samples))
        }
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let result = sweep::sweep(&subject, args.runs.max(1))?;
    let rows = &result.rows;
    let front = sweep::pareto(rows);
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
    std::fs::write(&csv_path, sweep::csv(rows, &front))
        .with_context(|| format!("writing {}", csv_path.display()))?;
    let title = format!(
        "{} at {w}x{h}: time versus error (one knob at a time)",
        args.scene
    );
    let png = sweep::plot(rows, &front, &title)
        .to_png()
        .map_err(|e| anyhow::anyhow!("encoding plot: {e}"))?;
    let plot_path = args.out.join("pareto.png");
    std::fs::write(&plot_path, png).with_context(|| format!("writing {}", plot_path.display()))?;
    say!("wrote {} and {}", csv_path.display(), plot_path.display());
    // The reference, and each Pareto-optimal setting's image and error heat map; images a
    // previous run left in the folder would read as part of this one.
    remove_previous_images(&args.out)?;
    for (index, reference) in result.references.iter().enumerate() {
        if let Some(r) = reference {
            let name = [
                "reference.png",
                "reference-blinn.png",
                "reference-textured.png",
            ][index];
            write_png(&args.out.join(name), r.width, r.height, r.to_srgb8())?;
        }
    }
    for &i in &front {
        let s = rows[i].setting;
        let (_, image) = sweep::run_setting(&subject, s, 1)?;
        let slug = s.label().replace(' ', "-");
        write_png(
            &args.out.join(format!("render-{slug}.png")),
            image.width,
            image.height,
            image.to_srgb8(),
        )?;
        if let Some(r) = &result.references[subject.reference_index(&s)] {
            write_png(
                &args.out.join(format!("heat-{slug}.png")),
                image.width,
                image.height,
                metrics::heat_map(&image, r),
            )?;
        }
    }
    say!(
        "wrote the reference image(s) and render-*.png, heat-*.png (dE00 0 black .. {} white) for the Pareto-optimal settings",
        metrics::HEAT_MAP_MAX_DE
    );
    Ok(())
}

/// Removes `reference*.png`, `render-*.png` and `heat-*.png` from `dir`.
fn remove_previous_images(dir: &Path) -> Result<()> {
    let entries = std::fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))?;
    for e in entries.flatten() {
        let name = e.file_name();
        let name = name.to_string_lossy();
        let ours = name.ends_with(".png")
            && ["reference", "render-", "heat-"]
                .iter()
                .any(|p| name.starts_with(p));
        if ours && e.file_type().is_ok_and(|t| t.is_file()) {
            std::fs::remove_file(e.path())
                .with_context(|| format!("removing {}", e.path().display()))?;
        }
    }
    Ok(())
}

fn write_png(path: &Path, width: u32, height: u32, rgb: Vec<u8>) -> Result<()> {
    image::RgbImage::from_raw(width, height, rgb)
        .context("image size mismatch")?
        .save(path)
        .with_context(|| format!("writing {}", path.display()))
}
