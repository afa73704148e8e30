use super::items::{collect, parse_shard, Shard};
use super::*;

#[test]
fn shard_values() {
    assert_eq!(parse_shard("1/2"), Ok(Shard { index: 1, count: 2 }));
    assert_eq!(parse_shard(" 3 / 3 "), Ok(Shard { index: 3, count: 3 }));
    for bad in ["0/2", "3/2", "1/0", "x", "1/x", "/2", "1/2/3", "-1/2", ""] {
        assert!(parse_shard(bad).is_err(), "{bad}");
    }
}

#[test]
fn shards_split_the_list_once() {
    let shards: Vec<Shard> = (1..=3).map(|i| Shard { index: i, count: 3 }).collect();
    for k in 0..10 {
        let owners = shards.iter().filter(|s| s.owns(k)).count();
        assert_eq!(owners, 1, "item {k}");
    }
    assert!(shards[0].owns(0) && shards[1].owns(1) && shards[2].owns(2) && shards[0].owns(3));
    assert_eq!(
        Shard { index: 1, count: 1 }.manifest_name(),
        "manifest.jsonl"
    );
    assert_eq!(
        Shard { index: 2, count: 4 }.manifest_name(),
        "manifest.shard-2-of-4.jsonl"
    );
}

#[test]
fn turntable_names_are_renders_names() {
    assert_eq!(
        Kind::Turntable(3).outputs(),
        ["turntable-0.png", "turntable-1.png", "turntable-2.png"]
    );
    assert_eq!(Kind::Turntable(12).outputs()[0], "turntable-00.png");
    assert_eq!(Kind::Still.outputs(), ["still.png"]);
    assert_eq!(Kind::Thumbnail(128).outputs(), ["thumbnail-128.png"]);
}

#[test]
fn items_sorted_named_and_mirrored() {
    let dir = realist_testkit::TempDir::new("batch-items");
    for f in [
        "in/b.obj",
        "in/a/Box.gltf",
        "in/a/Box.glb",
        "in/a/Box.bin",
        "in/a/tex.png",
        "in/a/x.mtl",
        "in/Z.STL",
        "in/c/d/e.ply",
        "loose/one/m.obj",
        "loose/two/n.glb",
    ] {
        dir.write(f, b"x");
    }
    let abs = |p: &str| dir.0.join(p).display().to_string();
    let list = dir.write(
        "list.txt",
        format!(
            "# models\n\n{}\n  {}  \n{}\n",
            abs("loose/one/m.obj"),
            abs("loose/two/n.glb"),
            abs("loose/missing.obj")
        ),
    );
    let (items, warnings) = collect(&[dir.0.join("in")], Some(&list), &dir.0).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let names: Vec<(&str, &str, bool)> = items
        .iter()
        .map(|i| (i.rel.as_str(), i.dir.as_str(), i.problem.is_some()))
        .collect();
    assert_eq!(
        names,
        [
            ("Z.STL", "Z", false),
            ("a/Box.glb", "a/Box.glb", false),
            ("a/Box.gltf", "a/Box.gltf", false),
            ("b.obj", "b", false),
            ("c/d/e.ply", "c/d/e", false),
            ("missing.obj", "missing", true),
            ("one/m.obj", "one/m", false),
            ("two/n.glb", "two/n", false),
        ]
    );
    // Two files of one name are an error naming both.
    let e = collect(
        &[dir.0.join("in/b.obj"), dir.0.join("loose/one")],
        None,
        &dir.0,
    )
    .err()
    .map(|e| e.to_string());
    assert_eq!(e, None, "b.obj and m.obj differ");
    dir.write("other/b.obj", b"x");
    let e = collect(&[dir.0.join("in"), dir.0.join("other")], None, &dir.0).unwrap_err();
    assert!(e.to_string().contains("both named b.obj"), "{e}");
    // The same file twice is one item; a missing input is an error.
    let (twice, _) = collect(&[dir.0.join("in"), dir.0.join("in")], None, &dir.0).unwrap();
    assert_eq!(twice.len(), 5);
    assert!(collect(&[dir.0.join("nothing")], None, &dir.0).is_err());
}
