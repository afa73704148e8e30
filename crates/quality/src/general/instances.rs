//! The scene as the reference draws it: each instance with its transforms, alpha and
//! texture slots resolved as the renderer resolves them, and the bump gradient in f64.

use super::*;

/// How a material's alpha is used, cutoff in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Alpha {
    Opaque,
    Mask(f64),
    Blend,
}

/// One drawable instance: matrices in f64 and its material resolved.
#[derive(Clone)]
pub(super) struct Inst<'a> {
    pub(super) tri: &'a TriMesh,
    pub(super) world: DMat4,
    /// Cofactor of the world matrix's 3x3 part, negated for mirroring matrices.
    pub(super) normal: DMat3,
    pub(super) mvp: DMat4,
    pub(super) flip: bool,
    pub(super) cull: bool,
    pub(super) base: DVec4,
    /// The material's Phong constants, as the renderer resolves them.
    pub(super) surface: Surface,
    pub(super) alpha: Alpha,
    /// Emitted light (linear RGB), added after lighting.
    pub(super) emissive: DVec3,
    /// Base-colour texture (textured mode).
    pub(super) texture: Option<RefSlot>,
    /// Gloss map (multiplies `K_s`), in the per-pixel modes the reference stands for but
    /// `pbr`.
    pub(super) gloss: Option<RefSlot>,
    /// Metallic-roughness texture (`pbr`): G multiplies roughness, B metallic.
    pub(super) metal_rough: Option<RefSlot>,
    /// `KHR_materials_unlit`: the base colour is the colour.
    pub(super) unlit: bool,
    /// Normal map, occlusion and emissive map (textured mode).
    pub(super) normal_map: Option<RefSlot>,
    pub(super) occlusion: Option<RefSlot>,
    pub(super) emissive_map: Option<RefSlot>,
    /// Bump map (textured mode).
    pub(super) bump: Option<RefSlot>,
    /// The `KHR_materials_*` extensions' textures (`pbr`), in the order of `Slot::LAYERS`.
    pub(super) layer_maps: [Option<RefSlot>; Slot::LAYERS.len()],
    /// The handedness of the world matrix (-1 mirrors the tangent frame).
    pub(super) handed: f64,
}

/// A texture slot as the reference reads it: the image or procedural texture, its sampler,
/// the UV set and the transform of its UVs, and its scalar (normal scale, occlusion
/// strength, bump height).
#[derive(Clone)]
pub(super) struct RefSlot {
    pub(super) source: TextureSource,
    pub(super) uv_set: u32,
    pub(super) transform: UvTransform,
    pub(super) sampler: Sampler,
    pub(super) scale: f64,
}

impl RefSlot {
    /// The UV of the slot's set at corner `k` of triangle `v`, transformed (in f64).
    pub(super) fn corner_uv(&self, tri: &TriMesh, v: [usize; 3], k: usize) -> DVec2 {
        let uv = tri
            .uv_set(self.uv_set)
            .and_then(|uv| uv.get(v[k]))
            .map_or(DVec2::ZERO, |u| u.as_dvec2());
        self.transform.matrix().as_dmat3().transform_point2(uv)
    }

    /// The slot's UV at barycentrics `b` of triangle `v`.
    pub(super) fn uv(&self, tri: &TriMesh, v: [usize; 3], b: DVec3) -> DVec2 {
        let at = |k| self.corner_uv(tri, v, k);
        at(0) * b.x + at(1) * b.y + at(2) * b.z
    }

    /// The slot's value at barycentrics `b` of triangle `v` of `tri`: an image sampled at
    /// the UV of its set, interpolated and transformed (in f64); a procedural texture
    /// evaluated at a point (no footprint: the supersampling filters it).
    pub(super) fn at(&self, tri: &TriMesh, v: [usize; 3], b: DVec3) -> DVec4 {
        match &self.source {
            TextureSource::Image(t) => {
                if tri.uv_set(self.uv_set).is_none() {
                    return DVec4::ONE;
                }
                sample_texture(t, self.uv(tri, v, b), self.sampler)
            }
            TextureSource::Procedural(p) => p.color(&self.point(tri, v, b)).as_dvec4(),
        }
    }

