//! The prepared scene as the ray-traced modes see it (the textbook's §9.6): one hierarchy
//! per mesh ([`realist_trace::Mesh`], built on first use and kept; a posed mesh's is refit
//! when the pose changes it) and one over the instances the settings show (every copy of
//! an instanced mesh, the ground plane when it is on), rebuilt when what is shown or where
//! it is changes. Instance keys are `instance << 32 | copy`.

use std::sync::{Arc, Mutex, PoisonError};

use glam::Mat4;
use rayon::prelude::*;

use super::prepare::PreparedScene;
use super::settings::{Hidden, Settings};
use realist_trace as trace;

/// What the instances' hierarchy was built for.
#[derive(Clone, Debug, PartialEq)]
struct Key {
    ground: Option<Mat4>,
    hidden: Hidden,
    /// Counts poses applied: instances move with them.
    pose: u64,
}

#[derive(Debug, Default)]
struct Cache {
    meshes: Vec<Option<Arc<trace::Mesh>>>,
    scene: Option<(Key, Arc<trace::Scene>)>,
    pose: u64,
}

/// The cache a prepared scene keeps; a clone starts empty (it builds its own on use).
#[derive(Debug, Default)]
pub(crate) struct Rays(Mutex<Cache>);

impl Clone for Rays {
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// Splits an instance key.
#[must_use]
pub fn unkey(key: u64) -> (usize, usize) {
    ((key >> 32) as usize, (key & 0xffff_ffff) as usize)
}

impl Rays {
    /// Poses applied so far (what a cached solution was made for).
    pub(crate) fn pose(&self) -> u64 {
        self.0.lock().unwrap_or_else(PoisonError::into_inner).pose
    }

    /// A pose moved mesh `meshes` (their hierarchies are refit from `scene`'s vertices
    /// when built) and perhaps instances.
    pub(crate) fn posed(
        &mut self,
        scene: &[super::PreparedMesh],
        meshes: impl Iterator<Item = usize>,
    ) {
        let c = self.0.get_mut().unwrap_or_else(PoisonError::into_inner);
        c.pose += 1;
        for m in meshes {
            if let (Some(Some(h)), Some(pm)) = (c.meshes.get_mut(m), scene.get(m)) {
                Arc::make_mut(h).refit(&pm.tri.positions, &pm.tri.triangles);
            }
        }
    }
}

impl PreparedScene {
    /// The scene's ray-query structure for `settings` (shown instances, ground plane).
    #[must_use]
    pub fn rays(&self, settings: &Settings) -> Arc<trace::Scene> {
        let ground = settings.ground.as_ref().map(|g| self.ground_world(g));
        let mut c = self.rays.0.lock().unwrap_or_else(PoisonError::into_inner);
        let key = Key {
            ground,
            hidden: settings.hidden.clone(),
            pose: c.pose,
        };
        if let Some((k, s)) = &c.scene {
            if *k == key {
                return Arc::clone(s);
            }
        }
        // The meshes an instance shows, built in parallel where missing.
        let shown = |k: usize| {
            let i = &self.instances[k];
            if i.ground {
                ground.is_some()
            } else {
                i.drawable && !settings.hidden.contains(k)
            }
        };
        c.meshes.resize(self.meshes.len(), None);
        let mut wanted: Vec<usize> = (0..self.instances.len())
            .filter(|&k| shown(k))
            .map(|k| self.instances[k].mesh)
            .filter(|&m| c.meshes[m].is_none())
            .collect();
        wanted.sort_unstable();
        wanted.dedup();
        let built: Vec<(usize, trace::Mesh)> = wanted
            .par_iter()
            .map(|&m| {
                let t = &self.meshes[m].tri;
                (m, trace::Mesh::new(&t.positions, &t.triangles))
            })
            .collect();
        for (m, h) in built {
            c.meshes[m] = Some(Arc::new(h));
        }
        let mut instances = Vec::new();
        for (k, inst) in self.instances.iter().enumerate() {
            if !shown(k) {
                continue;
            }
            for copy in 0..inst.copy_count() {
                let world = match (inst.ground, ground) {
                    (true, Some(g)) => g,
                    _ => inst.placement(copy),
                };
                let key = (k as u64) << 32 | copy as u64;
                if let Some(i) = trace::Instance::new(inst.mesh as u32, key, world) {
                    instances.push(i);
                }
            }
        }
        // Mesh slots line up with the prepared meshes (unbuilt ones are empty).
        let meshes = c
            .meshes
            .iter()
            .map(|m| m.clone().unwrap_or_default())
            .collect();
        let scene = Arc::new(trace::Scene::assemble(meshes, instances));
        c.scene = Some((key, Arc::clone(&scene)));
        scene
    }
}
