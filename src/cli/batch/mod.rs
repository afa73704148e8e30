//! `realist batch`: a still, a turntable or a thumbnail of every model in folders or a list,
//! each rendered by a process of its own (this program's `render` or `thumbnail`) with a
//! time limit, so that a model that hangs, panics, aborts or leaks is one failed item.
//!
//! Outputs mirror the inputs' relative paths under `--out`; each item's files are written
//! into a temporary folder and renamed into place only when its process succeeded. A
//! manifest line per finished item (appended and flushed at once) makes a run resumable: a
//! restart skips the items that a manifest in the folder records ok and whose outputs exist.
//! `--shard I/N` takes every N-th item of the one sorted list, for job arrays.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{bail, Context, Result};
use clap::{ArgGroup, Args, Parser};

mod child;
mod items;
mod manifest;
mod progress;
#[cfg(test)]
mod tests;

use child::{Ended, Running};
use items::{Item, Shard};
use manifest::{Manifest, Record};
use progress::Progress;

use super::render::RenderArgs;
use super::sequence::{frame_name, MAX_FRAMES};

/// Exit status when some items failed (the others are done): neither 1, an error of the
/// command, nor 2, a mistake in its arguments.
const FAILED_ITEMS: i32 = 3;

/// Default thumbnail size (pixels on the long side), the freedesktop "large" size.
const THUMBNAIL_SIZE: u32 = 256;

#[derive(Args)]
#[command(
    group(ArgGroup::new("kind").args(["turntable", "still", "thumbnail"])),
    after_help = "Exit status: 0 when every item is ok, 3 when some failed (their manifest \
                  lines say why; the others are done), 1 or 2 for a mistake in the command."
)]
pub(crate) struct BatchArgs {
    /// Folders (searched recursively for .gltf .glb .obj .stl .ply files; symbolic links to
    /// folders are not followed) and model files.
    #[arg(value_name = "INPUT", required_unless_present = "list")]
    inputs: Vec<PathBuf>,
    /// A file naming models, one path per line (lines starting with # are comments);
    /// relative paths are relative to the current folder.
    #[arg(long, value_name = "FILE")]
    list: Option<PathBuf>,
    /// N frames around each model, as `realist render --turntable N` makes them
    /// (DIR/turntable-0.png ...).
    #[arg(long, value_name = "N")]
    turntable: Option<u32>,
    /// One image of each model (DIR/still.png): the default.
    #[arg(long)]
    still: bool,
    /// A thumbnail of each model, as `realist thumbnail --size N` makes it
    /// (DIR/thumbnail-N.png).
    #[arg(long)]
    thumbnail: bool,
    /// Image size WIDTHxHEIGHT of stills and turntables (default 1280x720); with
    /// --thumbnail, N pixels on the long side (default 256).
    #[arg(long, value_name = "WxH|N")]
    size: Option<String>,
    /// The shading mode of each render (as `realist render --shading`).
    #[arg(long)]
    shading: Option<String>,
    /// The world's up axis of each render, y or z (as `realist render --up`).
    #[arg(long, value_name = "y|z")]
    up: Option<String>,
    /// Output folder: each model's images go to OUT/its path without the extension/, and
    /// the manifest to OUT/manifest.jsonl (OUT/manifest.shard-I-of-N.jsonl for a shard).
    #[arg(long, value_name = "DIR", default_value = "realist-batch")]
    out: PathBuf,
    /// Render only shard I of N (1-based): item k of the sorted list (0-based) is shard
    /// (k mod N) + 1's. Every shard lists the same items, so N runs with I = 1..N (a job
    /// array) together render each item once.
    #[arg(long, value_name = "I/N", value_parser = items::parse_shard)]
    shard: Option<Shard>,
    /// Items rendered at once, each by its own process (default 1: each render already uses
    /// every core). With more, each process gets cores/N threads unless --threads is given.
    #[arg(long, value_name = "N", default_value_t = 1)]
    jobs: usize,
    /// Worker threads of each item's render (default: all cores over --jobs).
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
    /// Seconds an item may take before its process is killed and it counts as failed
    /// (status timeout).
    #[arg(long, value_name = "SECONDS", default_value_t = 120.0)]
    timeout: f64,
    /// Further options for each `realist render` (after --), e.g. -- --msaa 4 --camera 30,20.
    #[arg(last = true, value_name = "RENDER_OPTIONS")]
    render: Vec<OsString>,
}