    /// A procedural texture's sample point at barycentrics `b` (no footprint).
    pub(super) fn point(&self, tri: &TriMesh, v: [usize; 3], b: DVec3) -> SamplePoint {
        match &self.source {
            TextureSource::Procedural(p) if p.domain() == Domain::Object => {
                let l = solid_corners(tri, v);
                SamplePoint::position((l[0] * b.x + l[1] * b.y + l[2] * b.z).as_vec3(), 0.0)
            }
            _ => SamplePoint::uv(self.uv(tri, v, b).as_vec2()),
        }
    }

    /// The tangent frame of triangle `v` (world corners `p`, unit normal `n`) for a mesh
    /// without tangents: [`maps::uv_tangent`] from the triangle's edges and this slot's UVs
    /// (the renderer's from the screen-space derivatives).
    pub(super) fn uv_tangent(
        &self,
        tri: &TriMesh,
        v: [usize; 3],
        p: &[DVec3; 3],
        n: DVec3,
    ) -> Option<(DVec3, f64)> {
        tri.uv_set(self.uv_set)?;
        let uv = [0, 1, 2].map(|k| self.corner_uv(tri, v, k));
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        maps::uv_tangent::<f64>(n, p[1] - p[0], p[2] - p[0], (d1.x, d2.x), (d1.y, d2.y))
    }

    /// The surface gradient of the bump displacement at barycentrics `b` of triangle `v`
    /// (world corners `p`, unit normal `n`): the renderer's formulas (`shade::texlab`) with
    /// the triangle's edges in place of the screen-space derivatives, in f64.
    pub(super) fn bump_gradient(
        &self,
        tri: &TriMesh,
        v: [usize; 3],
        p: &[DVec3; 3],
        b: DVec3,
        n: DVec3,
    ) -> Option<DVec3> {
        let (s1, s2) = (p[1] - p[0], p[2] - p[0]);
        let uv_slope = |slope: DVec2| {
            let uv = [0, 1, 2].map(|k| self.corner_uv(tri, v, k));
            let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
            maps::uv_height_gradient::<f64>(
                n,
                s1,
                s2,
                (d1.x, d2.x),
                (d1.y, d2.y),
                (slope.x, slope.y),
                self.scale,
            )
        };
        match &self.source {
            TextureSource::Image(t) => {
                tri.uv_set(self.uv_set)?;
                uv_slope(image_height_slope(t, self.uv(tri, v, b), self.sampler))
            }
            TextureSource::Procedural(pt) => {
                let g = pt.height_gradient(&self.point(tri, v, b)).as_dvec3();
                if pt.domain() == Domain::Uv {
                    return uv_slope(g.truncate());
                }
                let l = solid_corners(tri, v);
                let (l1, l2) = (l[1] - l[0], l[2] - l[0]);
                let sg = maps::surface_gradient::<f64>(n, s1, s2, g.dot(l1), g.dot(l2))?;
                let (ws, ls) = if l1.length_squared() >= l2.length_squared() {
                    (s1.length(), l1.length())
                } else {
                    (s2.length(), l2.length())
                };
                (ls > 0.0).then(|| sg * (self.scale * ws / ls))
            }
        }
    }
}

/// The corners of triangle `v` in the solid textures' frame (the mesh's bounding sphere is
/// the unit sphere), as the renderer's vertex stage computes them.
pub(super) fn solid_corners(tri: &TriMesh, v: [usize; 3]) -> [DVec3; 3] {
    let inv = if tri.radius > 0.0 && tri.radius.is_finite() {
        1.0 / f64::from(tri.radius)
    } else {
        1.0
    };
    v.map(|k| {
        tri.positions.get(k).map_or(DVec3::ZERO, |p| {
            (p.as_dvec3() - tri.center.as_dvec3()) * inv
        })
    })
}

/// The slope per texel of a height image in f64: central differences one texel apart of its R
/// channel, read bilinearly (nearest for a nearest sampler) on the base level, as
/// `shade::texlab::image_height_slope` does.
pub(super) fn image_height_slope(t: &Texture, uv: DVec2, s: Sampler) -> DVec2 {
    let filter = if s.filter == Filter::Nearest {
        Filter::Nearest
    } else {
        Filter::Bilinear
    };
    let s = Sampler { filter, ..s };
    let step = DVec2::new(
        1.0 / f64::from(t.width.max(1)),
        1.0 / f64::from(t.height.max(1)),
    );
    let h = |uv: DVec2| sample_texture(t, uv, s).x;
    let g = DVec2::new(
        (h(uv + DVec2::X * step.x) - h(uv - DVec2::X * step.x)) * 0.5,
        (h(uv + DVec2::Y * step.y) - h(uv - DVec2::Y * step.y)) * 0.5,
    );
    if g.is_finite() {
        g
    } else {
        DVec2::ZERO
    }
}

