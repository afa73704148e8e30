//! # realist
//!
//! A glTF 2.0 / OBJ scene viewer and material toolkit whose renderer is a tiled CPU rasterizer.
//!
//! Data flows one way:
//!
//! ```text
//! file --load--> Scene --prepare--> draw list --raster--> Framebuffer --> PNG
//! ```
//!
//! | module | owns |
//! |---|---|
//! | [`color`] | colour types and models, colorimetry (CIE tables, XYZ, Lab, Delta E, Planckian locus) |
//! | [`mesh`] | the vertex/edge/facet model, averaged normals, topology report, primitives |
//! | [`load`] | OBJ/MTL and glTF/GLB loaders producing a [`scene::Scene`] |
//! | [`scene`] | scene, instances, materials, lights, camera |
//! | [`texture`] | decoded images and samplers |
//! | [`raster`] | clip-space transform, culling, clipping, fixed-point setup, binning, tile fill |
//! | [`shade`] | shading modes (flat, Gouraud, Phong, Blinn, textured, debug views) and the renderer |
//! | [`quality`] | analytic references, error metrics, the time-versus-error sweep |
//! | [`overlay`] | 2D drawings with tiny-skia: the chromaticity diagram, plots |
//! | `viewer` | the interactive viewer (feature `viewer`): navigation, recent files, file watching |

pub mod color;
pub mod load;
pub mod mesh;
pub mod overlay;
pub mod quality;
pub mod raster;
pub mod scene;
pub mod shade;
pub mod texture;
#[cfg(feature = "viewer")]
pub mod viewer;