/// What each item makes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Still,
    Turntable(u32),
    /// The long side in pixels.
    Thumbnail(u32),
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Still => "still",
            Kind::Turntable(_) => "turntable",
            Kind::Thumbnail(_) => "thumbnail",
        }
    }

    /// The file names an item's process writes, in order.
    fn outputs(self) -> Vec<String> {
        match self {
            Kind::Still => vec!["still.png".into()],
            Kind::Turntable(n) => (0..n as usize)
                .map(|i| frame_name("turntable-{}.png", i, n as usize - 1))
                .collect(),
            Kind::Thumbnail(s) => vec![format!("thumbnail-{s}.png")],
        }
    }
}

/// `realist render`'s options, to check the ones passed on before any item runs.
#[derive(Parser)]
#[command(name = "realist render")]
struct RenderCheck {
    #[command(flatten)]
    args: RenderArgs,
}

/// The settings of the whole run.
struct Plan {
    kind: Kind,
    exe: PathBuf,
    /// Options of each item's process (before the output and the model).
    options: Vec<OsString>,
    out: PathBuf,
    timeout: Duration,
    jobs: usize,
}

impl Plan {
    fn new(args: &BatchArgs) -> Result<Self> {
        let kind = match (args.turntable, args.thumbnail) {
            (Some(n), _) if !(1..=MAX_FRAMES).contains(&n) => {
                bail!("--turntable {n}: expected 1 to {MAX_FRAMES} frames")
            }
            (Some(n), _) => Kind::Turntable(n),
            (None, true) => Kind::Thumbnail(match &args.size {
                None => THUMBNAIL_SIZE,
                Some(s) => s.trim().parse().ok().filter(|&n| n > 0).with_context(|| {
                    format!(
                        "--size {s}: with --thumbnail, give one number, the long side in pixels"
                    )
                })?,
            }),
            (None, false) => Kind::Still,
        };
        if !(args.timeout.is_finite() && args.timeout > 0.0 && args.timeout < 1e9) {
            bail!(
                "--timeout {}: expected a positive number of seconds",
                args.timeout
            );
        }
        if args.jobs == 0 {
            bail!("--jobs 0: expected at least 1");
        }
        let exe =
            std::env::current_exe().context("could not find this program to run each item")?;
        let mut options: Vec<OsString> = Vec::new();
        if let Kind::Thumbnail(s) = kind {
            if args.shading.is_some() || args.up.is_some() || !args.render.is_empty() {
                bail!("--thumbnail renders with the thumbnail's own preset: --shading, --up and render options do not apply");
            }
            if !has_thumbnail(&exe) {
                bail!("--thumbnail: this realist has no `thumbnail` command");
            }
            options.extend(["thumbnail".into(), "--size".into(), s.to_string().into()]);
        } else {
            options.push("render".into());
            if let Kind::Turntable(n) = kind {
                options.extend(["--turntable".into(), n.to_string().into()]);
            }
            if let Some(s) = &args.size {
                options.extend(["--size".into(), s.into()]);
            }
            if let Some(s) = &args.shading {
                options.extend(["--shading".into(), s.into()]);
            }
            if let Some(u) = &args.up {
                options.extend(["--up".into(), u.into()]);
            }
            let cores = std::thread::available_parallelism().map_or(1, usize::from);
            let threads = args
                .threads
                .or((args.jobs > 1).then(|| (cores / args.jobs).max(1)));
            if let Some(t) = threads {
                options.extend(["--threads".into(), t.to_string().into()]);
            }
            options.extend(args.render.iter().cloned());
            check_render_options(&options, kind)?;
        }
        Ok(Self {
            kind,
            exe,
            options,
            out: args.out.clone(),
            timeout: Duration::from_secs_f64(args.timeout),
            jobs: args.jobs,
        })
    }

    /// The arguments of `item`'s process, writing into `temp`.
    fn child_args(&self, item: &Item, temp: &Path) -> Vec<OsString> {
        let mut a = self.options.clone();
        let first = temp.join(match self.kind {
            Kind::Turntable(_) => "turntable-{}.png".to_string(),
            k => k.outputs().remove(0),
        });
        match self.kind {
            Kind::Thumbnail(_) => {
                a.push("--".into());
                a.push(item.path.clone().into());
                a.push(first.into());
            }
            _ => {
                a.extend(["-o".into(), first.into(), "--".into()]);
                a.push(item.path.clone().into());
            }
        }
        a
    }
}

