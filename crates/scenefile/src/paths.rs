//! Paths written in a file are relative to its folder; [`rebase`] rewrites them for a
//! file written somewhere else.

use std::path::{Component, Path, PathBuf};

use super::schema::SceneDoc;

/// `doc` with every path (model, texture, light images, output), read relative to
/// `from`, made relative to the folder of `dest` (absolute when the two share no root).
pub(super) fn rebase(doc: &SceneDoc, from: &Path, dest: &Path) -> SceneDoc {
    let to = match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    let fix = |p: &mut String| *p = relative(&absolute(&from.join(&*p)), &absolute(&to));
    let mut doc = doc.clone();
    if let Some(m) = doc.model.as_mut().filter(|m| *m != "demo") {
        fix(m);
    }
    // Procedural names (`checker:8`, `noise:0.02`) are not paths.
    let image = |p: &&mut String| {
        p.parse::<crate::texture::Procedural>().is_err()
            && !p.to_ascii_lowercase().starts_with("noise:")
    };
    doc.texture.iter_mut().filter(image).for_each(fix);
    doc.bump.iter_mut().filter(image).for_each(fix);
    doc.output.iter_mut().for_each(fix);
    let named = |p: &&mut String| {
        !matches!(p.as_str(), "none" | "off") && crate::texture::env::EnvImage::builtin(p).is_none()
    };
    doc.env.iter_mut().filter(named).for_each(fix);
    for l in &mut doc.light {
        l.image.iter_mut().for_each(fix);
    }
    doc
}

/// `p` made absolute and free of `.`/`..` (canonical when it exists).
fn absolute(p: &Path) -> PathBuf {
    if let Ok(c) = std::fs::canonicalize(p) {
        return c;
    }
    lexically_absolute(&std::env::current_dir().unwrap_or_default(), p)
}

/// `p` made absolute against `cwd` (unless it is already) with `.` and `..` resolved
/// lexically: no symbolic links followed, so it does not need the file to exist.
#[must_use]
pub fn lexically_absolute(cwd: &Path, p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in cwd.join(p).components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// `target` relative to folder `base` (both absolute), with `/` separators.
fn relative(target: &Path, base: &Path) -> String {
    let t: Vec<Component> = target.components().collect();
    let b: Vec<Component> = base.components().collect();
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    // Nothing shared but the root (or another drive): keep it absolute.
    if common <= 1 {
        return target.display().to_string();
    }
    let mut parts: Vec<String> = vec!["..".into(); b.len() - common];
    parts.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    if parts.is_empty() {
        ".".into()
    } else {
        parts.join("/")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_climb_and_descend() {
        let r = |t: &str, b: &str| relative(Path::new(t), Path::new(b));
        assert_eq!(r("/a/b/models/x.obj", "/a/b/scenes"), "../models/x.obj");
        assert_eq!(r("/a/b/x.obj", "/a/b"), "x.obj");
        assert_eq!(r("/a/b/c/d.png", "/a/e/f"), "../../b/c/d.png");
        assert_eq!(r("/x/y.obj", "/a/b"), "/x/y.obj");
    }
}
