//! The thumbnail's fixed preset and its two passes.
//!
//! - **View**: the model's bounding sphere (about its bounding box's centre, through its
//!   corners) fills the square image from 35 degrees round and 25 degrees up, the default
//!   three-quarter view of `realist render`. STL and PLY files are taken to be Z-up and
//!   turned to stand Y-up, the others are Y-up (glTF's axes; most OBJ writers follow them).
//! - **Quick preview**, drawn first: the file's own default look without the environment
//!   (textured or Phong under the default light rig; glTF materials in `pbr` under it), one
//!   sample per pixel. The watchdog writes it if the budget runs out during the second pass.
//! - **Thumbnail**: the `pbr` mode under the built-in studio environment (prefiltered here,
//!   beside the preview, without the disk cache: nothing is read or written but the model
//!   and the output), 4x multisampling, and up to 512 pixels drawn at twice the size and
//!   averaged down (2x2 boxes in linear light), so that thin parts and textures hold at 128.
//! - **Transparency**: the background is cleared to alpha 0 and every drawn sample has alpha
//!   1, so a pixel's alpha is the part of it the model covers; its colour is the covered
//!   samples' mean (un-premultiplied).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result};
use glam::Vec4;

use realist::load::{self, LoadOptions};
use realist::render::{Environment, PreparedScene, Renderer, Settings, View};
use realist::scene::{Camera, Scene, Up, DEFAULT_YFOV};
use realist::shade::Shading;
use realist::texture::env::{EnvImage, EnvView, Prefiltered};

use super::guard::Output;

/// The most worker threads: a thumbnail gains little from more, and each thread's stack
/// and allocator arena take address space from the memory budget.
const MAX_THREADS: usize = 8;

/// Address space per worker thread: glibc's allocator reserves up to 64 MiB for each
/// thread's arena, on top of the frame buffers and the model.
const BYTES_PER_THREAD: u64 = 256 << 20;

/// Three-quarter view: degrees round the up axis and above the horizon.
const AZIMUTH: f32 = 35.0;
const ELEVATION: f32 = 25.0;

/// Sizes up to this are drawn at twice the size and averaged down.
const SUPERSAMPLE_UP_TO: u32 = 512;

pub(super) struct Job {
    pub input: PathBuf,
    /// The long (and short: the image is square) side in pixels.
    pub size: u32,
    /// The loaders' memory budget (file, geometry, decoded textures).
    pub max_load_bytes: u64,
    /// The address-space limit: one worker thread per [`BYTES_PER_THREAD`] of it.
    pub memory: u64,
    /// A pause before the full pass (a hidden flag for the watchdog's test).
    pub hold_full_pass: std::time::Duration,
}

impl Job {
    pub(super) fn run(&self, out: &Output) -> Result<()> {
        let threads = std::thread::available_parallelism()
            .map_or(1, std::num::NonZero::get)
            .min(MAX_THREADS)
            .min(usize::try_from(self.memory / BYTES_PER_THREAD).unwrap_or(usize::MAX))
            .max(1);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .context("could not start worker threads")?;
        pool.install(|| self.run_in(out))
    }

    fn run_in(&self, out: &Output) -> Result<()> {
        let scene = self.load()?;
        // The environment is prefiltered while the preview is drawn (after the load, so
        // that a file that cannot be read fails at once).
        let (env, first) = rayon::join(studio, || self.preview(scene, out));
        let (prepared, camera, mut renderer) = first?;
        std::thread::sleep(self.hold_full_pass);
        let scale = if self.size <= SUPERSAMPLE_UP_TO { 2 } else { 1 };
        let full = Settings {
            shading: Some(Shading::Pbr),
            environment: Environment::On(EnvView::new(Arc::new(env))),
            background: Vec4::ZERO,
            msaa: 4,
            ..Settings::default()
        };
        let view = View {
            camera,
            width: self.size * scale,
            height: self.size * scale,
        };
        renderer.render(&prepared, &full, &view);
        let image = read_rgba(&renderer, scale)?;
        out.write(&encode_png(self.size, self.size, &image)?)
    }

    /// Frames the model and draws the quick preview, handed to `out`.
    fn preview(&self, scene: Scene, out: &Output) -> Result<(PreparedScene, Camera, Renderer)> {
        let mut scene = scene;
        stand_up(&mut scene, up_of(&self.input));
        let camera = framing(&scene);
        let prepared = PreparedScene::new(scene);
        let mut renderer = Renderer::new();
        let quick = Settings {
            shading: None,
            environment: Environment::Off,
            background: Vec4::ZERO,
            ..Settings::default()
        };
        let view = View {
            camera: camera.clone(),
            width: self.size,
            height: self.size,
        };
        renderer.render(&prepared, &quick, &view);
        let preview = read_rgba(&renderer, 1)?;
        out.set_preview(encode_png(self.size, self.size, &preview)?);
        Ok((prepared, camera, renderer))
    }

