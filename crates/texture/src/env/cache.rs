//! Prefiltered environments keyed by content: a process-wide in-memory cache and an optional
//! on-disk cache in a directory the caller chooses ([`default_cache_dir`] is the usual one).
//!
//! The key ([`content_key`]) hashes the prefilter's version and settings, the size and every
//! texel's bits, with FNV-1a over 64-bit words (two f32 a word) and an xor-shift after each
//! step, then a final avalanche: stable across Rust versions and platforms, not
//! cryptographic (a collision needs 2³² environments).
//!
//! Disk format, little-endian: magic `RLENVPF\0`, format version u32, [`PREFILTER_VERSION`]
//! u32, key u64, source width and height u32, level count u32, each level's width and height
//! u32, the 27 SH floats, every level's RGB f32 rows, and the hash of all the bytes before it
//! (u64). A file is used only if every header field equals what this build would produce
//! for the image, its length is exactly the expected one (checked on the file's metadata
//! before anything is read, so nothing unbounded is allocated) and the hash matches;
//! otherwise it is ignored and rewritten. Files are written to a temporary name and renamed.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use glam::Vec3;

use super::chain::{
    all_dims, BASE_HEIGHT, BASE_WIDTH, LEVEL_FILTER, LEVEL_SHIFT, SHEEN_LEVELS, SPECULAR_LEVELS,
};
use super::equirect::{EnvImage, Plane};
use super::prefilter::{Prefiltered, PREFILTER_VERSION};

const MAGIC: &[u8; 8] = b"RLENVPF\0";
const FORMAT_VERSION: u32 = 1;
const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// The word hash of the module docs.
struct WordHash(u64);

impl WordHash {
    fn new() -> Self {
        Self(FNV_OFFSET)
    }

    fn word(&mut self, w: u64) {
        self.0 = (self.0 ^ w).wrapping_mul(FNV_PRIME);
        self.0 ^= self.0 >> 32;
    }

    fn f32s(&mut self, v: &[f32]) {
        let mut pairs = v.chunks_exact(2);
        for p in &mut pairs {
            self.word(u64::from(p[0].to_bits()) | (u64::from(p[1].to_bits()) << 32));
        }
        for x in pairs.remainder() {
            self.word(u64::from(x.to_bits()));
        }
        self.word(v.len() as u64);
    }

    fn bytes(&mut self, b: &[u8]) {
        let mut words = b.chunks_exact(8);
        for w in &mut words {
            let mut a = [0u8; 8];
            a.copy_from_slice(w);
            self.word(u64::from_le_bytes(a));
        }
        for &x in words.remainder() {
            self.word(u64::from(x));
        }
        self.word(b.len() as u64);
    }

    /// splitmix64's finaliser.
    fn finish(self) -> u64 {
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

/// The cache key of `image`: its size and texels and this build's prefilter settings (not
/// its name).
#[must_use]
pub fn content_key(image: &EnvImage) -> u64 {
    let mut h = WordHash::new();
    h.word(u64::from(PREFILTER_VERSION));
    h.word(SPECULAR_LEVELS as u64);
    h.word(SHEEN_LEVELS as u64);
    h.word(BASE_WIDTH as u64);
    h.word(BASE_HEIGHT as u64);
    for (s, f) in LEVEL_SHIFT.iter().zip(LEVEL_FILTER) {
        h.word(u64::from(*s));
        for w in f.key() {
            h.word(w);
        }
    }
    h.word(u64::from(image.width()) << 32 | u64::from(image.height()));
    h.f32s(image.rgb());
    h.finish()
}

/// `$XDG_CACHE_HOME/realist/env`, else `$HOME/.cache/realist/env` (absolute paths only);
/// `None` if neither is set. Not created here.
#[must_use]
pub fn default_cache_dir() -> Option<PathBuf> {
    let absolute = |v: &str| {
        std::env::var_os(v)
            .map(PathBuf::from)
            .filter(|p| p.is_absolute())
    };
    absolute("XDG_CACHE_HOME")
        .or_else(|| absolute("HOME").map(|h| h.join(".cache")))
        .map(|c| c.join("realist").join("env"))
}

/// Where [`EnvCache::get_or_build`] found the environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CacheHit {
    /// Already in memory: no work.
    Memory,
    /// Read from the disk cache.
    Disk,
    /// Prefiltered now.
    Miss,
}

/// What [`EnvCache::get_or_build`] returns.
#[derive(Clone, Debug)]
pub struct Cached {
    pub env: Arc<Prefiltered>,
    pub hit: CacheHit,
    /// Why the disk cache was not used or not written (a bad file ignored, an I/O error);
    /// the environment is good regardless.
    pub disk_note: Option<String>,
}

/// Prefiltered environments by [`content_key`], most recent last, up to a byte budget (the
/// most recent one is kept even if larger).
#[derive(Debug)]
pub struct EnvCache {
    entries: Mutex<Vec<Arc<Prefiltered>>>,
    max_bytes: usize,
}

impl EnvCache {
    /// The global cache's budget: 512 MiB.
    pub const DEFAULT_BYTES: usize = 512 << 20;

