//! The vertex stage: per-vertex (or, for flat shading, per-facet) work that appends the
//! varyings of each mode to a group's buffer. Runs in parallel over vertices; allocates
//! nothing when the buffers have the capacity.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::frame::FrameInst;
use super::prepare::{PreparedMesh, PreparedScene};
use crate::shade::{illuminate, Debug, DrawParams, Fog, LightSet};
use crate::simd::{KernelKind, Level, Num, F8, LANES, V3};

const MIN_LEN: usize = 4096;

/// What the lit vertex functions share.
pub(super) struct Lit<'a> {
    pub scene: &'a PreparedScene,
    pub params: &'a [DrawParams],
    pub lights: &'a LightSet,
    /// Per-draw light indices ([`DrawParams::lights`]).
    pub active: &'a [u32],
    pub eye: Vec3,
    /// Unit view direction (depth fog).
    pub forward: Vec3,
    /// Fog, applied per vertex (Gouraud) or per facet (flat).
    pub fog: Option<Fog>,
    /// The kernel the lane lighting runs with.
    pub kernel: KernelKind,
}

/// Appends `n` vertices of `stride` floats to `out`, vertex `k` written by `f(k, floats)`,
/// in parallel (in place: no allocation when `out` has the capacity). Returns `stride`.
fn per_vertex(
    out: &mut Vec<f32>,
    n: usize,
    stride: usize,
    f: impl Fn(usize, &mut [f32]) + Sync + Send,
) -> usize {
    in_groups(out, n, stride, 1, f)
}

/// Appends `n` vertices of `stride` floats to `out` in parallel, eight at a time:
/// `f(k, floats)` writes vertices `k..k + floats.len() / stride` (eight, fewer at the end).
/// Returns `stride`.
fn per_vertices(
    out: &mut Vec<f32>,
    n: usize,
    stride: usize,
    f: impl Fn(usize, &mut [f32]) + Sync + Send,
) -> usize {
    in_groups(out, n, stride, LANES, f)
}

/// [`per_vertex`] and [`per_vertices`]: `f(k, floats)` writes the `group` vertices from `k`
/// (fewer at the end).
fn in_groups(
    out: &mut Vec<f32>,
    n: usize,
    stride: usize,
    group: usize,
    f: impl Fn(usize, &mut [f32]) + Sync + Send,
) -> usize {
    if stride == 0 {
        return 0;
    }
    let start = out.len();
    out.resize(start + n * stride, 0.0);
    out[start..]
        .par_chunks_mut(stride * group)
        .with_min_len(MIN_LEN / group)
        .enumerate()
        .for_each(|(k, o)| f(k * group, o));
    stride
}

crate::simd::per_kernel! {
    /// Gouraud's colours of vertices `k0..` of instance `fi`, eight at a time with the lane
    /// lighting (`out` holds up to eight vertices of 4, or 8 for both sides, floats): the
    /// lighting equation of [`Lit::colour`], the same operations on lanes.
    fn gouraud_lanes<L>(lit: &Lit<'_>, fi: &FrameInst, k0: usize, out: &mut [f32]) {
        let d = &lit.params[fi.param as usize];
        let mesh = &lit.scene.meshes[fi.mesh as usize];
        let tri = &mesh.tri;
        let stride = if d.double_sided { 8 } else { 4 };
        let count = (out.len() / stride).min(LANES);
        if count == 0 {
            return;
        }
        // The vertices' world positions, normals and colours as lanes (the last vertex
        // repeated in unused lanes).
        let (mut p, mut n, mut c) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3], [[1.0; LANES]; 4]);
        for i in 0..LANES {
            let k = k0 + i.min(count - 1);
            let (pw, nw) = world(fi, mesh, k);
            let col = tri.colors.as_ref().map_or(Vec4::ONE, |cs| cs[k]);
            for j in 0..3 {
                p[j][i] = pw[j];
                n[j][i] = nw[j];
            }
            for j in 0..4 {
                c[j][i] = col[j];
            }
        }
        // No closures and no array `map` over lanes here: a closure is a function of its own,
        // compiled without the kernel's features, and calls each vector intrinsic out of line
        // (measured: the AVX2 copy 4.5 times slower than the portable one).
        let p = V3::<L>::new(F8::from_array(p[0]), F8::from_array(p[1]), F8::from_array(p[2]));
        let n = V3::<L>::new(F8::from_array(n[0]), F8::from_array(n[1]), F8::from_array(n[2]));
        let sides = if d.double_sided { 2 } else { 1 };
        for side in 0..sides {
            let normal = if side == 0 { n } else { -n };
            let rgba = lit.colour_lanes::<L>(d, p, normal, &c);
            let rgba = [
                rgba[0].to_array(),
                rgba[1].to_array(),
                rgba[2].to_array(),
                rgba[3].to_array(),
            ];
            for i in 0..count {
                for j in 0..4 {
                    out[i * stride + 4 * side + j] = rgba[j][i];
                }
            }
        }
    }
}

