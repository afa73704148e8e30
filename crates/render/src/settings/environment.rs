//! The environment that lights the `pbr` draws: none, the built-in studio, or an image
//! loaded, prefiltered and cached.

use std::sync::Arc;

use crate::texture::env::{default_cache_dir, EnvCache, EnvImage, EnvView, Prefiltered};

/// The environment that lights the `pbr` draws (image-based lighting): diffuse irradiance
/// from its spherical harmonics, specular from its prefiltered chain (the split sum).
#[derive(Clone, Debug, Default)]
pub enum Environment {
    /// The built-in studio ([`EnvImage::studio`]), as [`Environment::builtin`] gives it.
    #[default]
    Auto,
    /// No environment: the lights, and the ambient light as a uniform environment.
    Off,
    On(EnvView),
}

impl PartialEq for Environment {
    fn eq(&self, o: &Self) -> bool {
        match (self, o) {
            (Environment::Auto, Environment::Auto) | (Environment::Off, Environment::Off) => true,
            (Environment::On(a), Environment::On(b)) => {
                Arc::ptr_eq(&a.env, &b.env)
                    && a.rotation_deg == b.rotation_deg
                    && a.intensity == b.intensity
            }
            (Environment::Auto | Environment::Off | Environment::On(_), _) => false,
        }
    }
}

impl Environment {
    /// The built-in environment `name` ("studio", "sky", "uniform": radiance 1),
    /// prefiltered on first use and kept for the process and, like a file's, on disk in
    /// [`default_cache_dir`] (prefiltering the studio costs about 200 ms of CPU; reading it
    /// back about 2 ms). A cache that cannot be read or written is passed over silently:
    /// the result is the same either way.
    #[must_use]
    pub fn builtin(name: &str) -> Option<Arc<Prefiltered>> {
        let image = EnvImage::builtin(name)?;
        let disk = default_cache_dir();
        Some(EnvCache::global().get_or_build(image, disk.as_deref()).env)
    }

    /// The environment a command line or scene file names: `none` (or `off`), a built-in
    /// (`studio`, `sky`, `uniform`) or an equirectangular `.hdr` / `.exr` image at
    /// `path(name)`, prefiltered once and kept by content (in memory, and on disk in
    /// `cache`). Returns it with a note for the user when the disk cache could not be
    /// used, or an error naming the file and the problem.
    ///
    /// # Errors
    /// The image cannot be read or is not a usable environment.
    pub fn named(
        name: &str,
        path: impl FnOnce(&str) -> std::path::PathBuf,
        cache: Option<&std::path::Path>,
    ) -> Result<(Environment, Option<String>), String> {
        if matches!(name, "none" | "off") {
            return Ok((Environment::Off, None));
        }
        if let Some(env) = Environment::builtin(name) {
            return Ok((Environment::On(EnvView::new(env)), None));
        }
        let image = EnvImage::load(&path(name)).map_err(|e| e.to_string())?;
        let cached = EnvCache::global().get_or_build(image, cache);
        Ok((Environment::On(EnvView::new(cached.env)), cached.disk_note))
    }

    /// This environment turned to `rotate` degrees and scaled to `intensity` (each if
    /// given): an error names the bad value, or says there is no environment to turn.
    ///
    /// # Errors
    /// A value is not finite (or the intensity negative), or the environment is off.
    pub fn adjusted(
        self,
        rotate: Option<f32>,
        intensity: Option<f32>,
    ) -> Result<Environment, String> {
        if rotate.is_none() && intensity.is_none() {
            return Ok(self);
        }
        let Some(mut view) = self.view() else {
            return Err("the environment is off: nothing to turn or scale".into());
        };
        if let Some(deg) = rotate {
            if !deg.is_finite() {
                return Err(format!("rotation {deg}: expected degrees"));
            }
            view.rotation_deg = deg;
        }
        if let Some(x) = intensity {
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!("intensity {x}: expected a number at least 0"));
            }
            view.intensity = x;
        }
        Ok(Environment::On(view))
    }

    /// What the frame lights with: `None` when off.
    #[must_use]
    pub fn view(&self) -> Option<EnvView> {
        match self {
            Environment::Auto => {
                static STUDIO: std::sync::OnceLock<Option<Arc<Prefiltered>>> =
                    std::sync::OnceLock::new();
                let env = STUDIO.get_or_init(|| Environment::builtin("studio"));
                env.clone().map(EnvView::new)
            }
            Environment::Off => None,
            Environment::On(v) => Some(v.clone()),
        }
    }
}
