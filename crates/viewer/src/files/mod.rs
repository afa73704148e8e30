//! Files the viewer needs besides the model itself: the recent-files list kept in the user's
//! config folder, the previous/next model in the current model's folder, and a watcher that
//! reports when the open model changes on disk ([`FileWatcher`]). No egui; errors are returned
//! or reported as one-line messages, never panics.
//!
//! # Conventions
//! - Paths in the recent list are absolute and canonical when they can be (symlinks
//!   resolved), most recent first, at most [`MAX_RECENT`].
//! - The config folder is `$XDG_CONFIG_HOME/realist`, else `$HOME/.config/realist`
//!   ([`config_dir`]); the list lives in `recent.json` there.
//! - Models are files named `*.obj`, `*.gltf` or `*.glb`, any case ([`is_model`]); folders
//!   are listed in natural order ([`natural_cmp`]: "model2" before "model10").

use std::cmp::Ordering;
use std::ffi::OsString;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

mod watch;

#[cfg(test)]
mod tests;

pub use watch::{FileWatcher, POLL_INTERVAL};

/// The most paths [`RecentFiles`] keeps.
pub const MAX_RECENT: usize = 12;
/// Extensions of the files the viewer opens, lower case, without the dot.
pub const MODEL_EXTENSIONS: [&str; 5] = ["obj", "gltf", "glb", "stl", "ply"];
/// A recent-files list larger than this (bytes) is treated as corrupt.
const MAX_LIST_BYTES: u64 = 1 << 20;

/// The viewer's config folder: `$XDG_CONFIG_HOME/realist`, else `$HOME/.config/realist`
/// (relative values are ignored, as the XDG spec asks); `None` when neither is usable.
#[must_use]
pub fn config_dir() -> Option<PathBuf> {
    config_dir_from(
        std::env::var_os("XDG_CONFIG_HOME"),
        std::env::var_os("HOME"),
    )
}

fn config_dir_from(xdg: Option<OsString>, home: Option<OsString>) -> Option<PathBuf> {
    let absolute = |v: OsString| Some(PathBuf::from(v)).filter(|p| p.is_absolute());
    xdg.and_then(absolute)
        .or_else(|| home.and_then(absolute).map(|h| h.join(".config")))
        .map(|dir| dir.join("realist"))
}

/// Whether `path` names a model file by its extension (case-insensitive).
#[must_use]
pub fn is_model(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| MODEL_EXTENSIONS.iter().any(|m| e.eq_ignore_ascii_case(m)))
}

/// The on-disk form of the list.
#[derive(Serialize, Deserialize)]
struct Stored {
    version: u32,
    files: Vec<String>,
}

/// Recently opened models, most recent first, deduplicated by canonical path, at most
/// [`MAX_RECENT`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RecentFiles {
    paths: Vec<PathBuf>,
}

impl RecentFiles {
    /// `recent.json` in [`config_dir`].
    #[must_use]
    pub fn default_path() -> Option<PathBuf> {
        config_dir().map(|dir| dir.join("recent.json"))
    }

    /// Loads from [`RecentFiles::default_path`]; see [`RecentFiles::load_from`].
    #[must_use]
    pub fn load() -> (Self, Option<String>) {
        match Self::default_path() {
            Some(path) => Self::load_from(&path),
            None => (
                Self::default(),
                Some("recent files: neither XDG_CONFIG_HOME nor HOME is set".into()),
            ),
        }
    }

    /// Loads a list saved by [`RecentFiles::save_to`]. A missing file is an empty list; an
    /// unreadable, oversized or corrupt one is an empty list plus a one-line message.
    /// Entries are kept even if their files are gone ([`RecentFiles::list`] drops those).
    #[must_use]
    pub fn load_from(path: &Path) -> (Self, Option<String>) {
        let fail = |why: String| {
            let message = format!("recent files {}: {why}; starting empty", path.display());
            (Self::default(), Some(message))
        };
        let text = match read_small(path) {
            Ok(text) => text,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return (Self::default(), None),
            Err(e) => return fail(e.to_string()),
        };
        let stored: Stored = match serde_json::from_str(&text) {
            Ok(stored) => stored,
            Err(e) => return fail(format!("not a recent-files list ({e})")),
        };
        let mut list = Self::default();
        for file in stored.files.iter().rev() {
            let file = Path::new(file);
            if file.is_absolute() {
                list.push_front(canonical(file).unwrap_or_else(|| file.to_owned()));
            }
        }
        (list, None)
    }

    /// Saves to [`RecentFiles::default_path`]; see [`RecentFiles::save_to`].
    pub fn save(&self) -> io::Result<()> {
        let path = Self::default_path().ok_or_else(|| {
            io::Error::new(
                io::ErrorKind::NotFound,
                "neither XDG_CONFIG_HOME nor HOME is set",
            )
        })?;
        self.save_to(&path)
    }

