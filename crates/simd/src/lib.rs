//! The bottom of the renderer: lane types and the kernel dispatch that `raster`, `texture`
//! and `shade` all use, and the numeric trait the lighting model is written over.
//!
//! - [`F8`], [`M8`], [`V3`], [`I8`]: eight f32 / mask / 3-vector / i32 lanes, one block row
//!   of pixels ([`lanes`]);
//! - [`KernelKind`], [`per_kernel!`] and [`kernel::dispatch`]: the instruction set lane code
//!   is compiled for, chosen once at run time ([`kernel`], the workspace's only `unsafe`);
//! - [`Real`]: `f32`, `f64` and the lanes ([`F8`]) behind one set of arithmetic, masks
//!   and selects, so the lighting model is stated once for the vertex stage, the pixel
//!   probe, the f64 references and the pixel shaders ([`real`]).
//!
//! Nothing here knows pixels, triangles or colours.

pub mod kernel;
pub mod lanes;
pub mod level;
pub mod real;

pub use kernel::KernelKind;
pub use lanes::{mad, Lane, F8, I8, LANES, M8, V3};
pub use level::Level;
pub use real::{Num, Real};
