//! Shadow maps: the depth of the nearest occluder seen from a directional light (parallel
//! projection over the scene's bounds) or a spot / rectangular light (perspective over its
//! cone), rendered by our own rasterizer ([`crate::render`]) and read here with
//! percentage-closer filtering and a slope-scaled bias.
//!
//! A point at light-space depth `z` is lit by a texel holding occluder depth `d` when
//! `d >= z - b`, with the bias `b = t (bias + slope tan θ)`: `t` is the world size of one
//! texel at that depth and θ the angle between the normal and the light, so surfaces seen
//! at a grazing angle from the light (whose depth changes fastest across a texel) get more
//! bias and flat surfaces facing the light get little: no acne, and little peter-panning.
//! Filtering takes `(2r + 1)²` bilinearly weighted comparisons (a tent over
//! `(2r + 2)²` texels), so an edge fades over about `2r + 1` texels.

use glam::{Mat4, Vec3, Vec4};

use crate::scene::Camera;
use crate::simd::Real;
use crate::simd::{Level, F8, V3};

/// Default shadow-map size (texels per side).
pub const SHADOW_SIZE: u32 = 1024;
/// Largest shadow-map size accepted.
pub const MAX_SHADOW_SIZE: u32 = 8192;

/// How shadow maps are rendered and read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowSettings {
    /// Texels per side.
    pub size: u32,
    /// PCF radius r: `(2r + 1)²` filtered taps; 0 = one bilinear tap (hardest edge).
    pub pcf: u32,
    /// Constant bias, in texels.
    pub bias: f32,
    /// Slope-scaled bias, in texels per unit `tan θ`.
    pub slope: f32,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        Self {
            size: SHADOW_SIZE,
            pcf: 1,
            bias: 1.0,
            slope: 1.5,
        }
    }
}

/// One light's shadow map.
#[derive(Clone, Debug, Default)]
pub struct ShadowMap {
    /// World -> the light's clip space (the projection the map was rendered with).
    pub view_proj: Mat4,
    /// The light's eye (spot) or the parallel view's origin (directional).
    pub origin: Vec3,
    /// Unit direction the light looks along.
    pub axis: Vec3,
    pub ortho: bool,
    pub size: u32,
    /// Light-space depth (distance along `axis` from `origin`) of the nearest occluder per
    /// texel, row 0 at the top; infinite where there is none.
    pub depth: Vec<f32>,
    /// World size of one texel at unit depth (perspective) or everywhere (parallel).
    pub texel: f32,
    pub settings: ShadowSettings,
    /// A screen-space mask instead of a depth map (`--shading whitted`): `depth` then holds
    /// each pixel's visibility of the light, found by a shadow ray from the point seen
    /// there, and `view_proj` is the frame's; the value is the `(width, height)` in pixels.
    pub screen: Option<(u32, u32)>,
}

/// One row of a matrix times `(p, 1)` on lanes.
#[inline(always)]
fn clip_row<L: Level>(r: Vec4, p: V3<L>) -> F8<L> {
    F8::splat(r.x) * p.x + F8::splat(r.y) * p.y + F8::splat(r.z) * p.z + F8::splat(r.w)
}

impl ShadowMap {
    /// The camera a map is rendered with: from `eye` (spot; parallel if `None`) along unit
    /// `axis`, covering the sphere (`center`, `radius`) that holds every occluder and receiver,
    /// within half-angle `spread` for a spot. Returns the camera and the world size of a
    /// texel (at unit depth for a spot).
    #[must_use]
    pub fn camera(
        eye: Option<Vec3>,
        axis: Vec3,
        spread: f32,
        center: Vec3,
        radius: f32,
        size: u32,
    ) -> (Camera, f32) {
        let radius = radius.max(1e-3);
        let up = if axis.cross(Vec3::Y).length_squared() < 1e-6 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        match eye {
            None => {
                let eye = center - axis * radius * 2.0;
                // Every field given (no `..Camera::default()`, whose name is a `String`): a
                // map is made every frame, which must not allocate.
                let cam = Camera {
                    name: String::new(),
                    eye,
                    target: center,
                    up,
                    yfov: 45f32.to_radians(),
                    near: radius * 0.5,
                    far: radius * 3.5,
                    aspect: None,
                    ortho: Some(radius * 1.01),
                    lens: Default::default(),
                };
                (cam, 2.0 * radius * 1.01 / size as f32)
            }
            Some(eye) => {
                let d = (center - eye).dot(axis);
                let dist = (center - eye).length();
                // The cone's half-angle, widened a little so PCF taps at its rim stay inside.
                let half = (spread * 1.02 + 0.01).min(85f32.to_radians());
                let far = (d + radius).max(1e-2) * 1.01;
                let near = (dist - radius).max(far * 1e-3).max(1e-3);
                // Every field given, as above.
                let cam = Camera {
                    name: String::new(),
                    eye,
                    target: eye + axis,
                    up,
                    yfov: 2.0 * half,
                    near,
                    far,
                    aspect: None,
                    ortho: None,
                    lens: Default::default(),
                };
                (cam, 2.0 * libm::tanf(half) / size as f32)
            }
        }
    }

    /// Converts the rasterizer's reversed depth (1 at `near`, 0 at `far`, 0 where nothing was
    /// drawn) of `cam` into light-space distance (infinite where nothing was drawn).
    pub fn depth_from_raster(cam: &Camera, z: &mut [f32]) {
        let (n, f) = (cam.near, cam.far);
        let ortho = cam.ortho.is_some();
        let a = n * f / (f - n);
        let b = -n / (f - n);
        for v in z {
            *v = if *v <= 0.0 || !v.is_finite() {
                f32::INFINITY
            } else if ortho {
                f - *v * (f - n)
            } else {
                a / (*v - b)
            };
        }
    }

