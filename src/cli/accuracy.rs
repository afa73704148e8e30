//! `realist bench accuracy`: the time-versus-error sweep (see `realist::quality::sweep`).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::quality::metrics;
use realist::quality::plane::PlaneSetup;
use realist::quality::sphere::{Shape, SphereSetup};
use realist::quality::sweep::{self, ModelSetup, Subject};
use realist::quality::traced::{self, Light, TracedSetup};
use realist::texture::Filter;

use realist::load::LoadOptions;
use realist::render::{Settings, Shot};
use realist::scenefile::{self, Format, SceneFile};

use super::{load_model, parse_size, NormalArgs};

#[derive(Args)]
pub(crate) struct AccuracyArgs {
    /// A scene file (.toml, .json) or model file, as --scene.
    #[arg(value_name = "SCENE", conflicts_with = "scene")]
    file: Option<String>,
    /// Scene: sphere, cylinder or plane (textured, at a grazing angle), each with an exact
    /// reference; or a model file (glTF, GLB, OBJ) or a scene file (.toml, .json: its
    /// model, camera, lights, materials, fog, tone mapping and sidedness), measured against
    /// the general f64 reference; or `shadows` (one shadow-casting directional light) or
    /// `environment` (a uniform sky alone): objects on a ground plane measured
    /// against the path tracer (the textbook's §9.6), for shadow maps and environment
    /// light without occlusion.
    #[arg(long, default_value = "sphere")]
    scene: String,
    /// With `--scene shadows` or `environment`: this model on the ground instead of the
    /// built-in sphere, torus and cube.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
    /// Samples per pixel side of the reference: a model's f64 reference (default 8 = 64
    /// samples per pixel) or the path tracer's (default 16 = 256 paths per pixel, at most
    /// 128).
    #[arg(long)]
    samples: Option<u32>,
    #[command(flatten)]
    normals: NormalArgs,
    /// Image size WIDTHxHEIGHT (default 1280x720, or a scene file's).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Output folder for results.csv and pareto.png.
    #[arg(long)]
    out: PathBuf,
    /// Timed renders per setting (the median is reported).
    #[arg(long, default_value_t = 7)]
    runs: usize,
}

/// The traced scenes' default size: the path-traced references cost minutes at 1280x720.
const TRACED_SIZE: (u32, u32) = (640, 360);