/// Appends `f(0), f(1), ..., f(n - 1)`, computed in parallel, to `out` (in place: the range
/// is indexed, so rayon writes into the reserved capacity).
fn per_item<T: Send>(out: &mut Vec<T>, n: usize, f: impl Fn(usize) -> T + Sync + Send) {
    out.par_extend((0..n).into_par_iter().with_min_len(MIN_LEN).map(f));
}

/// World position and unit world normal of render vertex `k`.
#[inline]
fn world(fi: &FrameInst, mesh: &PreparedMesh, k: usize) -> (Vec3, Vec3) {
    let normal = fi.normal;
    let p = fi.world.transform_point3(mesh.tri.positions[k]);
    // Num's normalize: glam's with the hardware square root (see `Num for f32`).
    let n = f32::normalize_or_zero(normal * mesh.tri.normals[k]);
    (p, n)
}

/// Per-pixel-lighting varyings in the draw's layout ([`DrawParams::layout`]); returns the
/// stride. Tangents go to the world by the model matrix (not the normal matrix: they lie in
/// the surface), their handedness flipped under a mirroring one so the bitangent
/// `w (N × T)` still runs along -v.
pub(super) fn lit(
    scene: &PreparedScene,
    fi: &FrameInst,
    params: &[DrawParams],
    out: &mut Vec<f32>,
) -> usize {
    let layout = params[fi.param as usize].layout;
    let mesh = &scene.meshes[fi.mesh as usize];
    let tri = &mesh.tri;
    let m3 = glam::Mat3::from_mat4(fi.world);
    let handed = if fi.mirrored { -1.0 } else { 1.0 };
    let inv_radius = if tri.radius > 0.0 && tri.radius.is_finite() {
        1.0 / tri.radius
    } else {
        1.0
    };
    per_vertex(out, tri.positions.len(), layout.stride(), |k, o| {
        let (p, n) = world(fi, mesh, k);
        let uv = |set: u32| tri.uv_set(set).map_or(Vec2::ZERO, |u| u[k]);
        let c = tri.colors.as_ref().map_or(Vec4::ONE, |c| c[k]);
        let t = tri.tangents.as_ref().map_or(Vec4::X, |t| t[k]);
        let tw = f32::normalize_or_zero(m3 * t.truncate());
        // Solid textures' frame: the mesh's bounding sphere is the unit sphere.
        let object = || (tri.positions[k] - tri.center) * inv_radius;
        layout.write(o, p, n, uv, object, c, tw.extend(t.w * handed));
    })
}

impl Lit<'_> {
    /// The lighting equation at a vertex or facet centroid, seen from the side `n` points
    /// to, fogged there (Phong's `R·V` highlight, as the textbook's Gouraud shading, unless
    /// the draw asks for Blinn's: [`crate::VertexLighting`]).
    #[inline]
    fn colour(&self, d: &DrawParams, p: Vec3, n: Vec3, c: Vec4) -> Vec4 {
        let base = d.base * c;
        let mut surf = d.surface.at::<f32>(base.truncate());
        // Gouraud's and flat's lighting is Phong's (as in `colour_lanes`).
        surf.pbr = None;
        let active = d.active(self.active);
        let mut rgb = illuminate::<f32>(self.lights, Some(active), &surf, p, n, self.eye, d.blinn);
        rgb += d.emissive;
        if let Some(fog) = &self.fog {
            rgb = fog.apply::<f32>(rgb, p, self.eye, self.forward);
        }
        rgb.extend(base.w)
    }
}