/// Whether this program has the `thumbnail` command (`realist help thumbnail` succeeds; `realist
/// thumbnail --help` would print the viewer's help, taking `thumbnail` for a model name).
fn has_thumbnail(exe: &Path) -> bool {
    std::process::Command::new(exe)
        .args(["help", "thumbnail"])
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Parses the render options as `realist render` would (with a stand-in model and output),
/// so that a mistake in them is one error now, not a failed item per model.
fn check_render_options(options: &[OsString], kind: Kind) -> Result<()> {
    let mut argv: Vec<OsString> = options.to_vec();
    let pattern = match kind {
        Kind::Turntable(_) => "frame-{}.png",
        _ => "still.png",
    };
    argv.extend(["-o".into(), pattern.into(), "--".into(), "model.obj".into()]);
    let parsed = RenderCheck::try_parse_from(&argv).map_err(|e| {
        let text = e.to_string();
        let first = text
            .lines()
            .next()
            .unwrap_or("")
            .trim_start_matches("error: ");
        anyhow::anyhow!("the options for each render: {first}")
    })?;
    let r = parsed.args;
    if r.sequence.animated.is_some() {
        bail!("the options for each render: --animated is not for batches (use --turntable N)");
    }
    if r.stats {
        bail!("the options for each render: --stats is not for batches");
    }
    Ok(())
}

pub(crate) fn batch(args: &BatchArgs) -> Result<()> {
    let plan = Plan::new(args)?;
    let cwd = std::env::current_dir().context("could not read the current folder")?;
    let (items, warnings) = items::collect(&args.inputs, args.list.as_deref(), &cwd)?;
    for w in warnings {
        eprintln!("warning: {w}");
    }
    let shard = args.shard.unwrap_or(Shard { index: 1, count: 1 });
    let out = &plan.out;
    std::fs::create_dir_all(out)
        .with_context(|| format!("could not create the output folder {}", out.display()))?;
    let (records, unreadable) = manifest::finished(out)?;
    if unreadable > 0 {
        eprintln!("warning: {unreadable} manifest line(s) in {} could not be read (a run cut short?); their items are done again", out.display());
    }
    let mine: Vec<usize> = (0..items.len()).filter(|&k| shard.owns(k)).collect();
    let todo: Vec<usize> = mine
        .iter()
        .copied()
        .filter(|&k| {
            let it = &items[k];
            !manifest::is_done(records.get(&it.rel), &expected(&plan, it), out)
        })
        .collect();
    let skipped = mine.len() - todo.len();
    let of = if shard.count > 1 {
        format!(
            ", shard {}/{}: {} of them",
            shard.index,
            shard.count,
            mine.len()
        )
    } else {
        String::new()
    };
    eprintln!(
        "batch: {} model(s){of}; {skipped} skipped (already done); {} to render into {}",
        items.len(),
        todo.len(),
        out.display()
    );
    let partial = out.join(".partial");
    let temp_root = partial.join(shard.tag());
    // What a killed run of this shard left half-written.
    let _ = std::fs::remove_dir_all(&temp_root);
    std::fs::create_dir_all(&temp_root)
        .with_context(|| format!("could not create {}", temp_root.display()))?;
    let mut manifest = Manifest::open(out.join(shard.manifest_name()))?;
    let mut progress = Progress::new(mine.len(), skipped);
    progress.start();
    let mut running: Vec<Running> = Vec::new();
    let result = run_items(
        &plan,
        &items,
        &todo,
        &temp_root,
        &mut manifest,
        &mut progress,
        &mut running,
    );
    progress.finish();
    for r in &mut running {
        r.kill();
    }
    result?;
    let _ = std::fs::remove_dir_all(&temp_root);
    let _ = std::fs::remove_dir(&partial);
    let failed = progress.failed();
    let ok = progress.finished() - failed;
    eprintln!(
        "batch: {ok} ok, {failed} failed, {skipped} skipped (already done); manifest {}",
        manifest.path.display()
    );
    if failed > 0 {
        eprintln!(
            "realist: {failed} of {} item(s) failed (their lines in {} say why)",
            mine.len(),
            manifest.path.display()
        );
        std::process::exit(FAILED_ITEMS);
    }
    Ok(())
}

/// `item`'s outputs relative to the output folder.
fn expected(plan: &Plan, item: &Item) -> Vec<String> {
    plan.kind
        .outputs()
        .into_iter()
        .map(|name| format!("{}/{name}", item.dir))
        .collect()
}

/// Runs the items `todo` (indices into `items`), `plan.jobs` at a time, recording each.
fn run_items(
    plan: &Plan,
    items: &[Item],
    todo: &[usize],
    temp_root: &Path,
    manifest: &mut Manifest,
    progress: &mut Progress,
    running: &mut Vec<Running>,
) -> Result<()> {
    let mut next = 0;
    loop {
        while running.len() < plan.jobs && next < todo.len() {
            let k = todo[next];
            next += 1;
            let item = &items[k];
            if let Some(problem) = &item.problem {
                record(
                    plan,
                    item,
                    "failed",
                    0.0,
                    Vec::new(),
                    Some(problem.clone()),
                    manifest,
                    progress,
                )?;
                continue;
            }
            let temp = temp_root.join(format!("{}-{k}", std::process::id()));
            let argv = plan.child_args(item, &temp);
            let started = std::fs::create_dir_all(&temp)
                .with_context(|| format!("could not create {}", temp.display()))
                .and_then(|()| Running::start(k, temp, &plan.exe, &argv));
            match started {
                Ok(r) => running.push(r),
                Err(e) => {
                    let msg = format!("{}: {e:#}", item.path.display());
                    record(
                        plan,
                        item,
                        "failed",
                        0.0,
                        Vec::new(),
                        Some(msg),
                        manifest,
                        progress,
                    )?;
                }
            }
        }
        if running.is_empty() && next >= todo.len() {
            return Ok(());
        }
        let mut any = false;
        let mut i = 0;
        while i < running.len() {
            match running[i].poll(plan.timeout)? {
                None => i += 1,
                Some(ended) => {
                    any = true;
                    let r = running.swap_remove(i);
                    finish(plan, &items[r.index], r, ended, manifest, progress)?;
                }
            }
        }
        if !any {
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}

/// Records an item whose process ended: its outputs renamed into place when it succeeded.
fn finish(
    plan: &Plan,
    item: &Item,
    r: Running,
    ended: Ended,
    manifest: &mut Manifest,
    progress: &mut Progress,
) -> Result<()> {
    let seconds = r.elapsed().as_secs_f64();
    let names_file = |msg: String| {
        let p = item.path.display().to_string();
        if msg.contains(&p) {
            msg
        } else {
            format!("{p}: {msg}")
        }
    };
    let (status, outputs, error) = match ended {
        Ended::Ok => match place(plan, item, &r.temp) {
            Ok(outputs) => ("ok", outputs, None),
            Err(e) => ("failed", Vec::new(), Some(names_file(format!("{e:#}")))),
        },
        Ended::Failed(msg) => ("failed", Vec::new(), Some(names_file(msg))),
        Ended::Timeout => (
            "timeout",
            Vec::new(),
            Some(names_file(format!(
                "still running after {} s (--timeout), killed",
                plan.timeout.as_secs_f64()
            ))),
        ),
    };
    let _ = std::fs::remove_dir_all(&r.temp);
    record(
        plan, item, status, seconds, outputs, error, manifest, progress,
    )
}

/// Moves an item's files from `temp` to its folder (each by a rename, so a file in the
/// output folder is always whole): the outputs relative to the output folder.
fn place(plan: &Plan, item: &Item, temp: &Path) -> Result<Vec<String>> {
    let names = plan.kind.outputs();
    for n in &names {
        if !temp.join(n).is_file() {
            bail!("the render ended without writing {n}");
        }
    }
    let dir = plan.out.join(&item.dir);
    std::fs::create_dir_all(&dir).with_context(|| format!("could not create {}", dir.display()))?;
    for n in &names {
        std::fs::rename(temp.join(n), dir.join(n))
            .with_context(|| format!("could not move the image into {}", dir.display()))?;
    }
    Ok(expected(plan, item))
}

#[allow(clippy::too_many_arguments)]
fn record(
    plan: &Plan,
    item: &Item,
    status: &str,
    seconds: f64,
    outputs: Vec<String>,
    error: Option<String>,
    manifest: &mut Manifest,
    progress: &mut Progress,
) -> Result<()> {
    let r = Record {
        item: item.rel.clone(),
        kind: plan.kind.name().into(),
        status: status.into(),
        seconds: (seconds * 1000.0).round() / 1000.0,
        outputs,
        error,
    };
    manifest.append(&r)?;
    progress.item(&r.item, status, seconds, r.error.as_deref());
    Ok(())
}
