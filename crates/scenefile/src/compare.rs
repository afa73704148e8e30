//! Comparison layouts: `[compare]` renders the scene once per `[[compare.variant]]` (each
//! overriding the shading mode, materials, texture filter, texture, bump map and generated
//! texture coordinates of the file's settings), with the same camera
//! and size, and lays the frames out in a grid, `columns` per row in the file's order, each
//! with its label centred in a strip below it and an optional title strip above the grid.
//! Labels are drawn by [`crate::overlay`] (outlines of the embedded DejaVu Sans).

use super::convert::{self, Bad};
use super::schema::CompareSpec;
use super::{SceneFile, SceneFileError, MAX_PIXELS, MAX_SIDE};
use crate::overlay::{Canvas, Color, HAlign, RgbaImage, VAlign};
use crate::render::{PreparedScene, Renderer, Settings, View};
use crate::scene::Scene;

/// Default label size in pixels (em size).
pub const LABEL_SIZE: f32 = 20.0;

/// One labelled variant.
#[derive(Clone, Debug)]
pub struct Variant {
    pub label: String,
    pub settings: Settings,
    /// Texture coordinates generated for this variant (the file's own `uv` otherwise).
    pub uv: Option<crate::schema::UvChoice>,
}

/// A resolved `[compare]`.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub title: Option<String>,
    /// Cells per row.
    pub columns: u32,
    /// Label em size in pixels.
    pub label_size: f32,
    pub variants: Vec<Variant>,
}

/// Where everything goes, in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Layout {
    pub columns: u32,
    pub rows: u32,
    pub cell: (u32, u32),
    pub label_h: u32,
    pub title_h: u32,
    pub width: u32,
    pub height: u32,
}

impl Layout {
    /// The layout of `spec`'s variants in cells of `cell` pixels; `(key, reason)` if it
    /// does not fit [`MAX_SIDE`] and [`MAX_PIXELS`].
    pub(super) fn new(spec: &CompareSpec, cell: (u32, u32)) -> Result<Layout, Bad> {
        let n = spec.variant.len().max(1) as u32;
        let label_size = match spec.label_size {
            Some(s) => convert::ranged("label_size", s, 6.0, 200.0)?,
            None => LABEL_SIZE,
        };
        let columns = spec.columns.unwrap_or(n.min(4));
        if !(1..=n).contains(&columns) {
            return Err(convert::bad(
                "columns",
                format!("{columns} is not between 1 and the number of variants ({n})"),
            ));
        }
        Ok(Self::sized(
            n,
            columns,
            label_size,
            spec.title.is_some(),
            cell,
        ))
        .and_then(|l| l.check())
    }

    fn sized(n: u32, columns: u32, label_size: f32, title: bool, cell: (u32, u32)) -> Layout {
        let rows = n.div_ceil(columns);
        let label_h = (label_size * 1.8).ceil() as u32;
        let title_h = if title {
            (label_size * 1.25 * 1.8).ceil() as u32
        } else {
            0
        };
        Layout {
            columns,
            rows,
            cell,
            label_h,
            title_h,
            width: cell.0.saturating_mul(columns),
            height: (cell.1 + label_h)
                .saturating_mul(rows)
                .saturating_add(title_h),
        }
    }

    fn check(self) -> Result<Layout, Bad> {
        let px = u64::from(self.width) * u64::from(self.height);
        if self.width > MAX_SIDE || self.height > MAX_SIDE || px > MAX_PIXELS {
            return Err(convert::bad(
                "variant",
                format!(
                    "the grid would be {}x{} pixels; at most {MAX_SIDE} a side and {MAX_PIXELS} pixels (reduce size or columns)",
                    self.width, self.height
                ),
            ));
        }
        Ok(self)
    }

    /// Top-left corner of cell `i`.
    fn origin(&self, i: u32) -> (u32, u32) {
        let (c, r) = (i % self.columns, i / self.columns);
        (
            c * self.cell.0,
            self.title_h + r * (self.cell.1 + self.label_h),
        )
    }
}