impl Lit<'_> {
    /// [`Lit::colour`] of eight points `p` with normals `n` and vertex colours `c` (RGBA).
    #[inline(always)]
    fn colour_lanes<L: Level>(
        &self,
        d: &DrawParams,
        p: V3<L>,
        n: V3<L>,
        c: &[[f32; LANES]; 4],
    ) -> [F8<L>; 4] {
        let base = d.base.to_array();
        let b: [F8<L>; 4] = [
            F8::splat(base[0]) * F8::from_array(c[0]),
            F8::splat(base[1]) * F8::from_array(c[1]),
            F8::splat(base[2]) * F8::from_array(c[2]),
            F8::splat(base[3]) * F8::from_array(c[3]),
        ];
        let mut surf = d.surface.at::<F8<L>>(V3::new(b[0], b[1], b[2]));
        // The vertex passes are Gouraud's and flat's, Phong's lighting: a `pbr` draw shades
        // per pixel. Said here, the compiler leaves the BRDF's code out of this function.
        surf.pbr = None;
        let active = d.active(self.active);
        let eye = V3::splat(self.eye);
        let mut rgb = illuminate::<F8<L>>(self.lights, Some(active), &surf, p, n, eye, d.blinn);
        rgb = rgb + V3::splat(d.emissive);
        if let Some(fog) = &self.fog {
            rgb = fog.apply::<F8<L>>(rgb, p, eye, V3::splat(self.forward));
        }
        [rgb.x, rgb.y, rgb.z, b[3]]
    }

    /// Gouraud: lighting per vertex, colours interpolated (4 floats). Double-sided materials
    /// also get the colour of the back side (normal flipped; 8 floats), of which set-up
    /// keeps the side each triangle shows (`DrawState::facing_varyings`, set for exactly
    /// these draws: no culling). Returns the stride.
    pub fn gouraud(&self, fi: &FrameInst, out: &mut Vec<f32>) -> usize {
        let d = &self.params[fi.param as usize];
        let mesh = &self.scene.meshes[fi.mesh as usize];
        let stride = if d.double_sided { 8 } else { 4 };
        let lanes = gouraud_lanes::pick(self.kernel);
        per_vertices(out, mesh.tri.positions.len(), stride, |k0, o| {
            lanes(self, fi, k0, o);
        })
    }

    /// Flat: one lighting evaluation per facet, at its area-weighted centroid with its plane
    /// normal turned towards the eye on double-sided materials; every corner of the
    /// (unindexed) triangles carries its facet's colour (4 floats). With
    /// [`DrawParams::provoking_vertex`], one evaluation per triangle instead, at its last
    /// corner (position and colour) with the triangle's plane normal, as OpenGL's flat
    /// shading does. `facets` is scratch memory. Returns the stride.
    pub fn flat(&self, fi: &FrameInst, facets: &mut Vec<Vec4>, out: &mut Vec<f32>) -> usize {
        let d = &self.params[fi.param as usize];
        let mesh = &self.scene.meshes[fi.mesh as usize];
        let (tri, flat) = (&mesh.tri, mesh.flat());
        let normal = fi.normal;
        let facing = |p: Vec3, n: Vec3| {
            let n = f32::normalize_or_zero(normal * n);
            if d.double_sided && n.dot(self.eye - p) < 0.0 {
                -n
            } else {
                n
            }
        };
        facets.clear();
        if d.provoking_vertex {
            per_item(facets, tri.triangles.len(), |t| {
                let [a, b, c] = tri.triangles[t].map(|k| k as usize);
                let q = &tri.positions;
                let p = fi.world.transform_point3(q[c]);
                let n = facing(p, (q[b] - q[a]).cross(q[c] - q[a]));
                let colour = tri.colors.as_ref().map_or(Vec4::ONE, |cs| cs[c]);
                self.colour(d, p, n, colour)
            });
        } else {
            per_item(facets, tri.facet_count(), |f| {
                let p = fi.world.transform_point3(flat.centroids[f]);
                self.colour(d, p, facing(p, tri.facet_normal(f)), flat.first_colors[f])
            });
        }
        let facets = &*facets;
        per_vertex(out, 3 * tri.triangles.len(), 4, |c, o| {
            let t = c / 3;
            let f = if d.provoking_vertex {
                t
            } else {
                tri.facet_of(t)
            };
            let colour = facets.get(f).copied().unwrap_or(Vec4::ZERO);
            o.copy_from_slice(&colour.to_array());
        })
    }
}

impl Lit<'_> {
    /// The colour of every vertex of an instance's points and lines (one per render vertex,
    /// into `out`, cleared first), following glTF's recommendation for them: lit as the
    /// Gouraud vertices are (the side the normal points to) when the mesh's normals come
    /// from the file and the material is not unlit; otherwise unlit, `base × COLOR_0 +
    /// emissive`. Fog applies to both.
    pub fn strokes(&self, fi: &FrameInst, out: &mut Vec<Vec4>) {
        let d = &self.params[fi.param as usize];
        let mesh = &self.scene.meshes[fi.mesh as usize];
        let tri = &mesh.tri;
        let lit = tri.file_normals && !d.unlit;
        out.clear();
        per_item(out, tri.positions.len(), |k| {
            let c = tri.colors.as_ref().map_or(Vec4::ONE, |c| c[k]);
            if lit {
                let (p, n) = world(fi, mesh, k);
                return self.colour(d, p, n, c);
            }
            let base = d.base * c;
            let mut rgb = base.truncate() + d.emissive;
            if let Some(fog) = &self.fog {
                let p = fi.world.transform_point3(tri.positions[k]);
                rgb = fog.apply::<f32>(rgb, p, self.eye, self.forward);
            }
            rgb.extend(base.w)
        });
    }
}

/// Debug views: the quantity itself (3 floats). Returns the stride.
pub(super) fn debug(
    scene: &PreparedScene,
    fi: &FrameInst,
    mode: Debug,
    out: &mut Vec<f32>,
) -> usize {
    let mesh = &scene.meshes[fi.mesh as usize];
    let tri = &mesh.tri;
    per_vertex(out, tri.positions.len(), 3, |k, o| {
        let v = match mode {
            Debug::Normals => world(fi, mesh, k).1,
            Debug::Depth => Vec3::splat(-fi.model_view.transform_point3(tri.positions[k]).z),
            Debug::Uv => tri.uv_set(0).map_or(Vec2::ZERO, |u| u[k]).extend(0.0),
        };
        o.copy_from_slice(&v.to_array());
    })
}

/// Nothing per vertex (depth-only and counting passes).
pub(super) fn unit(_: &PreparedScene, _: &FrameInst, _: &mut Vec<f32>) -> usize {
    0
}
