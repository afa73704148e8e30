//! The session: opening, reloading and saving files (models and scene files), the built-in demo, the texture lab's coordinates, the recent list and the file watcher, and the background work that finishes them.

use super::*;

impl ViewerApp {
    /// Starts loading `path`, a model or a scene file (in the background, or now in
    /// synchronous mode).
    pub fn open(&mut self, path: PathBuf) {
        if let Some(t) = self.loading.take() {
            t.cancel();
        }
        // A reload keeps the UV choice; another file starts with its own coordinates.
        let same = self.model.as_deref() == Some(path.as_path());
        let uv = self.uv.filter(|_| same && !loader::is_scene_file(&path));
        if self.synchronous {
            let out = loader::load_now(&path, self.normals, uv, None);
            self.finish_load(out);
        } else {
            self.loading = Some(LoadTask::start(
                path,
                self.normals,
                uv,
                Arc::clone(&self.repaint),
            ));
        }
    }

    /// Installs a finished load, or shows its error (the current scene stays).
    pub(super) fn finish_load(&mut self, out: loader::Outcome) {
        match out {
            Ok(Loaded {
                path,
                mut scene,
                base,
                uv,
                millis,
                from_file,
            }) => {
                // An animated scene is framed on where it moves, not only its rest pose.
                self.motion_sphere =
                    Arc::get_mut(&mut scene).and_then(crate::timeline::motion_sphere);
                let (center, radius) = self
                    .motion_sphere
                    .unwrap_or_else(|| scene.bounding_sphere());
                let aspect = self.viewport.aspect();
                let same = self.model.as_deref() == Some(path.as_path());
                let file = from_file.is_some();
                // The up axis stays as it was (`--up`, Ctrl+Y / Ctrl+Z) unless a scene file
                // names one.
                let up = match &from_file {
                    Some(f) if f.open.file.doc.up.is_some() => f.open.file.up().into(),
                    _ => self.nav.up_axis(),
                };
                let fresh = if let Some(f) = from_file {
                    // A scene file (opened or reloaded) sets everything it names: its
                    // settings now, its camera once the viewport's aspect is known.
                    self.nav = Navigator::new(center, radius, aspect);
                    self.nav.set_up_axis(up, aspect);
                    self.frame_pending = true;
                    self.install_file_settings(f, &path);
                    true
                } else if same {
                    // A reload keeps the camera; only the scene's extent may have changed.
                    self.nav.new_scene(center, radius, aspect);
                    false
                } else {
                    self.nav = Navigator::new(center, radius, aspect);
                    self.nav.set_up_axis(up, aspect);
                    self.frame_pending = true;
                    self.settings.materials = None;
                    true
                };
                if self.scene_file.is_some() && !loader::is_scene_file(&path) {
                    self.scene_file = None;
                }
                // A UV choice made during a reload of this model is generated next.
                let wanted = self.uv;
                let again = same && !loader::is_scene_file(&path) && wanted != uv;
                self.scene = scene;
                self.base = base;
                (self.uv, self.shown_uv, self.uv_task) = (uv, uv, None);
                if again {
                    self.set_uv_generator(wanted);
                }
                self.load_millis = Some(millis);
                self.error = None;
                self.recent.add(&path);
                self.save_state();
                self.watch(&path);
                self.model = Some(path);
                self.shared.probe = None;
                let taken = file.then(|| self.settings.clone());
                self.installed(fresh, taken.as_ref());
            }
            Err(e) => {
                // Also on stderr, for whoever started the viewer from a terminal.
                eprintln!("realist: {e}");
                if self.model.is_none() && self.scene.scene().instances.is_empty() {
                    // The first model failed: show the demo rather than nothing.
                    self.open_demo();
                }
                self.error = Some(e);
            }
        }
    }

    /// Takes a scene file's settings (the camera follows in the next UI pass).
    pub(super) fn install_file_settings(&mut self, f: FromFile, path: &Path) {
        let FromFile {
            open,
            settings,
            notes,
        } = f;
        // The split view's B side follows A's fog, shadows and ground (as the panel keeps
        // it); fog and ground turned off and on again come back as the file set them.
        self.split.b.fog = settings.fog;
        self.split.b.shadow = settings.shadow;
        self.split.b.ground = settings.ground;
        self.settings = settings;
        self.scene_file = Some(open);
        let mut notice = format!("opened scene file {}", path.display());
        for n in notes {
            notice += &format!("; {n}");
        }
        self.notice = Some(notice);
    }

