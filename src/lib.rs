//! # realist
//!
//! A glTF 2.0 / OBJ scene viewer and material toolkit whose renderer is a tiled CPU rasterizer.
//!
//! Data flows one way:
//!
//! ```text
//! file --load--> Scene --prepare--> PreparedScene --Renderer(View)--> tiles --> sRGB8 --> PNG / viewer
//! ```
//!
//! | module | owns |
//! |---|---|
//! | [`color`] | colour types and models, colorimetry (CIE tables, XYZ, Lab, Delta E, Planckian locus) |
//! | [`mesh`] | the vertex/edge/facet model, averaged normals, topology report, primitives |
//! | [`load`] | OBJ/MTL and glTF/GLB loaders producing a [`scene::Scene`] |
//! | [`scene`] | scene, instances, materials, lights, camera |
//! | [`scenefile`] | TOML/JSON scene files: model, camera, lights, materials, fog, shadows, output, comparison layouts |
//! | [`texture`] | decoded images and samplers |
//! | [`raster`] | clip-space transform, culling, clipping, fixed-point setup, binning, tile fill |
//! | [`render`] | the front end: prepared scenes, the reusable renderer (settings, views, passes, supersampling), the pixel probe |
//! | [`shade`] | the lighting equation and the shaders of every mode (flat, Gouraud, Phong, Blinn, textured, debug views) |
//! | [`quality`] | analytic references, error metrics, the time-versus-error sweep |
//! | [`overlay`] | 2D drawings with tiny-skia: the chromaticity diagram, plots |
//! | `viewer` | the egui/eframe viewer (feature `viewer`, on by default): worker thread, panels, navigation |
//!
//! Feature flags: `viewer` (default) builds the interactive viewer with eframe (glow + x11);
//! `--no-default-features` builds the headless library and command line.

pub use realist_color as color;
pub use realist_load as load;
pub use realist_mesh as mesh;
pub use realist_overlay as overlay;
pub use realist_quality as quality;
pub use realist_raster as raster;
pub use realist_render as render;
pub use realist_scene as scene;
pub use realist_scenefile as scenefile;
pub use realist_shade as shade;
pub use realist_simd as simd;
pub use realist_texture as texture;
pub use realist_texture::microfacet;
pub use realist_trace as trace;
#[cfg(feature = "viewer")]
pub use realist_viewer as viewer;
