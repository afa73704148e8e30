//! The items of a batch: the model files found under folders, named on the command line or
//! in a list file, each with the relative path its outputs mirror, in one sorted order that
//! every shard computes alike.

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use anyhow::{bail, Context, Result};

use realist::scenefile::lexically_absolute;

/// The file extensions a folder is searched for: every model format realist reads (their
/// buffers, textures and materials, .bin .png .mtl, are read through the model).
pub(crate) const MODEL_EXTENSIONS: [&str; 5] = ["gltf", "glb", "obj", "stl", "ply"];

/// One model to render.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Item {
    /// The file, as the inputs name it (a folder argument joined with what was found in it).
    pub path: PathBuf,
    /// Its path relative to its root, `/`-separated: the manifest's name for it, the order
    /// of the list, and where its outputs go.
    pub rel: String,
    /// The folder its outputs go to, relative to `--out` (`rel` without its extension, or
    /// with it when two models differ only by extension).
    pub dir: String,
    /// Why it cannot be rendered, found while listing (a listed file that is missing, a name
    /// that is not UTF-8): a failed item, not the end of the run.
    pub problem: Option<String>,
}

/// `--shard I/N` (1-based).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// Whether item `k` (0-based in the sorted list) is this shard's: shard (k mod N) + 1.
    pub fn owns(self, k: usize) -> bool {
        k % self.count + 1 == self.index
    }

    /// The manifest this shard appends to.
    pub fn manifest_name(self) -> String {
        if self.count == 1 {
            "manifest.jsonl".into()
        } else {
            format!("manifest.shard-{}-of-{}.jsonl", self.index, self.count)
        }
    }

    /// A name for this shard's temporary folder.
    pub fn tag(self) -> String {
        format!("shard-{}-of-{}", self.index, self.count)
    }
}

/// Parses `I/N`: 1 <= I <= N.
pub(crate) fn parse_shard(s: &str) -> Result<Shard, String> {
    let bad = |why: &str| format!("{why} (expected I/N with 1 <= I <= N, e.g. 1/4)");
    let (i, n) = s.split_once('/').ok_or_else(|| bad("no '/'"))?;
    let i: usize = i
        .trim()
        .parse()
        .map_err(|_| bad("I is not a whole number"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| bad("N is not a whole number"))?;
    if n == 0 {
        return Err(bad("N must be at least 1"));
    }
    if i == 0 {
        return Err(bad("shards are numbered from 1"));
    }
    if i > n {
        return Err(bad(&format!("there are only {n} shard(s)")));
    }
    Ok(Shard { index: i, count: n })
}

fn is_model(p: &Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| MODEL_EXTENSIONS.iter().any(|m| m.eq_ignore_ascii_case(e)))
}

/// `rel`'s components joined with `/`, or `None` when a component is not UTF-8.
fn slash_path(rel: &Path) -> Option<String> {
    let parts: Option<Vec<&str>> = rel
        .components()
        .filter(|c| matches!(c, Component::Normal(_)))
        .map(|c| c.as_os_str().to_str())
        .collect();
    parts.map(|p| p.join("/"))
}

/// Every model file under `root`, recursively (symbolic links to folders are not followed, so
/// a link loop cannot make the walk endless): (path, path relative to `root`).
fn walk(root: &Path, out: &mut Vec<(PathBuf, PathBuf)>, warnings: &mut Vec<String>) {
    let mut stack = vec![PathBuf::new()];
    while let Some(rel) = stack.pop() {
        let dir = root.join(&rel);
        let entries = match std::fs::read_dir(&dir) {
            Ok(e) => e,
            Err(e) => {
                warnings.push(format!("could not read the folder {}: {e}", dir.display()));
                continue;
            }
        };
        for entry in entries {
            let entry = match entry {
                Ok(e) => e,
                Err(e) => {
                    warnings.push(format!("could not read the folder {}: {e}", dir.display()));
                    continue;
                }
            };
            let name = entry.file_name();
            let child = rel.join(&name);
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_dir() {
                stack.push(child);
            } else if is_model(&child) && (kind.is_file() || root.join(&child).is_file()) {
                out.push((root.join(&child), child));
            }
        }
    }
}

/// The paths of a list file: one per line, `#` starting a comment line, blank lines ignored,
/// relative paths relative to the current folder.
fn read_list(list: &Path) -> Result<Vec<PathBuf>> {
    let text =
        std::fs::read(list).with_context(|| format!("could not read --list {}", list.display()))?;
    let text = String::from_utf8(text)
        .map_err(|_| anyhow::anyhow!("--list {}: the file is not UTF-8 text", list.display()))?;
    Ok(text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(PathBuf::from)
        .collect())
}