    /// The open scene file's camera for a viewport of `aspect` (without a `[camera]`, the
    /// demo's own camera for `model = "demo"`, as `realist render` takes it); `None` when no
    /// scene file is open or it leaves the view to the viewer's framing.
    pub(super) fn file_camera(&self, aspect: f32) -> Result<Option<scene::Camera>, String> {
        let Some(f) = &self.scene_file else {
            return Ok(None);
        };
        let scene = self.scene.scene();
        match f.file.camera(scene, aspect).map_err(|e| e.to_string())? {
            Some(c) => Ok(Some(c)),
            None if f.model == ModelSource::Demo => Ok(scene.cameras.first().cloned()),
            None => Ok(None),
        }
    }

    /// What [`ViewerApp::save_scene`] writes about the model: the open scene file's model
    /// and light scale, the model file (absolute), or the demo.
    #[must_use]
    pub fn model_source(&self) -> (ModelSource, f32) {
        match (&self.scene_file, &self.model) {
            (Some(f), _) => (f.model.clone(), f.light_scale),
            (None, Some(m)) => (
                ModelSource::File(std::path::absolute(m).unwrap_or_else(|_| m.clone())),
                1.0,
            ),
            (None, None) => (ModelSource::Demo, 1.0),
        }
    }

    /// Where "Save scene" writes unless told otherwise: the open scene file, else
    /// `scene.toml` next to the model (or in the working folder for the demo).
    #[must_use]
    pub fn default_save_path(&self) -> String {
        let path = match (&self.scene_file, &self.model) {
            (Some(f), _) => f.file.path.clone(),
            (None, Some(m)) => match m.parent() {
                Some(dir) if !dir.as_os_str().is_empty() => dir.join("scene.toml"),
                _ => PathBuf::from("scene.toml"),
            },
            (None, None) => PathBuf::from("scene.toml"),
        };
        path.display().to_string()
    }

    /// Saves the current scene (model, settings, camera at the viewport's size) as a scene
    /// file at `path` (`.toml` or `.json`), which becomes the open scene file. The viewer's
    /// refinement (`max_samples`) is saved as the file's `samples`, so `realist render`
    /// gives the still frame on screen. Returns the notes on what was left out.
    ///
    /// # Errors
    /// The one-line message (naming the file) when the extension is wrong or the file
    /// cannot be written; nothing changes then.
    pub fn save_scene(&mut self, path: &Path) -> Result<Vec<String>, String> {
        let (model, light_scale) = self.model_source();
        let settings = Settings {
            samples: self.max_samples,
            ..self.settings.clone()
        };
        let view = self.current_view();
        let (mut file, notes) = SceneFile::from_settings(&model, light_scale, &settings, &view);
        file.set_uv(self.uv);
        file.save(path).map_err(|e| e.to_string())?;
        // The saved file is now the one open (as "save as" does); the recent list and the
        // watcher follow, the watcher anew so that this write is not taken for a change.
        self.scene_file = Some(OpenScene {
            file,
            model,
            light_scale,
        });
        self.recent.add(path);
        self.save_state();
        self.watch(path);
        self.file_changed.store(false, Ordering::SeqCst);
        self.model = Some(path.to_owned());
        Ok(notes)
    }

    /// Watches the current model for changes (reloaded when it changes on disk).
    pub(super) fn watch(&mut self, path: &Path) {
        if self.synchronous {
            return;
        }
        let (flag, repaint) = (Arc::clone(&self.file_changed), Arc::clone(&self.repaint));
        self.watcher = FileWatcher::new(
            path,
            Box::new(move || {
                flag.store(true, Ordering::SeqCst);
                repaint();
            }),
        )
        .ok();
    }

    /// Shows the built-in demo scene again.
    pub fn open_demo(&mut self) {
        if let Some(t) = self.loading.take() {
            t.cancel();
        }
        let scene = Arc::new(PreparedScene::new(scene::demo()));
        self.motion_sphere = None;
        self.base = Arc::clone(scene.scene());
        (self.uv, self.shown_uv, self.uv_task) = (None, None, None);
        let (center, radius) = scene.bounding_sphere();
        self.nav = match scene.scene().cameras.first() {
            Some(cam) => Navigator::from_camera(cam, center, radius, Default::default()),
            None => Navigator::new(center, radius, self.viewport.aspect()),
        };
        self.scene = scene;
        self.frame_pending = true;
        self.model = None;
        self.scene_file = None;
        self.watcher = None;
        self.settings.materials = None;
        self.installed(true, None);
    }