impl SceneFile {
    /// The file's `[compare]`, each variant's settings being `base` with its overrides
    /// (materials applied to `base`'s overrides, else to `scene`'s materials).
    ///
    /// # Errors
    /// A variant's material override the model cannot take.
    pub fn comparison(
        &self,
        scene: &Scene,
        base: &Settings,
    ) -> Result<Option<Comparison>, SceneFileError> {
        let Some(spec) = &self.doc.compare else {
            return Ok(None);
        };
        let mut variants = Vec::with_capacity(spec.variant.len());
        for (i, v) in spec.variant.iter().enumerate() {
            let mut settings = base.clone();
            if let Some(m) = v.shading {
                settings.shading = Some(m.0);
            }
            if let Some(f) = v.filter {
                settings.filter = Some(f.0);
            }
            if let Some(b) = v.vertex_blinn {
                settings.vertex_lighting.blinn = b;
            }
            if let Some(p) = v.flat_last_vertex {
                settings.vertex_lighting.provoking_vertex = p;
            }
            self.apply_maps(
                &format!("compare.variant[{i}]."),
                v.texture.as_deref(),
                v.bump.as_deref(),
                v.bump_scale,
                &mut settings.slots,
            )?;
            if !v.material.is_empty() {
                let mut materials = base
                    .materials
                    .clone()
                    .unwrap_or_else(|| scene.materials.clone());
                convert::materials(
                    &format!("compare.variant[{i}].material"),
                    &v.material,
                    &mut materials,
                )
                .map_err(|(k, r)| self.invalid(k, r))?;
                settings.materials = Some(materials);
            }
            variants.push(Variant {
                label: v.label.clone(),
                settings,
                uv: v.uv.map(|u| u.0),
            });
        }
        let layout = Layout::new(spec, self.size().unwrap_or(super::DEFAULT_SIZE))
            .map_err(|(k, r)| self.invalid(format!("compare.{k}"), r))?;
        Ok(Some(Comparison {
            title: spec.title.clone(),
            columns: layout.columns,
            label_size: spec.label_size.map_or(LABEL_SIZE, |s| s as f32),
            variants,
        }))
    }
}

/// An sRGB8 RGB image, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Comparison {
    /// Renders every variant of `scene` from `view` with one renderer and lays them out
    /// with their labels (see [`compose`]).
    #[must_use]
    pub fn render(&self, scene: &PreparedScene, view: &View) -> (RgbImage, crate::raster::Stats) {
        let mut renderer = Renderer::new();
        let mut stats = crate::raster::Stats::default();
        let mut cells = Vec::with_capacity(self.variants.len());
        for v in &self.variants {
            // A variant with generated texture coordinates draws a copy of the scene with
            // them; `uv = "mesh"` draws the scene as loaded.
            let own;
            let scene = match v.uv.and_then(|u| u.generator()) {
                Some(g) => {
                    let mut copy = Scene::clone(scene.scene());
                    copy.apply_uv_generator(&g);
                    own = PreparedScene::new(copy);
                    &own
                }
                None => scene,
            };
            stats.add(&renderer.render(scene, &v.settings, view).stats);
            if let Some(t) = renderer.target() {
                cells.push(t.to_srgb8());
            }
        }
        (compose(self, (view.width, view.height), &cells), stats)
    }
}

/// Lays out `cells` (sRGB8 RGB frames of `cell` pixels, one per variant in order) with
/// their labels on a dark grey background.
#[must_use]
pub fn compose(cmp: &Comparison, cell: (u32, u32), cells: &[Vec<u8>]) -> RgbImage {
    let layout = Layout::sized(
        cmp.variants.len().max(1) as u32,
        cmp.columns.max(1),
        cmp.label_size,
        cmp.title.is_some(),
        cell,
    );
    let mut canvas = Canvas::new(layout.width, layout.height);
    canvas.background(Color::rgb(32, 32, 36));
    let white = Color::rgb(235, 235, 235);
    if let Some(title) = &cmp.title {
        canvas.text(
            title,
            layout.width as f32 * 0.5,
            layout.title_h as f32 * 0.5,
            cmp.label_size * 1.25,
            white,
            HAlign::Center,
            VAlign::Middle,
        );
    }
    for (i, (v, rgb)) in cmp.variants.iter().zip(cells).enumerate() {
        let (x, y) = layout.origin(i as u32);
        let pixels = rgb
            .chunks_exact(3)
            .map(|p| [p[0], p[1], p[2], 255])
            .collect();
        canvas.image(
            x as f32,
            y as f32,
            RgbaImage {
                width: cell.0,
                height: cell.1,
                pixels,
            },
        );
        canvas.text(
            &v.label,
            x as f32 + cell.0 as f32 * 0.5,
            (y + cell.1) as f32 + layout.label_h as f32 * 0.5,
            cmp.label_size,
            white,
            HAlign::Center,
            VAlign::Middle,
        );
    }
    let pixmap = canvas.to_pixmap();
    // Opaque background: premultiplied and straight colours agree.
    let rgb = pixmap
        .pixels()
        .iter()
        .flat_map(|p| [p.red(), p.green(), p.blue()])
        .collect();
    RgbImage {
        width: layout.width,
        height: layout.height,
        rgb,
    }
}
