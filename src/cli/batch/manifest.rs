//! The manifest: one JSON line per finished item, appended and flushed as each item
//! finishes, one file per shard; and what every manifest in the folder says is done.

use std::collections::HashMap;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

/// One line of a manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Record {
    /// The item's path relative to its input folder, `/`-separated.
    pub item: String,
    /// still, turntable or thumbnail.
    pub kind: String,
    /// ok, failed or timeout.
    pub status: String,
    /// Wall-clock seconds of the item's process.
    pub seconds: f64,
    /// The files written, relative to the output folder.
    pub outputs: Vec<String>,
    /// Why it failed (null when ok).
    pub error: Option<String>,
}

/// The manifest a shard appends to.
pub(crate) struct Manifest {
    file: File,
    pub path: PathBuf,
}

impl Manifest {
    pub fn open(path: PathBuf) -> Result<Self> {
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .with_context(|| format!("could not open the manifest {}", path.display()))?;
        Ok(Self { file, path })
    }

    /// Appends one line in one write, and flushes it to the file system (a line is either
    /// there whole or not, for a run killed at any moment, and other shards' processes on a
    /// shared file system read it).
    pub fn append(&mut self, r: &Record) -> Result<()> {
        let mut line = serde_json::to_string(r)?;
        line.push('\n');
        self.file
            .write_all(line.as_bytes())
            .and_then(|()| self.file.flush())
            .with_context(|| format!("could not append to {}", self.path.display()))?;
        // Where the file system cannot sync (some network ones), the write above stands.
        let _ = self.file.sync_data();
        Ok(())
    }
}

/// For each item, the outputs of each of its records whose status is ok.
pub(crate) type Finished = HashMap<String, Vec<Vec<String>>>;

/// Whether `name` is a manifest of this folder (manifest.jsonl, manifest.shard-I-of-N.jsonl).
fn is_manifest(name: &str) -> bool {
    name.starts_with("manifest") && name.ends_with(".jsonl")
}

/// What the manifests in `out` say: for each item, the outputs of its records whose status is
/// ok; and the number of lines that could not be read (a line cut short by a crash).
pub(crate) fn finished(out: &Path) -> Result<(Finished, usize)> {
    let mut done = Finished::new();
    let mut unreadable = 0;
    let entries = match std::fs::read_dir(out) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((done, 0)),
        Err(e) => return Err(e).with_context(|| format!("could not read {}", out.display())),
    };
    let mut names: Vec<PathBuf> = entries
        .flatten()
        .filter(|e| e.file_name().to_str().is_some_and(is_manifest))
        .map(|e| e.path())
        .collect();
    names.sort();
    for path in names {
        let bytes = std::fs::read(&path)
            .with_context(|| format!("could not read the manifest {}", path.display()))?;
        for line in bytes.split(|&b| b == b'\n') {
            if line.iter().all(u8::is_ascii_whitespace) {
                continue;
            }
            match serde_json::from_slice::<Record>(line) {
                Ok(r) if r.status == "ok" => done.entry(r.item).or_default().push(r.outputs),
                Ok(_) => {}
                Err(_) => unreadable += 1,
            }
        }
    }
    Ok((done, unreadable))
}

/// Whether an item whose outputs would be `expected` is done: a record says ok with exactly
/// those outputs, and every one of them is a file in `out`.
pub(crate) fn is_done(records: Option<&Vec<Vec<String>>>, expected: &[String], out: &Path) -> bool {
    records.is_some_and(|rs| {
        rs.iter().any(|outputs| {
            outputs.as_slice() == expected && expected.iter().all(|o| out.join(o).is_file())
        })
    })
}
