//! `realist thumbnail`: a PNG thumbnail of a model as the freedesktop thumbnail specification
//! asks (the long side `--size` pixels, a transparent background), made to run inside a file
//! manager's sandbox (GNOME's bubblewrap and seccomp filter: no display, no GPU, no `$HOME`),
//! within a wall-clock budget and a memory budget, writing nothing but its output.
//!
//! - [`draw`]: the fixed preset (framing, view, up axis, shading) and the two passes.
//! - [`guard`]: the budgets (the watchdog, the address-space limit) and the atomic write.
//! - [`install`]: the `.thumbnailer` file and the shared-mime-info package.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::Args;

mod draw;
mod guard;
mod install;

/// The sizes the freedesktop specification names (normal, large, x-large, xx-large); any
/// size from [`MIN_SIZE`] to [`MAX_SIZE`] is accepted.
const SPEC_SIZES: [u32; 4] = [128, 256, 512, 1024];
const MIN_SIZE: u32 = 16;
const MAX_SIZE: u32 = 1024;

#[derive(Args)]
#[command(after_help = AFTER_HELP)]
pub(crate) struct ThumbnailArgs {
    /// The model (.gltf, .glb, .obj, .stl, .ply). Scene files (.toml, .json) are not
    /// thumbnailed.
    #[arg(required_unless_present_any = ["install", "uninstall"])]
    input: Option<PathBuf>,
    /// The PNG to write (atomically: a temporary file in the same folder, then renamed).
    #[arg(required_unless_present_any = ["install", "uninstall"])]
    output: Option<PathBuf>,
    /// The long side in pixels: 128, 256, 512 or 1024 as the freedesktop specification
    /// names them, or any size from 16 to 1024.
    #[arg(long, short, default_value_t = 256, value_parser = parse_size)]
    size: u32,
    /// Wall-clock budget in seconds. When it runs out, the quick preview (drawn first,
    /// without the environment or anti-aliasing) is written if there is one and the exit status is 0; if the model was
    /// still loading, nothing is written and the exit status is 1.
    #[arg(long, value_name = "SECONDS", default_value_t = 5.0, value_parser = parse_budget)]
    budget: f64,
    /// Memory budget in MiB: the process's address space is limited to it (RLIMIT_AS; the
    /// allocator reserves some for each worker thread, one thread per 256 MiB), and a model
    /// whose data (file, geometry, textures) would need more than half of it is refused with
    /// a message before it is read. Going past the limit anyway ends the process (SIGABRT).
    #[arg(long, value_name = "MIB", default_value_t = 2048, value_parser = parse_memory)]
    memory: u64,
    /// Install the thumbnailer: `realist.thumbnailer` (in /usr/share/thumbnailers, or the
    /// user's data folder with --user) naming this binary, and a shared-mime-info package for
    /// the model formats, then run update-mime-database if it is there.
    #[arg(long, conflicts_with_all = ["input", "output", "uninstall"])]
    install: bool,
    /// Remove what --install wrote (with --user: from the user's data folder).
    #[arg(long, conflicts_with_all = ["input", "output"])]
    uninstall: bool,
    /// With --install or --uninstall: $XDG_DATA_HOME (default ~/.local/share) instead of
    /// /usr/share.
    #[arg(long)]
    user: bool,
    /// For tests of the watchdog: wait this many seconds before the full pass.
    #[arg(long, hide = true, value_name = "SECONDS", default_value_t = 0.0)]
    hold_full_pass: f64,
}

const AFTER_HELP: &str = "\
The thumbnail is the model alone on a transparent background, seen from the front, right and \
above (35 degrees round, 25 up), framed by its bounding sphere, in the pbr mode under the \
built-in studio environment. STL and PLY files are taken to be Z-up (most are scans or CAD \
parts), the others Y-up. Exit status 0: the PNG is written. Anything else: nothing is \
written (the file manager then records the file as failed and does not try again).

Only the model formats are registered by --install (model/gltf+json, model/gltf-binary, \
model/obj, model/stl, application/x-ply); scene files (.toml, .json) have generic types and \
are not claimed.";

fn parse_size(s: &str) -> Result<u32, String> {
    let n: u32 = s
        .trim()
        .parse()
        .map_err(|_| format!("bad size '{s}' (expected pixels, e.g. 256)"))?;
    if !(MIN_SIZE..=MAX_SIZE).contains(&n) {
        return Err(format!(
            "size {n}: expected {MIN_SIZE} to {MAX_SIZE} pixels (the specification's sizes \
             are {SPEC_SIZES:?})"
        ));
    }
    Ok(n)
}

fn parse_budget(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 3600.0 => Ok(v),
        _ => Err(format!(
            "bad budget '{s}' (expected seconds, more than 0, at most 3600)"
        )),
    }
}

fn parse_memory(s: &str) -> Result<u64, String> {
    match s.trim().parse::<u64>() {
        Ok(v) if (512..=1 << 20).contains(&v) => Ok(v),
        _ => Err(format!(
            "bad memory budget '{s}' (expected MiB, 512 to 1048576)"
        )),
    }
}

pub(crate) fn thumbnail(args: &ThumbnailArgs) -> Result<()> {
    if args.install {
        return install::install(args.user);
    }
    if args.uninstall {
        return install::uninstall(args.user);
    }
    let (Some(input), Some(output)) = (&args.input, &args.output) else {
        bail!("thumbnail: INPUT and OUTPUT are required");
    };
    let start = Instant::now();
    let memory = args.memory << 20;
    guard::limit_address_space(memory)?;
    let out = Arc::new(guard::Output::new(output.clone()));
    let deadline = start + Duration::from_secs_f64(args.budget);
    let watchdog = guard::watchdog(Arc::clone(&out), deadline, input.display().to_string());
    let job = draw::Job {
        input: input.clone(),
        size: args.size,
        // The rest of the memory is the renderer's, the decoder's and the threads'.
        max_load_bytes: memory / 2,
        memory,
        hold_full_pass: Duration::try_from_secs_f64(args.hold_full_pass).unwrap_or_default(),
    };
    // A panic is caught here (the release profile unwinds): the message names the file
    // and the exit status is 1; the output is left untouched.
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| job.run(&out)));
    watchdog.finish();
    match result {
        Ok(r) => r.context("thumbnail"),
        Err(_) => bail!(
            "no thumbnail of {}: internal error (a panic, reported above)",
            input.display()
        ),
    }
}
