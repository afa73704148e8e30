//! Ray queries for realist's ray-traced modes (the textbook's §9.6): bounding-volume
//! hierarchies over meshes and over their instances, the nearest hit of a ray and whether
//! anything blocks a shadow ray. Geometry only: what a hit looks like is the renderer's.
//!
//! The triangle test is watertight ([`triangle`]) and the box test robust ([`bvh`]): a ray
//! aimed at an edge or a vertex shared by triangles of a closed mesh never passes through.

pub mod bvh;
pub mod packet;
mod sah;
pub mod scene;
pub mod triangle;

pub use packet::PACKET;
pub use scene::{Hit, Instance, Mesh, Ray, Scene};

#[cfg(test)]
mod tests;
