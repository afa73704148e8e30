//! Tests of the recent-files list, sibling models and the watcher, in temporary folders.

use std::sync::atomic::{AtomicUsize, Ordering as AtomicOrdering};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

use super::watch::{Debounce, Stamp};
use super::*;

/// A fresh directory under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let n = NEXT.fetch_add(1, AtomicOrdering::Relaxed);
        let dir =
            std::env::temp_dir().join(format!("realist-viewer-{tag}-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir.canonicalize().unwrap())
    }

    fn write(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn recent_files_round_trip_atomically() {
    let dir = TempDir::new("recent");
    let files: Vec<PathBuf> = ["a.obj", "b.glb", "c.gltf"]
        .iter()
        .map(|n| dir.write(n, b"x"))
        .collect();
    let mut recent = RecentFiles::default();
    for f in &files {
        recent.add(f);
    }
    let path = dir.0.join("config").join("realist").join("recent.json");
    recent.save_to(&path).unwrap();
    let (loaded, message) = RecentFiles::load_from(&path);
    assert_eq!(message, None);
    assert_eq!(loaded, recent);
    assert_eq!(
        loaded.paths(),
        [files[2].clone(), files[1].clone(), files[0].clone()]
    );
    // Saving again replaces the file and leaves no temporary behind.
    recent.add(&files[0]);
    recent.save_to(&path).unwrap();
    assert_eq!(RecentFiles::load_from(&path).0.paths()[0], files[0]);
    let names: Vec<_> = std::fs::read_dir(path.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["recent.json"]);
}

#[test]
fn recent_files_dedupe_by_canonical_path_and_cap() {
    let dir = TempDir::new("dedupe");
    let a = dir.write("a.obj", b"x");
    let b = dir.write("b.obj", b"x");
    let mut recent = RecentFiles::default();
    recent.add(&a);
    recent.add(&b);
    // The same file by another spelling moves to the front instead of being added twice.
    std::fs::create_dir(dir.0.join("sub")).unwrap();
    recent.add(&dir.0.join(".").join("sub").join("..").join("a.obj"));
    recent.add(&dir.0.join(".").join("a.obj"));
    assert_eq!(recent.paths(), [a.clone(), b.clone()]);
    #[cfg(unix)]
    {
        let link = dir.0.join("link.obj");
        std::os::unix::fs::symlink(&b, &link).unwrap();
        recent.add(&link);
        assert_eq!(recent.paths(), [b.clone(), a.clone()]);
    }
    for i in 0..MAX_RECENT + 3 {
        recent.add(&dir.write(&format!("m{i}.obj"), b"x"));
    }
    assert_eq!(recent.paths().len(), MAX_RECENT);
    assert_eq!(
        recent.paths()[0],
        dir.0.join(format!("m{}.obj", MAX_RECENT + 2))
    );
    assert_eq!(recent.paths()[MAX_RECENT - 1], dir.0.join("m3.obj"));
    recent.remove(&dir.0.join("m5.obj"));
    assert_eq!(recent.paths().len(), MAX_RECENT - 1);
    // Missing files are dropped when listed.
    std::fs::remove_file(dir.0.join("m7.obj")).unwrap();
    assert_eq!(recent.paths().len(), MAX_RECENT - 1);
    assert_eq!(recent.list().len(), MAX_RECENT - 2);
    assert!(!recent.paths().contains(&dir.0.join("m7.obj")));
}

#[test]
fn corrupt_or_unreadable_lists_load_empty_with_a_message() {
    let dir = TempDir::new("corrupt");
    let (list, message) = RecentFiles::load_from(&dir.0.join("absent.json"));
    assert!(
        list.paths().is_empty() && message.is_none(),
        "first run is silent"
    );
    for (name, text) in [
        (
            "broken.json",
            &b"{\"version\": 1, \"files\": [\"/a.obj\""[..],
        ),
        ("shape.json", b"{\"version\": 1, \"files\": 3}"),
        ("binary.json", &[0xff, 0xfe, 0x00, 0x7b]),
        ("empty.json", b""),
    ] {
        let (list, message) = RecentFiles::load_from(&dir.write(name, text));
        assert!(list.paths().is_empty(), "{name}");
        let message = message.unwrap_or_default();
        assert!(message.contains(name), "{name}: {message}");
    }
    // A folder where the file should be: a message, and saving there fails cleanly.
    let folder = dir.0.join("recent.json");
    std::fs::create_dir(&folder).unwrap();
    assert!(RecentFiles::load_from(&folder).1.is_some());
    assert!(RecentFiles::default().save_to(&folder).is_err());
    // Relative and duplicate entries are dropped on load; the cap holds.
    let many: Vec<String> = (0..20).map(|i| format!("\"/gone/{i}.obj\"")).collect();
    let text = format!(
        "{{\"version\": 1, \"files\": [\"rel.obj\", \"/gone/0.obj\", {}]}}",
        many.join(",")
    );
    let (list, message) = RecentFiles::load_from(&dir.write("many.json", text.as_bytes()));
    assert_eq!(message, None);
    assert_eq!(list.paths().len(), MAX_RECENT);
    assert_eq!(list.paths()[0], Path::new("/gone/0.obj"));
    assert_eq!(list.paths()[1], Path::new("/gone/1.obj"));
}

#[test]
fn config_dir_follows_xdg_then_home() {
    let os = |s: &str| Some(OsString::from(s));
    assert_eq!(
        config_dir_from(os("/x/cfg"), os("/home/u")),
        Some(PathBuf::from("/x/cfg/realist"))
    );
    assert_eq!(
        config_dir_from(None, os("/home/u")),
        Some(PathBuf::from("/home/u/.config/realist"))
    );
    assert_eq!(
        config_dir_from(os("relative"), os("/home/u")),
        Some(PathBuf::from("/home/u/.config/realist"))
    );
    assert_eq!(config_dir_from(os(""), None), None);
}

#[test]
fn natural_order_compares_numbers_by_value() {
    let mut names = vec![
        "model10.obj",
        "Model1.GLB",
        "model2.obj",
        "model.obj",
        "a.gltf",
        "model02.obj",
        "b",
    ];
    names.sort_by(|a, b| natural_cmp(a, b));
    assert_eq!(
        names,
        [
            "a.gltf",
            "b",
            "model.obj",
            "Model1.GLB",
            "model02.obj",
            "model2.obj",
            "model10.obj"
        ]
    );
    assert_eq!(natural_cmp("x", "x"), Ordering::Equal);
    assert_ne!(natural_cmp("A.obj", "a.obj"), Ordering::Equal);
}

#[test]
fn sibling_models_in_natural_order_wrap_around() {
    let dir = TempDir::new("siblings");
    for name in [
        "model10.obj",
        "model2.obj",
        "Model1.GLB",
        "a.gltf",
        "notes.txt",
        "b.3ds",
    ] {
        dir.write(name, b"x");
    }
    std::fs::create_dir(dir.0.join("folder.obj")).unwrap();
    let at = |name: &str| dir.0.join(name);
    let next = |name: &str, step| sibling_model(&at(name), step);
    assert_eq!(next("a.gltf", 1), Some(at("Model1.GLB")));
    assert_eq!(next("Model1.GLB", 1), Some(at("model2.obj")));
    assert_eq!(next("model2.obj", 1), Some(at("model10.obj")));
    assert_eq!(next("model10.obj", 1), Some(at("a.gltf")), "wraps forwards");
    assert_eq!(
        next("a.gltf", -1),
        Some(at("model10.obj")),
        "wraps backwards"
    );
    assert_eq!(next("a.gltf", 6), Some(at("model2.obj")));
    assert_eq!(next("a.gltf", 0), None);
    assert_eq!(next("a.gltf", 4), None, "a full turn lands on itself");
    assert_eq!(next("a.gltf", i32::MIN), None, "a multiple of the count");
    assert_eq!(next("a.gltf", i32::MAX), Some(at("model10.obj")));
    // A deleted current file counts from where it would sort.
    assert_eq!(next("model3.obj", 1), Some(at("model10.obj")));
    assert_eq!(next("model3.obj", -1), Some(at("model2.obj")));

    let lonely = TempDir::new("lonely");
    let only = lonely.write("only.obj", b"x");
    lonely.write("readme.md", b"x");
    assert_eq!(sibling_model(&only, 1), None);
    assert_eq!(
        sibling_model(&lonely.0.join("missing-dir").join("x.obj"), 1),
        None
    );
}

#[test]
fn debounce_reports_a_stable_change_once() {
    let stamp = |len| {
        Some(Stamp {
            modified: Some(SystemTime::UNIX_EPOCH + Duration::from_secs(len)),
            len,
            inode: 7,
        })
    };
    let mut d = Debounce::new(stamp(1));
    assert!(!d.poll(stamp(1)), "unchanged");
    // Being rewritten: changes on every poll, reported once stable.
    assert!(!d.poll(stamp(2)));
    assert!(!d.poll(stamp(3)));
    assert!(d.poll(stamp(3)));
    assert!(!d.poll(stamp(3)));
    // Deleted: not reported; recreated: reported when stable.
    assert!(!d.poll(None));
    assert!(!d.poll(None));
    assert!(!d.poll(stamp(4)));
    assert!(d.poll(stamp(4)));
    // A flicker back to the reported version is not a change.
    assert!(!d.poll(stamp(5)));
    assert!(!d.poll(stamp(4)));
    assert!(!d.poll(stamp(4)));
}

/// Polls `count` until it reaches `want` or `timeout` passes.
fn wait_for(count: &AtomicUsize, want: usize, timeout: Duration) -> usize {
    let start = Instant::now();
    while count.load(AtomicOrdering::SeqCst) < want && start.elapsed() < timeout {
        std::thread::sleep(Duration::from_millis(5));
    }
    count.load(AtomicOrdering::SeqCst)
}

#[test]
fn watcher_fires_once_per_change_and_stops_promptly() {
    let dir = TempDir::new("watch");
    let file = dir.write("m.obj", b"v 0 0 0\n");
    let count = Arc::new(AtomicUsize::new(0));
    let counter = Arc::clone(&count);
    let interval = Duration::from_millis(20);
    let on_change = Box::new(move || {
        counter.fetch_add(1, AtomicOrdering::SeqCst);
    });
    let watcher = FileWatcher::with_interval(&file, interval, on_change).unwrap();
    assert_eq!(watcher.path(), file);
    std::thread::sleep(interval * 10);
    assert_eq!(count.load(AtomicOrdering::SeqCst), 0, "nothing changed");

    std::fs::write(&file, b"v 0 0 0\nv 1 0 0\n").unwrap();
    assert_eq!(wait_for(&count, 1, Duration::from_secs(5)), 1);
    std::thread::sleep(interval * 10);
    assert_eq!(count.load(AtomicOrdering::SeqCst), 1, "reported once");

    std::fs::remove_file(&file).unwrap();
    std::thread::sleep(interval * 10);
    assert_eq!(
        count.load(AtomicOrdering::SeqCst),
        1,
        "deletion is not reported"
    );
    std::fs::write(&file, b"v 2 0 0\n").unwrap();
    assert_eq!(
        wait_for(&count, 2, Duration::from_secs(5)),
        2,
        "recreation is"
    );

    let start = Instant::now();
    drop(watcher);
    assert!(
        start.elapsed() < Duration::from_millis(250),
        "{:?}",
        start.elapsed()
    );
    // Even with the default half-second interval, drop does not wait for the next poll.
    let idle = FileWatcher::new(&file, Box::new(|| {})).unwrap();
    std::thread::sleep(Duration::from_millis(20));
    let start = Instant::now();
    drop(idle);
    assert!(
        start.elapsed() < Duration::from_millis(250),
        "{:?}",
        start.elapsed()
    );
}
