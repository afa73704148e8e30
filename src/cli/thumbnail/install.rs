//! `realist thumbnail --install [--user]` and `--uninstall`: the freedesktop thumbnailer
//! entry (`thumbnailers/realist.thumbnailer`, read by GNOME's file manager and other
//! freedesktop desktops) and a shared-mime-info package (`mime/packages/realist.xml`) giving
//! every model format realist reads a type and glob, under /usr/share or the user's data
//! folder (`$XDG_DATA_HOME`, default `~/.local/share`).

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, Context, Result};

/// The thumbnailer entry's file name under `thumbnailers/`.
pub(super) const ENTRY: &str = "realist.thumbnailer";
/// The shared-mime-info package's file name under `mime/packages/`.
pub(super) const PACKAGE: &str = "realist.xml";

/// A model format: its MIME type (shared-mime-info's name where it has one), a comment,
/// the glob and a magic string at offset 0, if any.
struct Format {
    mime: &'static str,
    comment: &'static str,
    glob: &'static str,
    magic: Option<&'static str>,
}

/// The model formats realist reads. glTF, GLB, OBJ and STL have the types of
/// freedesktop.org.xml (shared-mime-info); PLY has none there, and `application/x-ply` is
/// the name other tools register. Scene files (.toml, .json) are not claimed: their types
/// are generic.
const FORMATS: [Format; 5] = [
    Format {
        mime: "model/gltf+json",
        comment: "glTF model",
        glob: "*.gltf",
        magic: None,
    },
    Format {
        mime: "model/gltf-binary",
        comment: "glTF binary model",
        glob: "*.glb",
        magic: Some("glTF"),
    },
    Format {
        mime: "model/obj",
        comment: "OBJ 3D model",
        glob: "*.obj",
        magic: None,
    },
    Format {
        mime: "model/stl",
        comment: "STL 3D model",
        glob: "*.stl",
        magic: None,
    },
    Format {
        mime: "application/x-ply",
        comment: "PLY 3D model",
        glob: "*.ply",
        magic: Some("ply\\n"),
    },
];

/// Where the files go: /usr/share, or for `user` `$XDG_DATA_HOME` (if absolute) else
/// `$HOME/.local/share`.
fn data_dir(user: bool) -> Result<PathBuf> {
    if !user {
        return Ok(PathBuf::from("/usr/share"));
    }
    let absolute = |v: &str| {
        std::env::var_os(v)
            .map(PathBuf::from)
            .filter(|p| p.is_absolute())
    };
    match (absolute("XDG_DATA_HOME"), absolute("HOME")) {
        (Some(d), _) => Ok(d),
        (None, Some(h)) => Ok(h.join(".local").join("share")),
        (None, None) => bail!("--user: neither XDG_DATA_HOME nor HOME is set"),
    }
}

pub(super) fn install(user: bool) -> Result<()> {
    let data = data_dir(user)?;
    let exe = std::env::current_exe()
        .and_then(|p| p.canonicalize())
        .context("could not find this program's own path")?;
    let entry = data.join("thumbnailers").join(ENTRY);
    let package = data.join("mime").join("packages").join(PACKAGE);
    write(&entry, &thumbnailer_entry(&exe), user)?;
    write(&package, &mime_package(), user)?;
    println!("wrote {}", entry.display());
    println!("wrote {}", package.display());
    update_mime_database(&data.join("mime"));
    Ok(())
}

pub(super) fn uninstall(user: bool) -> Result<()> {
    let data = data_dir(user)?;
    for path in [
        data.join("thumbnailers").join(ENTRY),
        data.join("mime").join("packages").join(PACKAGE),
    ] {
        match std::fs::remove_file(&path) {
            Ok(()) => println!("removed {}", path.display()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                println!("{} was not there", path.display());
            }
            Err(e) => {
                return Err(e).with_context(|| format!("could not remove {}", path.display()))
            }
        }
    }
    update_mime_database(&data.join("mime"));
    Ok(())
}

fn write(path: &Path, text: &str, user: bool) -> Result<()> {
    let parent = path.parent().unwrap_or(Path::new("."));
    let hint = if user {
        ""
    } else {
        " (--user installs for this user alone)"
    };
    std::fs::create_dir_all(parent)
        .with_context(|| format!("could not create {}{hint}", parent.display()))?;
    super::guard::write_atomic(path, text.as_bytes()).with_context(|| hint.to_string())
}

