//! What one instance draws with: the slots it reads (the settings' override or the material's texture), its material's surface and base colour under the mode, and its raster state.

use super::*;

/// The Phong modes' `K_d` and alpha of material `m`: its base colour, times
/// `1 - metallic` for a metallic-roughness material (metals have no diffuse colour; see
/// `phong_from_pbr` in the glTF loader). With a metallic-roughness texture, which the Phong
/// modes do not read, the factor is only an upper bound, and the material is taken as a
/// dielectric rather than blackening, say, a helmet whose texture marks a few parts metal.
#[must_use]
pub fn phong_base(m: &Material) -> Vec4 {
    match m.pbr {
        Some(_) if m.metallic_roughness_texture.is_none() && m.metallic.is_finite() => {
            let k = 1.0 - m.metallic.clamp(0.0, 1.0);
            (m.base_color.truncate() * k).extend(m.base_color.w)
        }
        _ => m.base_color,
    }
}

/// The light material `m` emits: `emissive` times `KHR_materials_emissive_strength`,
/// non-finite or negative channels made zero.
#[must_use]
pub fn material_emission(m: &Material) -> Vec3 {
    finite_colour(m.emissive * m.pbr.map_or(1.0, |p| p.emissive_strength))
}

/// How one instance is drawn under `settings`: its material parameters, mode and state.
pub(crate) struct Resolved {
    pub params: DrawParams,
    pub mode: Shading,
    pub blend: bool,
    pub state: DrawState,
}

/// A slot as one draw reads it: the material's own texture or the settings' override.
#[derive(Clone, Debug)]
pub struct Found {
    pub source: TextureSource,
    pub uv_set: u32,
    pub transform: UvTransform,
    pub sampler: Sampler,
    /// The slot's scalar (normal scale, occlusion strength, bump height).
    pub scale: f32,
}

/// What draws of material `m` on mesh `tri` read in `slot`: the settings' override if there
/// is one (an image or a 2D pattern needs the mesh to have its UV set; a solid texture needs
/// nothing), else the material's texture if it exists and the mesh has its UV set. The
/// renderer and the f64 reference both read the slots through it.
#[must_use]
pub fn found(
    scene: &crate::scene::Scene,
    settings: &Settings,
    tri: &TriMesh,
    m: &Material,
    slot: Slot,
) -> Option<Found> {
    let own = m.slot(slot);
    match settings.slots.get(slot) {
        Some(SlotOverride::Off) => None,
        Some(SlotOverride::Source {
            source,
            uv_set,
            transform,
            sampler,
            scale,
        }) => {
            if source.needs_uv() {
                tri.uv_set(*uv_set)?;
            }
            Some(Found {
                source: source.clone(),
                uv_set: *uv_set,
                transform: *transform,
                sampler: sampler.or(own.map(|t| t.sampler)).unwrap_or_default(),
                scale: *scale,
            })
        }
        None => {
            let t = own?;
            tri.uv_set(t.uv_set)?;
            let texture = scene.textures.get(t.texture)?;
            Some(Found {
                source: TextureSource::Image(Arc::clone(texture)),
                uv_set: t.uv_set,
                transform: t.transform,
                sampler: t.sampler,
                scale: t.scale,
            })
        }
    }
}