    fn load(&self) -> Result<Scene> {
        let opts = LoadOptions {
            max_bytes: self.max_load_bytes,
            ..LoadOptions::default()
        };
        let scene = load::load(&self.input, &opts)?;
        scene
            .check_drawable(&self.input)
            .map_err(anyhow::Error::msg)?;
        Ok(scene)
    }
}

/// The built-in studio environment at a quarter of its resolution (128x64, 4x4 boxes
/// averaged), prefiltered: a sixteenth of the work of the full image, which matters here
/// as it is done on every run (the disk cache of `realist render` is neither read nor
/// written). Thumbnails show no reflection sharp enough to tell the difference.
fn studio() -> Prefiltered {
    let full = EnvImage::studio();
    let (w, h) = (full.width() as usize, full.height() as usize);
    const K: usize = 4;
    let (sw, sh) = (w / K, h / K);
    let rgb = full.rgb();
    let mut texels = vec![[0f32; 3]; sw * sh];
    for (i, t) in texels.iter_mut().enumerate() {
        let (x, y) = (i % sw, i / sw);
        for dy in 0..K {
            for dx in 0..K {
                let at = ((y * K + dy) * w + x * K + dx) * 3;
                for c in 0..3 {
                    t[c] += rgb[at + c] / (K * K) as f32;
                }
            }
        }
    }
    match EnvImage::from_rgb(sw as u32, sh as u32, texels) {
        Ok(small) => Prefiltered::build(small.with_name("studio")),
        Err(_) => Prefiltered::build(full),
    }
}

/// Z-up for STL and PLY (scans and CAD parts, which mostly lie on their back otherwise),
/// Y-up for the rest.
pub(super) fn up_of(path: &Path) -> Up {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("stl" | "ply") => Up::Z,
        _ => Up::Y,
    }
}

/// Turns a Z-up model so that its up is +Y, the environment's and the camera's (turning
/// the camera instead, as `realist render --up z` does, would light it from the side with
/// the studio's floor and ceiling). Every instance is turned; STL and PLY files, the ones
/// taken as Z-up, have no lights or cameras to turn.
fn stand_up(scene: &mut Scene, up: Up) {
    if up == Up::Y {
        return;
    }
    let turn = glam::Mat4::from_quat(up.to_y_up());
    for inst in &mut scene.instances {
        inst.world = turn * inst.world;
    }
}

/// The camera that frames `scene`'s bounding sphere in a square image from the
/// three-quarter view.
fn framing(scene: &Scene) -> Camera {
    let (lo, hi) = scene
        .bounds()
        .unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::ONE));
    let center = (lo + hi) * 0.5;
    let radius = ((hi - lo) * 0.5).length();
    Camera::frame_sphere_fov(center, radius, 1.0, AZIMUTH, ELEVATION, DEFAULT_YFOV)
}

/// The last frame as straight-alpha 8-bit RGBA (sRGB colour), `scale` x `scale` pixels
/// averaged into one.
fn read_rgba(renderer: &Renderer, scale: u32) -> Result<Vec<u8>> {
    let fb = renderer
        .target()
        .context("no frame was rendered")?
        .resolve();
    let (w, h) = (fb.width / scale, fb.height / scale);
    let lut = realist::color::Srgb8Table::get();
    let mut out = Vec::with_capacity(w as usize * h as usize * 4);
    let n = (scale * scale) as f32;
    for y in 0..h {
        for x in 0..w {
            let mut sum = Vec4::ZERO;
            for dy in 0..scale {
                let row = ((y * scale + dy) * fb.width + x * scale) as usize;
                for c in &fb.color[row..row + scale as usize] {
                    // Colours are premultiplied by coverage here (cleared to 0); NaN is
                    // nothing drawn.
                    let c = Vec4::select(c.is_nan_mask(), Vec4::ZERO, *c);
                    sum += c.clamp(Vec4::ZERO, Vec4::new(f32::MAX, f32::MAX, f32::MAX, 1.0));
                }
            }
            let alpha = sum.w / n;
            let rgb = if sum.w > 0.0 {
                sum.truncate() / sum.w
            } else {
                glam::Vec3::ZERO
            };
            out.extend_from_slice(&[
                lut.encode(rgb.x),
                lut.encode(rgb.y),
                lut.encode(rgb.z),
                (alpha.clamp(0.0, 1.0) * 255.0 + 0.5) as u8,
            ]);
        }
    }
    Ok(out)
}

/// RGBA8 pixels as a PNG file's bytes.
pub(super) fn encode_png(w: u32, h: u32, rgba: &[u8]) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.add_text_chunk("Software".into(), "realist thumbnail".into())
            .context("PNG text")?;
        let mut writer = enc.write_header().context("PNG header")?;
        writer.write_image_data(rgba).context("PNG data")?;
        writer.finish().context("PNG end")?;
    }
    Ok(bytes)
}