    /// An empty cache holding up to `max_bytes` ([`Prefiltered::bytes`]).
    #[must_use]
    pub fn new(max_bytes: usize) -> Self {
        Self {
            entries: Mutex::new(Vec::new()),
            max_bytes,
        }
    }

    /// The process-wide cache ([`EnvCache::DEFAULT_BYTES`]).
    #[must_use]
    pub fn global() -> &'static EnvCache {
        static GLOBAL: OnceLock<EnvCache> = OnceLock::new();
        GLOBAL.get_or_init(|| EnvCache::new(Self::DEFAULT_BYTES))
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<Arc<Prefiltered>>> {
        self.entries
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// The environment with `key`, made the most recent.
    #[must_use]
    pub fn get(&self, key: u64) -> Option<Arc<Prefiltered>> {
        let mut e = self.lock();
        let i = e.iter().position(|p| p.key() == key)?;
        let env = e.remove(i);
        e.push(Arc::clone(&env));
        Some(env)
    }

    fn insert(&self, env: &Arc<Prefiltered>) {
        let mut e = self.lock();
        e.retain(|p| p.key() != env.key());
        e.push(Arc::clone(env));
        while e.len() > 1 && e.iter().map(|p| p.bytes()).sum::<usize>() > self.max_bytes {
            e.remove(0);
        }
    }

    /// Environments held.
    #[must_use]
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Drops every environment (those still shared elsewhere live on).
    pub fn clear(&self) {
        self.lock().clear();
    }

    /// The prefiltered `image`: from memory, else from `disk` (a directory, created if
    /// needed), else built now, then kept in memory and written to `disk`.
    #[must_use]
    pub fn get_or_build(&self, image: EnvImage, disk: Option<&Path>) -> Cached {
        let key = content_key(&image);
        if let Some(env) = self.get(key) {
            return Cached {
                env,
                hit: CacheHit::Memory,
                disk_note: None,
            };
        }
        let mut disk_note = None;
        if let Some(dir) = disk {
            let path = file_path(dir, key);
            match read_file(&path, key, &image) {
                Ok(Some((levels, sh))) => {
                    let env = Arc::new(Prefiltered::from_parts(image, key, levels, sh));
                    self.insert(&env);
                    return Cached {
                        env,
                        hit: CacheHit::Disk,
                        disk_note: None,
                    };
                }
                Ok(None) => {}
                Err(reason) => {
                    disk_note = Some(format!("{}: ignored ({reason}), rebuilt", path.display()));
                }
            }
        }
        let env = Arc::new(Prefiltered::build_keyed(image, key));
        self.insert(&env);
        if let Some(dir) = disk {
            if let Err(e) = write_file(dir, &env) {
                let note = format!("{}: not written: {e}", file_path(dir, key).display());
                disk_note = Some(disk_note.map_or(note.clone(), |n| format!("{n}; {note}")));
            }
        }
        Cached {
            env,
            hit: CacheHit::Miss,
            disk_note,
        }
    }
}

/// The cache file of `key` in `dir`.
#[must_use]
pub(super) fn file_path(dir: &Path, key: u64) -> PathBuf {
    dir.join(format!("{key:016x}.rlenv"))
}

/// The header and body a build for a `width×height` source writes, minus the data.
fn header(key: u64, width: usize, height: usize) -> Vec<u8> {
    let mut b = Vec::with_capacity(128);
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(&PREFILTER_VERSION.to_le_bytes());
    b.extend_from_slice(&key.to_le_bytes());
    let dims = all_dims(width, height);
    for v in [width, height, dims.len()] {
        b.extend_from_slice(&(v as u32).to_le_bytes());
    }
    for (w, h) in dims {
        b.extend_from_slice(&(w as u32).to_le_bytes());
        b.extend_from_slice(&(h as u32).to_le_bytes());
    }
    b
}

/// Bytes of a valid file for this header: header, SH, data, hash.
fn expected_len(header: &[u8], width: usize, height: usize) -> u64 {
    let data: usize = all_dims(width, height)
        .iter()
        .map(|(w, h)| 12 * w * h)
        .sum();
    (header.len() + 27 * 4 + data + 8) as u64
}

fn write_file(dir: &Path, env: &Prefiltered) -> std::io::Result<()> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let (w, h) = env.source_size();
    let mut b = header(env.key(), w as usize, h as usize);
    for c in env.sh() {
        for x in c.to_array() {
            b.extend_from_slice(&x.to_le_bytes());
        }
    }
    for level in env.level_planes() {
        for x in &level.rgb {
            b.extend_from_slice(&x.to_le_bytes());
        }
    }
    let mut hash = WordHash::new();
    hash.bytes(&b);
    b.extend_from_slice(&hash.finish().to_le_bytes());
    std::fs::create_dir_all(dir)?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = dir.join(format!("{:016x}.tmp{}-{n}", env.key(), std::process::id()));
    let result = std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(&b))
        .and_then(|()| std::fs::rename(&tmp, file_path(dir, env.key())));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

type Parts = (Vec<Plane>, [Vec3; 9]);

/// The levels and SH of `path` if it is a valid cache file for `image` (`Ok(None)` if there
/// is no file, `Err(reason)` if there is a bad one).
fn read_file(path: &Path, key: u64, image: &EnvImage) -> Result<Option<Parts>, String> {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let head = header(key, w, h);
    let want = expected_len(&head, w, h);
    let mut file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e.to_string()),
    };
    let len = file.metadata().map_err(|e| e.to_string())?.len();
    if len != want {
        return Err(format!("{len} bytes, expected {want}"));
    }
    let mut bytes = Vec::with_capacity(want as usize);
    (&mut file)
        .take(want)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 != want {
        return Err("shorter than its metadata said".into());
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    let mut hash = WordHash::new();
    hash.bytes(body);
    if tail != hash.finish().to_le_bytes() {
        return Err("hash mismatch".into());
    }
    let Some(rest) = body.strip_prefix(head.as_slice()) else {
        return Err("header differs (another version, size or key)".into());
    };
    let mut floats = rest
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]));
    let mut sh = [Vec3::ZERO; 9];
    for c in &mut sh {
        let v = [0; 3].map(|_| floats.next().unwrap_or(f32::NAN));
        *c = Vec3::from_array(v);
    }
    let levels: Vec<Plane> = all_dims(w, h)
        .iter()
        .map(|&(lw, lh)| Plane {
            width: lw,
            height: lh,
            rgb: floats.by_ref().take(3 * lw * lh).collect(),
        })
        .collect();
    let valid = |x: f32| x.is_finite() && x >= 0.0;
    let finite_sh = sh.iter().all(|c| c.is_finite());
    let sizes_ok = levels.iter().all(|p| p.rgb.len() == 3 * p.width * p.height);
    if !finite_sh || !sizes_ok || !levels.iter().all(|p| p.rgb.iter().copied().all(valid)) {
        return Err("bad values".into());
    }
    Ok(Some((levels, sh)))
}
