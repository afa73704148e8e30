//! Memory kept between frames for each varying type: the renderer draws groups whose
//! varying types differ (a colour for Gouraud, position + normal + UV for textured Phong,
//! nothing for a depth pass), so their buffers live in a map keyed by type. Taking a buffer
//! out and putting it back moves a `Box`; nothing is allocated once every type in use has
//! been seen.

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
    pub start: u32,
    pub len: u32,
}

/// The buffers of one group of draws with varying type `V`.
pub(super) struct GroupScratch<V> {
    pub clip: Vec<Vec4>,
    pub var: Vec<V>,
    pub items: Vec<Item>,
    pub raster: RasterScratch<V>,
}

impl<V> Default for GroupScratch<V> {
    fn default() -> Self {
        Self {
            clip: Vec::new(),
            var: Vec::new(),
            items: Vec::new(),
            raster: RasterScratch::default(),
        }
    }
}

impl<V> GroupScratch<V> {
    pub fn clear(&mut self) {
        self.clip.clear();
        self.var.clear();
        self.items.clear();
    }
}
