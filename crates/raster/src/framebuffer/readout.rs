//! Reading a target out: sRGB8 and RGBA8 pixels (through a colour map), depth, one pixel, the resolve to a framebuffer.

use super::*;

impl Target {
    /// 8-bit sRGB-encoded RGB, row-major, straight from the tiles (in parallel over tile
    /// rows); out-of-range values are clamped and NaN becomes 0.
    ///
    /// A row of a tile is encoded a plane at a time: the table indices of its red, green
    /// and blue values first (a loop the compiler vectorises), then the table lookups.
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        let lut = crate::color::Srgb8Table::get();
        let entries = lut.entries();
        let row_bytes = self.width as usize * 3;
        let mut out = vec![0u8; row_bytes * self.height as usize];
        let tiles_x = self.tiles_x as usize;
        out.par_chunks_mut(row_bytes * TILE as usize)
            .zip(self.tiles.par_chunks(tiles_x.max(1)))
            .for_each(|(band, row)| {
                let mut index = [[0u32; TILE as usize]; 3];
                for t in row {
                    let (x0, w) = (t.x0 as usize, t.w as usize);
                    if let Some(c) = t.pending_clear {
                        let rgb = [lut.encode(c.x), lut.encode(c.y), lut.encode(c.z)];
                        for y in 0..t.h as usize {
                            band[y * row_bytes + x0 * 3..][..w * 3]
                                .chunks_exact_mut(3)
                                .for_each(|px| px.copy_from_slice(&rgb));
                        }
                        continue;
                    }
                    let samples = t.samples as usize;
                    let mut mean = [0f32; TILE as usize];
                    for y in 0..t.h as usize {
                        for (plane, index) in index.iter_mut().enumerate() {
                            let at = |s: usize| {
                                &t.color[(4 * s + plane) * TILE_PIXELS + y * TILE as usize..][..w]
                            };
                            let src = if samples == 1 {
                                at(0)
                            } else {
                                // The average of the samples, as `Tile::stored` takes it.
                                mean[..w].fill(0.0);
                                for s in 0..samples {
                                    for (m, &v) in mean.iter_mut().zip(at(s)) {
                                        *m += v;
                                    }
                                }
                                let k = samples as f32;
                                mean[..w].iter_mut().for_each(|m| *m /= k);
                                &mean[..w]
                            };
                            for (i, &v) in index.iter_mut().zip(src) {
                                *i = crate::color::Srgb8Table::index(v);
                            }
                        }
                        let dst = &mut band[y * row_bytes + x0 * 3..][..w * 3];
                        for (x, px) in dst.chunks_exact_mut(3).enumerate() {
                            px[0] = entries[index[0][x] as usize];
                            px[1] = entries[index[1][x] as usize];
                            px[2] = entries[index[2][x] as usize];
                        }
                    }
                }
            });
        out
    }

    /// Encodes the image as 8-bit sRGB with alpha 255 into `out` (row-major, `width * height`
    /// pixels; e.g. an egui `ColorImage`'s pixels), in parallel over tile rows, without any
    /// intermediate buffer. Out-of-range values are clamped and NaN becomes 0.
    ///
    /// # Panics
    /// If `out` does not hold exactly `width * height` pixels.
    pub fn write_rgba8(&self, out: &mut [[u8; 4]]) {
        self.write_rgba8_mapped(out, |c| c);
    }

    /// [`Target::write_rgba8`] with every linear colour passed through `map` first (e.g. a
    /// false-colour ramp for a counting pass).
    ///
    /// # Panics
    /// If `out` does not hold exactly `width * height` pixels.
    pub fn write_rgba8_mapped(&self, out: &mut [[u8; 4]], map: impl Fn(Vec4) -> Vec4 + Sync) {
        self.write_pixels(out, map, |p| p);
    }

    /// Encodes the image as 8-bit sRGB into any pixel type (`make` turns RGBA bytes into a
    /// pixel, e.g. egui's `Color32::from_rgba_premultiplied`), after `map`.
    ///
    /// # Panics
    /// If `out` does not hold exactly `width * height` pixels.
    pub fn write_pixels<P: Send>(
        &self,
        out: &mut [P],
        map: impl Fn(Vec4) -> Vec4 + Sync,
        make: impl Fn([u8; 4]) -> P + Sync,
    ) {
        let w = self.width as usize;
        assert_eq!(out.len(), w * self.height as usize, "output size");
        let lut = crate::color::Srgb8Table::get();
        let px = |c: Vec4| {
            let c = map(c);
            make([lut.encode(c.x), lut.encode(c.y), lut.encode(c.z), 255])
        };
        out.par_chunks_mut(w * TILE as usize)
            .enumerate()
            .for_each(|(ty, band)| {
                for t in &self.tiles[ty * self.tiles_x as usize..(ty + 1) * self.tiles_x as usize] {
                    let clear = t.pending_clear;
                    for y in 0..t.h as usize {
                        let dst = &mut band[y * w + t.x0 as usize..][..t.w as usize];
                        match clear {
                            Some(c) => dst.iter_mut().for_each(|d| *d = px(c)),
                            None => {
                                let src =
                                    (0..t.w as usize).map(|x| t.stored(y * TILE as usize + x));
                                for (d, c) in dst.iter_mut().zip(src) {
                                    *d = px(c);
                                }
                            }
                        }
                    }
                }
            });
    }

    /// Writes the depth plane row-major into `out` (`width * height` values; 0 where
    /// nothing was drawn).
    ///
    /// # Panics
    /// If `out` does not hold exactly `width * height` values.
    pub fn write_depth(&self, out: &mut [f32]) {
        let w = self.width as usize;
        assert_eq!(out.len(), w * self.height as usize, "output size");
        out.par_chunks_mut(w * TILE as usize)
            .enumerate()
            .for_each(|(ty, band)| {
                for t in &self.tiles[ty * self.tiles_x as usize..(ty + 1) * self.tiles_x as usize] {
                    for y in 0..t.h as usize {
                        let dst = &mut band[y * w + t.x0 as usize..][..t.w as usize];
                        match t.pending_clear {
                            Some(_) => dst.fill(0.0),
                            None => {
                                for (x, d) in dst.iter_mut().enumerate() {
                                    *d = t.stored_depth(y * TILE as usize + x);
                                }
                            }
                        }
                    }
                }
            });
    }

    /// Colour and depth at pixel (x, y), or `None` outside the image.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Option<(Vec4, f32)> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let (t, o) = self.locate(x, y);
        let tile = &self.tiles[t];
        Some((tile.color_at(o), tile.depth_at(o)))
    }

    /// Index of the tile holding pixel (x, y), and the pixel's offset inside it.
    #[inline]
    #[must_use]
    pub fn locate(&self, x: u32, y: u32) -> (usize, usize) {
        let t = (y / TILE) * self.tiles_x + x / TILE;
        let o = (y % TILE) * TILE + x % TILE;
        (t as usize, o as usize)
    }

    /// Resolves the tiles into a row-major framebuffer.
    #[must_use]
    pub fn resolve(&self) -> Framebuffer {
        let n = self.width as usize * self.height as usize;
        let mut fb = Framebuffer {
            width: self.width,
            height: self.height,
            color: vec![Vec4::ZERO; n],
            depth: vec![0.0; n],
        };
        for t in &self.tiles {
            for y in 0..t.h {
                let src = (y * TILE) as usize;
                let dst = ((t.y0 + y) * self.width + t.x0) as usize;
                let w = t.w as usize;
                match t.pending_clear {
                    Some(c) => {
                        fb.color[dst..dst + w].fill(c);
                        fb.depth[dst..dst + w].fill(0.0);
                    }
                    None => {
                        for (x, c) in fb.color[dst..dst + w].iter_mut().enumerate() {
                            *c = t.stored(src + x);
                        }
                        for (x, d) in fb.depth[dst..dst + w].iter_mut().enumerate() {
                            *d = t.stored_depth(src + x);
                        }
                    }
                }
            }
        }
        fb
    }
}
