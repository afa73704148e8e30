//! Memory kept between frames, in a map keyed by type: the groups' vertex buffers and the
//! rasterizer's scratch ([`GroupScratch`]), and the scratch of particular passes (flat
//! shading's facet colours). Taking a buffer out and putting it back moves a `Box`; nothing
//! is allocated once every type in use has been seen.

use std::any::{Any, TypeId};
use std::collections::HashMap;

use glam::Vec4;

use crate::raster::RasterScratch;

/// A map from type to one kept value of that type.
#[derive(Default)]
pub(super) struct Pool(HashMap<TypeId, Box<dyn Any + Send>>);

impl std::fmt::Debug for Pool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Pool({} types)", self.0.len())
    }
}

impl Pool {
    /// The kept value of type `T` (or a new default one), taken out of the pool.
    pub fn take<T: Default + Send + 'static>(&mut self) -> Box<T> {
        self.0
            .remove(&TypeId::of::<T>())
            .and_then(|b| b.downcast::<T>().ok())
            .unwrap_or_default()
    }

    /// Gives a value back for the next [`Pool::take`] of its type.
    pub fn put<T: Send + 'static>(&mut self, value: Box<T>) {
        self.0.insert(TypeId::of::<T>(), value);
    }
}

/// Where a draw's vertices are in a group's buffers.
#[derive(Clone, Copy, Debug)]
pub(super) struct Item {
    /// Index into the frame's instances.
    pub inst: u32,
    /// First vertex in the clip positions, and vertex count.
    pub start: u32,
    pub len: u32,
    /// First float in the varyings, and floats per vertex.
    pub var_start: u32,
    pub stride: u32,
    /// With sorted triangles: first triangle in [`GroupScratch::sorted`] (the draw has all
    /// of its mesh's triangles there, farthest first); `u32::MAX` otherwise.
    pub sorted: u32,
}

/// The buffers of one group of draws.
#[derive(Default)]
pub(super) struct GroupScratch {
    pub clip: Vec<Vec4>,
    pub var: Vec<f32>,
    pub items: Vec<Item>,
    pub raster: RasterScratch,
    /// Triangles sorted back to front (blended instances), and the sort keys.
    pub sorted: Vec<[u32; 3]>,
    pub keys: Vec<(f32, u32)>,
}

impl GroupScratch {
    pub fn clear(&mut self) {
        self.clip.clear();
        self.var.clear();
        self.items.clear();
        self.sorted.clear();
    }
}
