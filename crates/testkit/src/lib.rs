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

/// `$REALIST_SHARED`, or `None` after printing why the test is skipped.
pub fn shared(test: &str) -> Option<PathBuf> {
    match std::env::var_os("REALIST_SHARED") {
        Some(dir) => {
            let dir = PathBuf::from(dir);
            assert!(
                dir.join("models").is_dir(),
                "REALIST_SHARED={} has no models/ folder",
                dir.display()
            );
            Some(dir)
        }
        None => {
            eprintln!("{test}: REALIST_SHARED is not set; skipped");
            None
        }
    }
}
