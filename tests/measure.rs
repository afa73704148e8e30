//! Measurement: `realist info` reports the bounds of what is drawn, in the file's units.

use std::path::PathBuf;

fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("realist-measure-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A box from (-1, 0, 0.5) to (1, 3, 4.5) as an OBJ.
const BOX: &str =
    "v -1 0 0.5\nv 1 0 0.5\nv 1 3 0.5\nv -1 3 0.5\nv -1 0 4.5\nv 1 0 4.5\nv 1 3 4.5\nv -1 3 4.5\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

#[test]
fn info_prints_the_bounds_in_text_and_json() {
    let dir = folder("info");
    std::fs::write(dir.join("box.obj"), BOX).unwrap();
    let run = |json: bool| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_realist"));
        c.current_dir(&dir).args(["info", "box.obj"]);
        if json {
            c.arg("--json");
        }
        let r = c.output().unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        String::from_utf8(r.stdout).unwrap()
    };
    let text = run(false);
    assert!(
        text.contains("bounds: min (-1, 0, 0.5), max (1, 3, 4.5); size 2 x 3 x 4, diagonal 5.385"),
        "{text}"
    );
    let v: serde_json::Value = serde_json::from_str(&run(true)).unwrap();
    let b = &v["bounds"];
    assert_eq!(b["size"], serde_json::json!([2.0, 3.0, 4.0]), "{b}");
    assert_eq!(b["center"], serde_json::json!([0.0, 1.5, 2.5]), "{b}");
    let _ = std::fs::remove_dir_all(&dir);
}
