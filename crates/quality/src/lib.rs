//! Accuracy, measured: analytic references that need no rasterizer, error metrics between
//! images, and the time-versus-error sweep behind `realist bench accuracy`.
//!
//! | file | owns |
//! |---|---|
//! | `image.rs` | [`LinearImage`]: f64 linear RGB, supersampling resolve |
//! | `metrics.rs` | RMSE, PSNR, max error, CIEDE2000 mean / p95 / count, heat map |
//! | `general/` | the f64 reference of any scene: `mod.rs` the request, the camera and the bands; `instances.rs` the scene as drawn (alpha, slots, bump); `coverage.rs` homogeneous visibility; `texels.rs` f64 texel reads |
//! | `sphere.rs` | the ray-cast sphere reference and its rasterizer scene |
//! | `plane.rs` | the exactly box-filtered textured plane reference and its scene |
//! | `sweep.rs` | one knob at a time: settings, timings, metrics, Pareto front, plot |
//! | `traced.rs` | scenes measured against the path tracer: shadows, environment occlusion |

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_color as color;
use realist_geom as geom;
use realist_mesh as mesh;
use realist_raster as raster;
use realist_render as render;
use realist_scene as scene;
use realist_shade as shade;
use realist_texture as texture;
use realist_texture::microfacet;

pub mod general;
mod image;
pub mod metrics;
pub mod plane;
pub mod sphere;
pub mod sweep;
pub mod traced;

pub use image::LinearImage;
pub use metrics::{compare, Metrics};

#[cfg(test)]
mod tests;