    /// Writes the list as JSON, atomically: to a temporary file beside `path`, then renamed
    /// over it, so a crash never leaves a half-written list. Creates the folder if needed.
    /// Paths that are not valid UTF-8 cannot be stored in JSON and are left out.
    pub fn save_to(&self, path: &Path) -> io::Result<()> {
        let stored = Stored {
            version: 1,
            files: self
                .paths
                .iter()
                .filter_map(|p| p.to_str().map(str::to_owned))
                .collect(),
        };
        let json = serde_json::to_vec_pretty(&stored).map_err(io::Error::other)?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let mut name = path.file_name().unwrap_or(path.as_os_str()).to_owned();
        name.push(format!(".{}.tmp", std::process::id()));
        let temp = path.with_file_name(name);
        let written = (|| {
            let mut file = std::fs::File::create(&temp)?;
            file.write_all(&json)?;
            file.write_all(b"\n")?;
            file.sync_all()?;
            std::fs::rename(&temp, path)
        })();
        if written.is_err() {
            let _ = std::fs::remove_file(&temp);
        }
        written
    }

    /// Puts `path` first (moving it up if already listed, by canonical path), dropping the
    /// oldest beyond [`MAX_RECENT`]. A path that cannot be made absolute is ignored.
    pub fn add(&mut self, path: &Path) {
        let path = canonical(path).or_else(|| std::path::absolute(path).ok());
        if let Some(path) = path {
            self.push_front(path);
        }
    }

    /// Removes `path` (compared by canonical path when it still exists).
    pub fn remove(&mut self, path: &Path) {
        let path = canonical(path).unwrap_or_else(|| path.to_owned());
        self.paths.retain(|p| *p != path);
    }

    pub fn clear(&mut self) {
        self.paths.clear();
    }

    /// The entries whose files still exist, most recent first; the others are dropped.
    pub fn list(&mut self) -> &[PathBuf] {
        self.paths.retain(|p| p.is_file());
        &self.paths
    }

    /// All entries as stored, without checking the files.
    #[must_use]
    pub fn paths(&self) -> &[PathBuf] {
        &self.paths
    }

    fn push_front(&mut self, path: PathBuf) {
        self.paths.retain(|p| *p != path);
        self.paths.insert(0, path);
        self.paths.truncate(MAX_RECENT);
    }
}

/// The canonical form of `path` if it exists.
fn canonical(path: &Path) -> Option<PathBuf> {
    path.canonicalize().ok()
}

/// Reads a text file of at most [`MAX_LIST_BYTES`].
fn read_small(path: &Path) -> io::Result<String> {
    let file = std::fs::File::open(path)?;
    let mut text = String::new();
    file.take(MAX_LIST_BYTES + 1).read_to_string(&mut text)?;
    if text.len() as u64 > MAX_LIST_BYTES {
        return Err(io::Error::new(io::ErrorKind::InvalidData, "file too large"));
    }
    Ok(text)
}

/// The model `step` places after `current` (negative: before) among the models in its
/// folder, in [`natural_cmp`] order of file names, wrapping around. `current` need not still
/// exist (it then counts from where it would sort). `None` when the folder cannot be read or
/// the step lands on `current` itself (e.g. it is the only model). The result is `current`
/// with its file name replaced.
#[must_use]
pub fn sibling_model(current: &Path, step: i32) -> Option<PathBuf> {
    let name = current.file_name()?.to_string_lossy().into_owned();
    let dir = match current.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(Result::ok)
        .map(|entry| entry.path())
        .filter(|path| is_model(path) && path.is_file())
        .filter_map(|path| path.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    names.push(name.clone());
    names.sort_by(|a, b| natural_cmp(a, b));
    names.dedup();
    let here = names.iter().position(|n| *n == name)?;
    let count = i64::try_from(names.len()).ok()?;
    let there = usize::try_from((here as i64 + i64::from(step)).rem_euclid(count)).ok()?;
    (there != here).then(|| current.with_file_name(&names[there]))
}

/// Natural order of file names: runs of ASCII digits compare as numbers ("model2" <
/// "model10"), other characters case-insensitively; ties fall back to plain byte order, so
/// the order is total.
#[must_use]
pub fn natural_cmp(a: &str, b: &str) -> Ordering {
    let (mut x, mut y) = (a, b);
    loop {
        match (x.chars().next(), y.chars().next()) {
            (None, None) => return a.cmp(b),
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
            (Some(c), Some(d)) if c.is_ascii_digit() && d.is_ascii_digit() => {
                let (nx, rest_x) = split_digits(x);
                let (ny, rest_y) = split_digits(y);
                let (tx, ty) = (nx.trim_start_matches('0'), ny.trim_start_matches('0'));
                let order = tx.len().cmp(&ty.len()).then_with(|| tx.cmp(ty));
                if order != Ordering::Equal {
                    return order;
                }
                (x, y) = (rest_x, rest_y);
            }
            (Some(c), Some(d)) => {
                let order = c.to_lowercase().cmp(d.to_lowercase());
                if order != Ordering::Equal {
                    return order;
                }
                (x, y) = (&x[c.len_utf8()..], &y[d.len_utf8()..]);
            }
        }
    }
}

/// Splits a string into its leading run of ASCII digits and the rest.
fn split_digits(s: &str) -> (&str, &str) {
    s.split_at(s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len()))
}
