//! Test helpers shared by the crates of realist (a dev-dependency only): temporary folders
//! removed when dropped, and the shared test data named by `REALIST_SHARED`.

use std::path::PathBuf;

/// A fresh directory under the system temp dir, removed on drop.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(tag: &str) -> Self {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("realist-{tag}-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    /// Writes `name` (relative) and returns its path.
    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `$REALIST_SHARED`: the shared test data (`../shared` beside a clone in CI). A test that
/// needs it is marked `#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]`:
/// the build script `build/shared_cfg.rs` sets that cfg when `REALIST_SHARED` or `CI` is
/// set, so without the data the test is reported as ignored, and this is reached only when
/// the data should be there. Panics naming what is missing (`what`: the test's words for
/// the data it reads) when `REALIST_SHARED` is unset (under `CI`) or names no folder with
/// a `models/` folder in it.
pub fn shared(what: &str) -> PathBuf {
    let Some(dir) = std::env::var_os("REALIST_SHARED") else {
        panic!(
            "{what}: REALIST_SHARED is not set, and CI is: the shared test data must be there \
             (set REALIST_SHARED to the shared folder)"
        );
    };
    let dir = PathBuf::from(dir);
    assert!(
        dir.join("models").is_dir(),
        "{what}: REALIST_SHARED={} has no models/ folder",
        dir.display()
    );
    dir
}

/// splitmix64: a small, fast, deterministic stream of random numbers for tests (the same
/// numbers on every machine and run).
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`, 24 bits.
    pub fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in `[0, 1)`, 53 bits.
    pub fn unit_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}