/// What draws of material `m` on mesh `tri` read in `slot`: the renderer's own choice
/// ([`crate::render::found`]), read here in f64.
pub(super) fn ref_slot(
    scene: &Scene,
    opts: &Shot,
    tri: &TriMesh,
    m: &Material,
    slot: Slot,
) -> Option<RefSlot> {
    let f = crate::render::found(scene, &opts.settings, tri, m, slot)?;
    Some(RefSlot {
        source: f.source,
        uv_set: f.uv_set,
        transform: f.transform,
        sampler: f.sampler,
        scale: f64::from(f.scale),
    })
}

pub(super) fn instances<'a>(
    scene: &'a Scene,
    opts: &'a Shot,
    meshes: &'a [TriMesh],
    view: &View,
) -> Vec<Inst<'a>> {
    let mut out = Vec::new();
    for inst in &scene.instances {
        let (Some(tri), Some(mesh)) = (meshes.get(inst.mesh), scene.meshes.get(inst.mesh)) else {
            continue;
        };
        if tri.triangles.is_empty() || !inst.world.is_finite() || inst.copy_count() == 0 {
            continue;
        }
        let m = scene.material_of(mesh);
        // The renderer's choice of maps (`render::frame::resolve`): a slot is read when its
        // texture exists and the mesh has its UV set (a normal map on a mesh without
        // tangents takes its frame from the triangle's edges and UVs); the
        // textured mode (chosen by default when any map is usable) reads every map, the
        // other per-pixel modes only the gloss map.
        let usable = |slot: Slot| ref_slot(scene, opts, tri, &m, slot);
        let emissive = crate::render::material_emission(&m).as_dvec3();
        let base_map = usable(Slot::BaseColor);
        let normal = usable(Slot::Normal);
        let occlusion = usable(Slot::Occlusion);
        let emissive_map = usable(Slot::Emissive).filter(|_| emissive != DVec3::ZERO);
        let bump = usable(Slot::Bump);
        let mapped = base_map.is_some()
            || normal.is_some()
            || occlusion.is_some()
            || emissive_map.is_some()
            || bump.is_some();
        let policy = Policy::new(opts.settings.shading, inst.style, &m, mapped);
        let textured = policy.textured;
        let textured_only = |s: Option<RefSlot>| s.filter(|_| textured);
        let world = inst.placement(0).as_dmat4();
        let det = world.determinant();
        let first = Inst {
            tri,
            world,
            normal: crate::geom::normal_matrix_f64(DMat3::from_mat4(world)),
            mvp: view.vp * world,
            flip: det < 0.0,
            cull: !(m.double_sided || opts.settings.double_sided),
            base: policy.base.as_dvec4(),
            surface: policy.surface,
            unlit: policy.unlit,
            alpha: match m.alpha_mode {
                AlphaMode::Opaque => Alpha::Opaque,
                AlphaMode::Mask(c) => Alpha::Mask(f64::from(c)),
                AlphaMode::Blend => Alpha::Blend,
            },
            emissive,
            texture: textured_only(base_map),
            gloss: usable(Slot::Specular).filter(|_| !policy.pbr),
            metal_rough: usable(Slot::MetallicRoughness).filter(|_| policy.pbr),
            normal_map: textured_only(normal),
            occlusion: textured_only(occlusion),
            emissive_map: textured_only(emissive_map),
            bump: textured_only(bump),
            layer_maps: Slot::LAYERS.map(|s| usable(s).filter(|_| textured && policy.pbr)),
            handed: if det < 0.0 { -1.0 } else { 1.0 },
        };
        // An instanced mesh's copies (`EXT_mesh_gpu_instancing`): the same but for where
        // each is placed.
        let copies: Vec<Inst> = inst
            .placements()
            .skip(1)
            .map(|placed| {
                let world = placed.as_dmat4();
                let det = world.determinant();
                Inst {
                    world,
                    normal: crate::geom::normal_matrix_f64(DMat3::from_mat4(world)),
                    mvp: view.vp * world,
                    flip: det < 0.0,
                    handed: if det < 0.0 { -1.0 } else { 1.0 },
                    ..first.clone()
                }
            })
            .collect();
        out.push(first);
        out.extend(copies);
    }
    out
}