pub(crate) fn accuracy(args: &AccuracyArgs) -> Result<()> {
    let name = args.file.as_deref().unwrap_or(&args.scene);
    let (w, h) = args.size.unwrap_or(scenefile::DEFAULT_SIZE);
    let samples = args.samples.unwrap_or(8);
    if args.model.is_some() && !matches!(name, "shadows" | "environment") {
        bail!("--model goes with --scene shadows or --scene environment");
    }
    let subject = match name {
        "shadows" | "environment" => {
            let light = if name == "shadows" {
                Light::Shadows
            } else {
                Light::Environment
            };
            let (w, h) = args.size.unwrap_or(TRACED_SIZE);
            let samples = args.samples.unwrap_or(16);
            if !(1..=traced::MAX_SAMPLES).contains(&samples) {
                bail!(
                    "--samples {samples}: the path-traced reference takes 1 to {} paths per pixel side",
                    traced::MAX_SAMPLES
                );
            }
            Subject::Traced(match &args.model {
                Some(path) => {
                    let scene = load_model(path, &args.normals)?;
                    TracedSetup::with_scene(light, scene, w, h, samples)
                }
                None => TracedSetup::standard(light, w, h, samples),
            })
        }
        "sphere" => Subject::Shape(SphereSetup::standard_shape(Shape::Sphere, w, h)),
        "cylinder" => Subject::Shape(SphereSetup::standard_shape(Shape::Cylinder, w, h)),
        "plane" => Subject::Plane(PlaneSetup::standard(w, h)),
        path if Format::of(Path::new(path)).is_some() => {
            Subject::Model(scene_file_setup(Path::new(path), args)?)
        }
        path => {
            let path = Path::new(path);
            if !path.exists() {
                bail!(
                    "--scene {}: not sphere, cylinder or plane, and no such model file",
                    path.display()
                );
            }
            let scene = load_model(path, &args.normals)?;
            Subject::Model(ModelSetup::new(scene, w, h, samples))
        }
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    if let Subject::Traced(t) = &subject {
        say!(
            "references: the path tracer at {} paths per pixel, direct light (exact visibility) and every bounce",
            t.samples * t.samples
        );
    }
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
    filter_summary(rows)?;
    if let Subject::Traced(t) = &subject {
        if let Some(r) = &result.references[traced::Reference::Areas.index()] {
            let n = t.noise(r);
            say!(
                "reference noise: another {} paths a pixel differ from the direct-light reference by mean dE00 {:.4} (rmse {:.5}); errors well above it are the renderer's",
                t.samples * t.samples,
                n.mean_de2000,
                n.rmse
            );
        }
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
    let (w, h) = subject.size();
    let title = format!("{name} at {w}x{h}: time versus error (one knob at a time)");
    let axes = [
        "median render time (ms, log)",
        "mean \u{0394}E00 vs reference (log)",
    ];
    let png = realist::overlay::chart::pareto(&chart_points(rows), &front, &title, axes)
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
            let name = subject.reference_name(index);
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

/// Every texture filter's time and error without supersampling, time relative to
/// trilinear's (when the sweep has filter rows).
fn filter_summary(rows: &[sweep::Row]) -> Result<()> {
    let single: Vec<&sweep::Row> = rows
        .iter()
        .filter(|r| r.knob == "filter" && r.setting.ss == 1 && r.setting.msaa == 1)
        .collect();
    let Some(tri) = single
        .iter()
        .find(|r| r.setting.filter == Some(Filter::Trilinear))
    else {
        return Ok(());
    };
    say!("Texture filters (one sample per pixel; time relative to trilinear):");
    for r in &single {
        let Some(f) = r.setting.filter else { continue };
        say!(
            "  {:<10} {:>8.2} ms  x{:<5.2} mean dE00 {:.4}  rmse {:.5}",
            f.name(),
            r.ms,
            r.ms / tri.ms.max(1e-9),
            r.metrics.mean_de2000,
            r.metrics.rmse
        );
    }
    Ok(())
}

/// The sweep's subject for a scene file: its model with its material overrides applied,
/// its camera and size (`--size` wins), and its lights, fog, tone mapping, sidedness and
/// texture in every render and reference. The sweep varies shading, supersampling,
/// multisampling, sub-pixel bits and filters itself, so the file's values of those are not
/// used; nor are shadows and the ground plane, which the f64 reference does not draw. The
/// file's material variant and hidden parts are applied to the scene itself, so the
/// renders and the reference both draw them.
fn scene_file_setup(path: &Path, args: &AccuracyArgs) -> Result<ModelSetup> {
    let file = SceneFile::read(path)?;
    let opts = LoadOptions {
        normals: args.normals.options()?,
        ..LoadOptions::default()
    };
    let mut scene = file.load_model(&opts)?;
    let settings = file.settings(&scene)?;
    let (w, h) = args
        .size
        .or_else(|| file.size())
        .unwrap_or(scenefile::DEFAULT_SIZE);
    let camera = file.camera(&scene, w as f32 / h as f32)?;
    if settings.ground.is_some() || lights_shadow(&settings.lights) {
        eprintln!(
            "note: {}: shadows and the ground plane are not in the f64 reference; measured without them",
            path.display()
        );
    }
    if !settings.sections.is_empty() {
        eprintln!(
            "note: {}: section planes are not in the f64 reference; measured without them",
            path.display()
        );
    }
    if file.doc.compare.is_some() {
        eprintln!(
            "note: {}: [compare] is ignored; the sweep compares its own settings",
            path.display()
        );
    }
    if let Some(m) = settings.materials.clone() {
        scene.materials = m;
    }
    apply_variant_and_hidden(&mut scene, &settings);
    let mut lights = settings.lights.clone();
    if let realist::render::Lights::Custom { lights, .. } = &mut lights {
        lights.iter_mut().for_each(|l| l.shadow = false);
    }
    let mut setup = ModelSetup::new(scene, w, h, args.samples.unwrap_or(8));
    if let Some(c) = camera {
        setup.camera = c;
    }
    setup.base = Box::new(Shot {
        settings: Settings {
            double_sided: settings.double_sided,
            slots: settings.slots.clone(),
            lights,
            fog: settings.fog,
            tone: settings.tone,
            ..Settings::default()
        },
        ..Shot::default()
    });
    Ok(setup)
}

/// Gives each mesh its material under `settings`' variant and removes the hidden
/// instances (the node tree's instance lists renumbered to match).
fn apply_variant_and_hidden(scene: &mut realist::scene::Scene, settings: &Settings) {
    let variant = settings.variant_index(scene);
    for m in &mut scene.meshes {
        m.material = m.material_in(variant);
    }
    if settings.hidden.is_empty() {
        return;
    }
    let mut kept = 0;
    let renumber: Vec<Option<usize>> = (0..scene.instances.len())
        .map(|k| {
            (!settings.hidden.contains(k)).then(|| {
                kept += 1;
                kept - 1
            })
        })
        .collect();
    let mut k = 0;
    scene.instances.retain(|_| {
        k += 1;
        renumber[k - 1].is_some()
    });
    for node in &mut scene.graph.nodes {
        node.instances = node
            .instances
            .iter()
            .filter_map(|&i| renumber.get(i).copied().flatten())
            .collect();
    }
}

fn lights_shadow(lights: &realist::render::Lights) -> bool {
    matches!(lights, realist::render::Lights::Custom { lights, .. } if lights.iter().any(|l| l.shadow))
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
    realist::color::png::Png::rgb(width, height, &rgb)
        .with_text("Source", "realist bench accuracy")
        .write(path)
        .map_err(anyhow::Error::msg)
}

/// The sweep's rows as chart points: median time against mean ΔE00, coloured by knob,
/// labelled by setting.
fn chart_points(rows: &[sweep::Row]) -> Vec<realist::overlay::chart::ChartPoint> {
    rows.iter()
        .map(|r| realist::overlay::chart::ChartPoint {
            x: r.ms,
            y: r.metrics.mean_de2000,
            series: r.knob,
            label: r.setting.label(),
        })
        .collect()
}