/// Resolves an instance's material (with the settings' overrides) and mode.
pub(crate) fn resolve(
    scene: &PreparedScene,
    settings: &Settings,
    inst: &PreparedInstance,
) -> Resolved {
    let tri = &scene.meshes[inst.mesh].tri;
    let k = scene.material_of(inst, settings.variant_index(scene.scene()));
    let m = settings
        .materials
        .as_ref()
        .and_then(|ms| ms.get(k))
        .unwrap_or(&scene.materials[k]);
    let slot = |s: Slot| found(scene.scene(), settings, tri, m, s);
    let base_map = slot(Slot::BaseColor);
    let normal_map = slot(Slot::Normal);
    let occlusion = slot(Slot::Occlusion);
    let emissive = material_emission(m);
    let emissive_map = slot(Slot::Emissive).filter(|_| emissive != Vec3::ZERO);
    let bump = slot(Slot::Bump);
    let mapped = base_map.is_some()
        || normal_map.is_some()
        || occlusion.is_some()
        || emissive_map.is_some()
        || bump.is_some();
    let policy = Policy::new(settings.shading, inst.style, m, mapped);
    let mode = policy.mode;
    let view = mode.tex_view().unwrap_or_default();
    let debug = mode.mode().debug();
    let blend = m.alpha_mode == AlphaMode::Blend && !debug && mode.mode().pass != Pass::Edges;
    let double_sided = m.double_sided || settings.double_sided;
    let mut state = DrawState {
        cull: if double_sided { Cull::None } else { Cull::Back },
        depth_write: !blend,
        blend: if blend { Blend::Alpha } else { Blend::Replace },
        flip_winding: inst.mirrored,
        subpixel_bits: settings.subpixel_bits,
        ..DrawState::opaque()
    };
    if settings.output == Output::Overdraw {
        state = DrawState {
            depth_test: DepthTest::Always,
            depth_write: false,
            blend: Blend::Add,
            ..state
        };
    }
    let per_pixel = mode.per_pixel();
    let Policy { textured, pbr, .. } = policy;
    let base_map = if mode.mode().base == Base::UvGrid {
        tri.uv_set(0).map(|_| Found {
            source: TextureSource::Procedural(Arc::clone(uv_grid())),
            uv_set: 0,
            transform: UvTransform::IDENTITY,
            sampler: Sampler::default(),
            scale: 1.0,
        })
    } else {
        base_map.filter(|_| textured)
    };
    let mut layout = LitLayout {
        color: tri.colors.is_some(),
        ..LitLayout::default()
    };
    // Each slot the mode samples gets the UV channel of its (set, transform), or the object
    // position for a solid texture.
    let mut params_of = |found: Option<Found>, on: bool| {
        let f = found.filter(|_| on)?;
        let uv_at = if f.source.needs_uv() {
            layout.channel(f.uv_set, f.transform)?
        } else {
            layout.object = true;
            0
        };
        let mut sampler = f.sampler;
        if let Some(filter) = settings.filter {
            sampler.filter = filter;
        }
        Some(SlotParams {
            source: f.source,
            sampler,
            uv_at,
            scale: f.scale,
        })
    };
    let mut base_map = params_of(base_map, true);
    let mut gloss = params_of(
        slot(Slot::Specular),
        per_pixel && view == TexView::Lit && !pbr,
    );
    let mut metal_rough = params_of(slot(Slot::MetallicRoughness), pbr);
    let mut normal_map = params_of(normal_map, textured);
    let mut occlusion = params_of(occlusion, textured && view == TexView::Lit);
    let mut emissive_map = params_of(emissive_map, textured && view == TexView::Lit);
    let mut bump = params_of(bump, textured);
    // The extensions' slots: the `pbr` mode's lit surface reads them.
    let mut layer_maps =
        Slot::LAYERS.map(|s| params_of(slot(s), pbr && textured && view == TexView::Lit));
    let coat_normal = layer_maps[Slot::ClearcoatNormal.layer_index().unwrap_or_default()].is_some();
    // The object position goes after every UV channel: its index is known only now.
    if let Some(k) = layout.object_at() {
        for p in [
            &mut base_map,
            &mut gloss,
            &mut normal_map,
            &mut occlusion,
            &mut emissive_map,
            &mut bump,
            &mut metal_rough,
        ]
        .into_iter()
        .chain(&mut layer_maps)
        .flatten()
        {
            if !p.source.needs_uv() {
                p.uv_at = k as u8;
            }
        }
    }
    // Without tangents the tangent-normals view takes its frame from the screen-space
    // derivatives of the position and a UV set (as glTF viewers do for such meshes).
    // So does a normal map on a mesh without tangents (an image put in the normal slot of
    // an OBJ, say), per pixel.
    let uv_frame = view == TexView::TangentNormals && tri.tangents.is_none();
    let normal_mapped = normal_map.is_some() || coat_normal;
    // An anisotropic material reads the tangents (the mesh's: the loader makes them).
    let anisotropic = pbr && view == TexView::Lit && m.pbr.is_some_and(|p| p.anisotropy > 0.0);
    let derived_frame = normal_mapped && tri.tangents.is_none();
    layout.position_derivatives = bump.is_some() || uv_frame || derived_frame;
    layout.tangent = tri.tangents.is_some()
        && (normal_mapped
            || anisotropic
            || matches!(view, TexView::Tangents | TexView::TangentNormals));
    // The texture the mip-level, texel-density and anisotropy views measure: the first
    // image the draw reads, else UV set 0 against a nominal 1024 x 1024 image.
    let measure = match view {
        TexView::MipLevel
        | TexView::TexelDensity
        | TexView::Anisotropy
        | TexView::TangentNormals
            if view != TexView::TangentNormals || uv_frame =>
        {
            let slots = [
                Slot::BaseColor,
                Slot::Specular,
                Slot::Normal,
                Slot::Occlusion,
            ]
            .into_iter()
            .chain([Slot::Emissive, Slot::Bump]);
            let image = slots.filter_map(slot).find_map(|f| match &f.source {
                TextureSource::Image(t) => Some((f.uv_set, f.transform, [t.width, t.height])),
                TextureSource::Procedural(_) => None,
            });
            let (set, transform, size) =
                image.unwrap_or((0, UvTransform::IDENTITY, [NOMINAL_SIZE; 2]));
            tri.uv_set(set)
                .and_then(|_| layout.channel(set, transform))
                .map(|at| (at, size.map(|s| s as f32)))
        }
        _ => None,
    };
    let mapped = [
        &base_map,
        &gloss,
        &normal_map,
        &occlusion,
        &emissive_map,
        &bump,
        &metal_rough,
    ]
    .into_iter()
    .chain(&layer_maps)
    .any(Option::is_some);
    let params = DrawParams {
        base: policy.base,
        surface: policy.surface,
        emissive: if debug { Vec3::ZERO } else { emissive },
        base_map,
        gloss,
        normal_map,
        occlusion,
        emissive_map,
        bump,
        metal_rough,
        layer_maps,
        model_scale: glam::Vec3::new(
            inst.world.x_axis.truncate().length(),
            inst.world.y_axis.truncate().length(),
            inst.world.z_axis.truncate().length(),
        ),
        unlit: policy.unlit,
        view,
        measure,
        layout,
        mapped,
        blinn: mode.mode().blinn
            || (settings.vertex_lighting.blinn
                && matches!(mode.mode().pass, Pass::Vertices | Pass::Facets)),
        provoking_vertex: settings.vertex_lighting.provoking_vertex
            && mode.mode().pass == Pass::Facets,
        alpha: if debug {
            AlphaMode::Opaque
        } else {
            m.alpha_mode
        },
        double_sided,
        lights: (0, 0),
    };
    Resolved {
        params,
        mode,
        blend,
        state,
    }
}

/// The image size the mip-level, texel-density and anisotropy views assume for a draw that
/// reads no image.
pub const NOMINAL_SIZE: u32 = 1024;

/// The UV test grid of the UV-checker mode, prepared once.
pub(super) fn uv_grid() -> &'static Arc<ProceduralTexture> {
    static GRID: std::sync::OnceLock<Arc<ProceduralTexture>> = std::sync::OnceLock::new();
    GRID.get_or_init(|| Arc::new(ProceduralTexture::new(Procedural::grid(8))))
}

/// A colour with every non-finite or negative channel made zero.
pub(super) fn finite_colour(c: Vec3) -> Vec3 {
    let f = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
    Vec3::new(f(c.x), f(c.y), f(c.z))
}