    /// The screen mask's value at the pixel `p` projects into (1 outside the image).
    fn screen_lookup(&self, p: Vec3, w: u32, h: u32) -> f32 {
        let c: Vec4 = self.view_proj * p.extend(1.0);
        self.screen_texel(c.x, c.y, c.w, w, h)
    }

    /// The mask's value at clip position `(x, y, w)`. The pixel's centre projects to about
    /// `(i + 0.5, j + 0.5)`: truncating (the floor, for what is not negative) finds it.
    #[inline(always)]
    fn screen_texel(&self, cx: f32, cy: f32, cw: f32, w: u32, h: u32) -> f32 {
        if cw.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return 1.0;
        }
        let u = (cx / cw * 0.5 + 0.5) * w as f32;
        let v = (0.5 - cy / cw * 0.5) * h as f32;
        if !(u.is_finite() && v.is_finite()) {
            return 1.0;
        }
        let x = (u.max(0.0) as u32).min(w - 1) as usize;
        let y = (v.max(0.0) as u32).min(h - 1) as usize;
        self.depth.get(y * w as usize + x).copied().unwrap_or(1.0)
    }

    /// [`ShadowMap::screen_lookup`] on the lanes of `mask` (others 1): the projection on
    /// all lanes at once, the reads lane by lane.
    #[inline(always)]
    fn screen_lanes<L: Level>(&self, p: V3<L>, mask: u32, w: u32, h: u32) -> F8<L> {
        let m = self.view_proj;
        let cx = clip_row(m.row(0), p).to_array();
        let cy = clip_row(m.row(1), p).to_array();
        let cw = clip_row(m.row(3), p).to_array();
        let mut out = [1.0; 8];
        let mut bits = mask;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            out[i] = self.screen_texel(cx[i], cy[i], cw[i], w, h);
        }
        F8::from_array(out)
    }

    /// Visibility of the light at `p` with unit normal `n` and unit direction to the light
    /// `l`: 1 lit, 0 in shadow, between at a filtered edge.
    #[must_use]
    pub fn visibility<T: Real>(&self, p: T::V, n: T::V, l: T::V) -> T {
        let ndl = T::dot(n, l).to_f64() as f32;
        T::of(self.lookup(T::to_vec3(p), ndl))
    }

    /// [`ShadowMap::visibility`] on the lanes of `mask` (others 1).
    #[must_use]
    #[inline(always)]
    pub fn visibility_lanes<L: Level>(&self, p: V3<L>, n: V3<L>, l: V3<L>, mask: u32) -> F8<L> {
        if let Some((w, h)) = self.screen {
            return self.screen_lanes(p, mask, w, h);
        }
        let ndl = n.dot(l).to_array();
        let (px, py, pz) = (p.x.to_array(), p.y.to_array(), p.z.to_array());
        let mut out = [1.0; 8];
        let mut m = mask;
        while m != 0 {
            let i = m.trailing_zeros() as usize;
            m &= m - 1;
            out[i] = self.lookup(Vec3::new(px[i], py[i], pz[i]), ndl[i]);
        }
        F8::from_array(out)
    }

    /// The filtered comparison at world point `p` whose normal makes cosine `ndl` with the
    /// light.
    #[must_use]
    pub fn lookup(&self, p: Vec3, ndl: f32) -> f32 {
        if let Some((w, h)) = self.screen {
            return self.screen_lookup(p, w, h);
        }
        let size = self.size as usize;
        if size == 0 || self.depth.len() < size * size || !p.is_finite() {
            return 1.0;
        }
        let c: Vec4 = self.view_proj * p.extend(1.0);
        // Behind the light (or NaN): not in the map.
        if c.w.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return 1.0;
        }
        let s = self.size as f32;
        let u = (c.x / c.w * 0.5 + 0.5) * s;
        let v = (0.5 - c.y / c.w * 0.5) * s;
        if !(u.is_finite() && v.is_finite()) {
            return 1.0;
        }
        let z = (p - self.origin).dot(self.axis);
        let texel = if self.ortho {
            self.texel
        } else {
            self.texel * z.max(0.0)
        };
        let ndl = ndl.clamp(0.05, 1.0);
        let tan = ((1.0 - ndl * ndl).max(0.0).sqrt() / ndl).min(20.0);
        let st = &self.settings;
        let r = st.pcf.min(8) as i64;
        let z_ref = z - texel * (st.bias + st.slope * tan) * (1.0 + r as f32 * 0.5);
        let x0 = (u - 0.5).floor();
        let y0 = (v - 0.5).floor();
        let (fx, fy) = (u - 0.5 - x0, v - 0.5 - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let weight = |i: i64, f: f32| {
            if i == -r {
                1.0 - f
            } else if i == r + 1 {
                f
            } else {
                1.0
            }
        };
        let mut lit = 0.0;
        for j in -r..=r + 1 {
            let y = y0 + j;
            let wy = weight(j, fy);
            if y < 0 || y >= size as i64 {
                lit += wy * (2 * r + 1) as f32;
                continue;
            }
            let row = &self.depth[y as usize * size..][..size];
            for i in -r..=r + 1 {
                let x = x0 + i;
                let w = wy * weight(i, fx);
                if x < 0 || x >= size as i64 || row[x as usize] >= z_ref {
                    lit += w;
                }
            }
        }
        lit / ((2 * r + 1) * (2 * r + 1)) as f32
    }
}