/// The deepest folder holding every one of `files` (absolute, lexical).
fn common_folder(files: &[PathBuf]) -> PathBuf {
    let mut common: Option<PathBuf> = None;
    for f in files {
        let parent = f.parent().unwrap_or(Path::new("/"));
        common = Some(match common {
            None => parent.to_path_buf(),
            Some(c) => {
                let mut shared = PathBuf::new();
                for (a, b) in c.components().zip(parent.components()) {
                    if a != b {
                        break;
                    }
                    shared.push(a);
                }
                shared
            }
        });
    }
    common.unwrap_or_default()
}

/// The sorted items of `inputs` (folders and files) and `list` (a list file), and warnings
/// (folders that could not be read). A folder is searched recursively for model files; a
/// file given by name is an item whatever its extension. Items of a folder are named
/// relative to it; files given by name (here or in the list) relative to the deepest folder
/// holding all of them. An input that does not exist is an error; a listed file that does
/// not exist is a failed item (the list stays the same for every shard).
pub(crate) fn collect(
    inputs: &[PathBuf],
    list: Option<&Path>,
    cwd: &Path,
) -> Result<(Vec<Item>, Vec<String>)> {
    let mut warnings = Vec::new();
    let mut found: Vec<(PathBuf, PathBuf)> = Vec::new();
    let mut loose: Vec<(PathBuf, PathBuf)> = Vec::new();
    for input in inputs {
        let meta =
            std::fs::metadata(input).with_context(|| format!("input {}", input.display()))?;
        if meta.is_dir() {
            walk(input, &mut found, &mut warnings);
        } else {
            loose.push((input.clone(), lexically_absolute(cwd, input)));
        }
    }
    if let Some(list) = list {
        for p in read_list(list)? {
            loose.push((p.clone(), lexically_absolute(cwd, &p)));
        }
    }
    let abs: Vec<PathBuf> = loose.iter().map(|(_, a)| a.clone()).collect();
    let root = common_folder(&abs);
    for (path, a) in loose {
        let rel = a
            .strip_prefix(&root)
            .map_or_else(|_| a.clone(), Path::to_path_buf);
        found.push((path, rel));
    }
    // One item per name: the same file found twice is one item; two files of one name is
    // an error (their outputs would overwrite each other).
    let mut by_name: BTreeMap<Vec<u8>, Item> = BTreeMap::new();
    for (path, rel) in found {
        let (name, problem) = match slash_path(&rel) {
            Some(s) => (s, None),
            None => (
                rel.to_string_lossy().replace('\\', "/"),
                Some(format!(
                    "{}: the path is not valid UTF-8 (the manifest names items in UTF-8)",
                    path.display()
                )),
            ),
        };
        let problem = problem.or_else(|| {
            (!path.is_file()).then(|| match std::fs::metadata(&path) {
                Err(e) => format!("{}: {e}", path.display()),
                Ok(_) => format!("{}: not a file", path.display()),
            })
        });
        let key = name.as_bytes().to_vec();
        if let Some(old) = by_name.get(&key) {
            if lexically_absolute(cwd, &old.path) == lexically_absolute(cwd, &path) {
                continue;
            }
            bail!(
                "{} and {} are both named {name} in the batch, so their outputs would \
                 overwrite each other; run them in separate batches (another --out)",
                old.path.display(),
                path.display()
            );
        }
        by_name.insert(
            key,
            Item {
                path,
                rel: name,
                dir: String::new(),
                problem,
            },
        );
    }
    let mut items: Vec<Item> = by_name.into_values().collect();
    name_folders(&mut items);
    Ok((items, warnings))
}

/// Each item's output folder: its name without the extension, or with it when another
/// item has the same name but for the extension (Box.gltf and Box.glb side by side).
fn name_folders(items: &mut [Item]) {
    let stem = |rel: &str| -> String {
        let (head, file) = rel.rsplit_once('/').map_or(("", rel), |(h, f)| (h, f));
        let base = match file.rsplit_once('.') {
            Some((s, _)) if !s.is_empty() => s,
            _ => file,
        };
        if head.is_empty() {
            base.to_string()
        } else {
            format!("{head}/{base}")
        }
    };
    let mut count: BTreeMap<String, usize> = BTreeMap::new();
    for it in items.iter() {
        *count.entry(stem(&it.rel)).or_default() += 1;
    }
    for it in items.iter_mut() {
        let s = stem(&it.rel);
        it.dir = if count[&s] > 1 || s == it.rel {
            it.rel.clone()
        } else {
            s
        };
    }
}