    /// Tells the panels that a scene was installed (`fresh`: another scene; `settings`: a
    /// scene file's), and forgets the probed pixel, the hovered light and the hidden parts.
    pub(super) fn installed(&mut self, fresh: bool, settings: Option<&Settings>) {
        if fresh {
            self.shared.probe = None;
            self.shared.hovered_light = None;
            // Hidden parts are the old scene's instance numbers and variants its names (a
            // reload keeps them; a scene file brings its own).
            if settings.is_none() {
                self.settings.hidden = Default::default();
                self.settings.variant = None;
            }
            self.split.b.hidden = self.settings.hidden.clone();
            self.split.b.variant.clone_from(&self.settings.variant);
        }
        self.panels.installed(&Installed {
            fresh,
            settings,
            save_path: self.default_save_path(),
        });
    }

    /// Opens the previous (`step` = -1) or next (+1) model in the current model's folder.
    pub fn step_file(&mut self, step: i32) {
        match self.model.as_deref().and_then(|m| sibling_model(m, step)) {
            Some(p) => self.open(p),
            None => self.notice = Some("no other model in this folder".into()),
        }
    }

    /// Draws the model with the texture coordinates of `uv` (the textbook's §9.5; `None`:
    /// the file's own): generated from the scene as loaded, off the UI thread (now in
    /// synchronous mode), then drawn in place of the scene on screen. The camera, the
    /// settings and the split view stay as they are.
    pub fn set_uv_generator(&mut self, uv: Option<UvGenerator>) {
        self.uv = uv;
        if uv == self.shown_uv {
            self.uv_task = None;
            return;
        }
        if self.uv_task.as_ref().is_some_and(|t| t.uv == uv) {
            return;
        }
        if self.synchronous {
            let scene = Arc::new(lab::prepare(&self.base, uv));
            self.install_uv(scene, uv);
        } else {
            self.uv_task = Some(UvTask::start(
                Arc::clone(&self.base),
                uv,
                Arc::clone(&self.repaint),
            ));
        }
    }

    /// Draws `scene`, the scene as loaded with the coordinates of `uv`.
    pub(super) fn install_uv(&mut self, scene: Arc<PreparedScene>, uv: Option<UvGenerator>) {
        self.scene = scene;
        self.shown_uv = uv;
        self.uv_task = None;
        // The probe's UV and shading belong to the old coordinates.
        self.shared.probe = None;
        self.notice = Some(match uv {
            None => "texture coordinates: the model's own".to_owned(),
            Some(g) => {
                format!("texture coordinates: the {g} map on every mesh (the textbook's §9.5)")
            }
        });
    }

    /// Reloads the current model.
    pub fn reload(&mut self) {
        if let Some(m) = self.model.clone() {
            self.open(m);
        }
    }

    /// Saves what persists between runs (the recent files).
    pub fn save_state(&mut self) {
        // Losing the recent list is not worth an error dialog.
        let _ = match &self.recent_file {
            Some(p) => self.recent.save_to(p),
            None => self.recent.save(),
        };
    }

    /// Saves the scene file at `path` ([`ViewerApp::save_scene`]) and says how it went in
    /// the status bar and the scene file section.
    pub fn save_scene_reported(&mut self, path: &Path) {
        let result = if path.as_os_str().is_empty() {
            Err("no path to save the scene file to".to_owned())
        } else {
            self.save_scene(path).map(|notes| {
                let shown = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
                let mut msg = format!("saved scene file {}", shown.display());
                if !notes.is_empty() {
                    msg += &format!(" (left out: {})", notes.join("; "));
                }
                msg
            })
        };
        match &result {
            Ok(msg) => {
                self.notice = Some(msg.clone());
                self.error = None;
            }
            Err(e) => self.error = Some(e.clone()),
        }
        self.saved = Some(result);
    }

    /// Loads that finished (models, texture coordinates), and files that changed on disk
    /// (the panels' own background work is theirs: [`Panel::poll`]).
    pub(super) fn poll_background(&mut self) {
        if let Some(out) = self.loading.as_ref().and_then(LoadTask::poll) {
            self.loading = None;
            self.finish_load(out);
        }
        let uv = self
            .uv_task
            .as_ref()
            .and_then(|t| Some((Arc::clone(&t.base), t.uv, t.poll()?)));
        if let Some((base, uv, out)) = uv {
            self.uv_task = None;
            match out {
                // Made for a scene since replaced (a load finished meanwhile): dropped.
                Ok(_) if !Arc::ptr_eq(&base, &self.base) => {}
                Ok(scene) => self.install_uv(scene, uv),
                Err(e) => {
                    self.uv = self.shown_uv;
                    self.error = Some(e);
                }
            }
        }
        if self.file_changed.swap(false, Ordering::SeqCst) && self.loading.is_none() {
            self.notice = Some("file changed on disk: reloaded".into());
            self.reload();
        }
    }
}