/// Runs `update-mime-database DIR` if the program is there; says so if not (the types
/// are then known after the next run of it, e.g. by the package manager).
fn update_mime_database(dir: &Path) {
    match Command::new("update-mime-database").arg(dir).status() {
        Ok(s) if s.success() => println!("ran update-mime-database {}", dir.display()),
        Ok(s) => eprintln!(
            "warning: update-mime-database {} failed ({s})",
            dir.display()
        ),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            println!("update-mime-database is not installed: the MIME types are known once it runs")
        }
        Err(e) => eprintln!("warning: could not run update-mime-database: {e}"),
    }
}

/// The `[Thumbnailer Entry]` for the binary at `exe`.
pub(super) fn thumbnailer_entry(exe: &Path) -> String {
    let mimes: Vec<&str> = FORMATS.iter().map(|f| f.mime).collect();
    let exe = exe.to_string_lossy();
    format!(
        "[Thumbnailer Entry]\n\
         TryExec={}\n\
         Exec={} thumbnail --size %s %i %o\n\
         MimeType={};\n",
        key_file_escape(&exe),
        key_file_escape(&exec_quote(&exe)),
        mimes.join(";")
    )
}

/// An argument of an `Exec` line: as it is when it needs no quoting, else in double quotes
/// with `"`, `` ` ``, `$` and `\` escaped (the desktop entry specification); `%` doubled.
fn exec_quote(arg: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "/._+-,:@".contains(c);
    let arg = arg.replace('%', "%%");
    if arg.chars().all(plain) {
        return arg;
    }
    let mut q = String::from("\"");
    for c in arg.chars() {
        if matches!(c, '"' | '`' | '$' | '\\') {
            q.push('\\');
        }
        q.push(c);
    }
    q.push('"');
    q
}

/// A key file value: backslashes doubled, line breaks as `\n`.
fn key_file_escape(s: &str) -> String {
    s.replace('\\', "\\\\").replace('\n', "\\n")
}

/// The shared-mime-info package.
pub(super) fn mime_package() -> String {
    let mut xml = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <!-- Written by realist (thumbnail, install): the model formats realist reads. -->\n\
         <mime-info xmlns=\"http://www.freedesktop.org/standards/shared-mime-info\">\n",
    );
    for f in &FORMATS {
        xml.push_str(&format!(
            "  <mime-type type=\"{}\">\n    <comment>{}</comment>\n",
            f.mime, f.comment
        ));
        if let Some(m) = f.magic {
            xml.push_str(&format!(
                "    <magic priority=\"50\">\n      <match type=\"string\" value=\"{m}\" \
                 offset=\"0\"/>\n    </magic>\n"
            ));
        }
        xml.push_str(&format!(
            "    <glob pattern=\"{}\"/>\n  </mime-type>\n",
            f.glob
        ));
    }
    xml.push_str("</mime-info>\n");
    xml
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exec_line_quotes_what_needs_it() {
        assert_eq!(exec_quote("/usr/bin/realist"), "/usr/bin/realist");
        assert_eq!(
            exec_quote("/opt/my tools/re$al\"ist%"),
            "\"/opt/my tools/re\\$al\\\"ist%%\""
        );
        let e = thumbnailer_entry(Path::new("/a b/realist"));
        assert!(
            e.contains("Exec=\"/a b/realist\" thumbnail --size %s %i %o\n"),
            "{e}"
        );
        assert!(e.contains("TryExec=/a b/realist\n"), "{e}");
    }

    #[test]
    fn package_names_every_format() {
        let xml = mime_package();
        for f in &FORMATS {
            assert!(xml.contains(&format!("type=\"{}\"", f.mime)));
            assert!(xml.contains(&format!("pattern=\"{}\"", f.glob)));
        }
        assert!(!xml.contains(".toml") && !xml.contains(".json"));
        // XML comments may not hold a double hyphen (update-mime-database rejects the file).
        let comments = xml
            .split("<!--")
            .skip(1)
            .map(|c| c.split("-->").next().unwrap());
        for c in comments {
            assert!(!c.contains("--"), "{c}");
        }
    }
}
