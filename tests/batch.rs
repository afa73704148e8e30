//! `realist batch`: shards that together make one run, a killed run resumed, a corrupt file
//! as one failed item, bad `--shard` values, the time limit, thumbnails.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use realist_testkit::TempDir;
use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_realist");

fn batch(cwd: &Path, args: &[&str]) -> Command {
    let mut c = Command::new(BIN);
    c.current_dir(cwd)
        .arg("batch")
        .args(args)
        .env("LC_ALL", "C")
        .stdin(Stdio::null());
    c
}

fn run(cwd: &Path, args: &[&str]) -> Output {
    batch(cwd, args).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `$REALIST_SHARED/models`.
fn models() -> PathBuf {
    realist_testkit::shared("the batch tests").join("models")
}

/// Every file under `dir` but the manifests, by path relative to it: the images a run made.
fn images(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
                if !rel.starts_with("manifest") {
                    out.insert(rel, std::fs::read(&p).unwrap());
                }
            }
        }
    }
    out
}

/// The lines of every manifest in `dir` (only whole lines: a line being written is left).
fn manifest_lines(dir: &Path) -> Vec<Value> {
    let mut lines = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return lines;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with("manifest") && name.ends_with(".jsonl") {
            let text = std::fs::read_to_string(e.path()).unwrap();
            let whole = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
            lines.extend(
                whole
                    .lines()
                    .map(|l| serde_json::from_str::<Value>(l).unwrap()),
            );
        }
    }
    lines
}

fn items_with(lines: &[Value], status: &str) -> Vec<String> {
    lines
        .iter()
        .filter(|l| l["status"] == status)
        .map(|l| l["item"].as_str().unwrap().to_string())
        .collect()
}

/// The shared models: how many of the formats a folder is searched for.
fn model_count(dir: &Path) -> usize {
    let mut n = 0;
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().and_then(|e| e.to_str()).is_some_and(|e| {
                ["gltf", "glb", "obj", "stl", "ply"].contains(&e.to_ascii_lowercase().as_str())
            }) {
                n += 1;
            }
        }
    }
    n
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn two_shards_make_one_run() {
    let models = models();
    let m = models.to_str().unwrap();
    let tmp = TempDir::new("batch-shards");
    let common = ["--turntable", "8", "--size", "96x72"];
    // The two shards at once into one folder, as a job array on a shared file system.
    let shards: Vec<_> = ["1/2", "2/2"]
        .iter()
        .map(|s| {
            let mut args = vec![m, "--shard", s, "--out", "sharded"];
            args.extend(common);
            batch(&tmp.0, &args)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for s in shards {
        let o = s.wait_with_output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let mut args = vec![m, "--out", "whole"];
    args.extend(common);
    let o = run(&tmp.0, &args);
    assert!(o.status.success(), "{}", stderr(&o));

    let count = model_count(&models);
    let whole = images(&tmp.0.join("whole"));
    let sharded = images(&tmp.0.join("sharded"));
    assert_eq!(whole.len(), count * 8, "8 frames of each model");
    assert!(
        whole.contains_key("gltf/Box/turntable-0.png"),
        "{:?}",
        whole.keys()
    );
    assert_eq!(
        whole.keys().collect::<Vec<_>>(),
        sharded.keys().collect::<Vec<_>>(),
        "the same files"
    );
    for (name, bytes) in &whole {
        assert!(sharded[name] == *bytes, "{name} differs between the runs");
    }
    // Each shard's manifest holds its half; together, the whole run's items, once each.
    let one = manifest_lines(&tmp.0.join("whole"));
    assert_eq!(one.len(), count);
    let s1 = std::fs::read_to_string(tmp.0.join("sharded/manifest.shard-1-of-2.jsonl")).unwrap();
    let s2 = std::fs::read_to_string(tmp.0.join("sharded/manifest.shard-2-of-2.jsonl")).unwrap();
    assert_eq!(s1.lines().count(), count.div_ceil(2));
    assert_eq!(s2.lines().count(), count / 2);
    let mut both = items_with(&manifest_lines(&tmp.0.join("sharded")), "ok");
    both.sort();
    let mut all = items_with(&one, "ok");
    all.sort();
    assert_eq!(both, all);
    assert_eq!(all.len(), count);
    assert!(
        !tmp.0.join("sharded/.partial").exists(),
        "temporary files left"
    );
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn a_killed_run_resumes() {
    let models = models();
    let m = models.to_str().unwrap();
    let tmp = TempDir::new("batch-resume");
    let common = ["--still", "--size", "96x72", "--jobs", "1"];
    let mut args = vec![m, "--out", "out"];
    args.extend(common);
    let count = model_count(&models);

    // Killed once its manifest has a finished line.
    let mut child = batch(&tmp.0, &args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let out = tmp.0.join("out");
    let mut polls = 0;
    while manifest_lines(&out).is_empty() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before a line"
        );
        polls += 1;
        assert!(polls < 60_000, "no manifest line after 10 minutes");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let before = manifest_lines(&out);
    let finished: BTreeSet<String> = items_with(&before, "ok").into_iter().collect();
    assert!(!finished.is_empty());
    assert!(finished.len() < count, "killed before the end");

    // The restart skips them and does the rest.
    let o = run(&tmp.0, &args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(&format!("; {} skipped (already done)", finished.len())),
        "{} finished before the kill: {err}",
        finished.len()
    );
    let after = manifest_lines(&out);
    let mut ok = items_with(&after, "ok");
    assert_eq!(ok.len(), count, "each item done once: {ok:?}");
    ok.sort();
    ok.dedup();
    assert_eq!(ok.len(), count);
    assert!(!out.join(".partial").exists(), "temporary files left");

    // The same images as a run never stopped.
    let mut args = vec![m, "--out", "whole"];
    args.extend(common);
    let o = run(&tmp.0, &args);
    assert!(o.status.success(), "{}", stderr(&o));
    let whole = images(&tmp.0.join("whole"));
    assert_eq!(whole.len(), count);
    assert!(images(&out) == whole, "the resumed run's images differ");

    // Run again: nothing left to do.
    let o = run(&tmp.0, &args);
    assert!(
        stderr(&o).contains(&format!("; {count} skipped")),
        "{}",
        stderr(&o)
    );
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn a_corrupt_file_is_one_failed_item() {
    let models = models();
    let tmp = TempDir::new("batch-corrupt");
    let glb = std::fs::read(models.join("gltf/Box.glb")).unwrap();
    tmp.write("in/Box.glb", &glb);
    tmp.write(
        "in/suzanne.obj",
        std::fs::read(models.join("obj/suzanne.obj")).unwrap(),
    );
    tmp.write(
        "in/tri/Triangle.gltf",
        std::fs::read(models.join("gltf/khronos/Triangle/Triangle.gltf")).unwrap(),
    );
    tmp.write("in/bad/truncated.glb", &glb[..glb.len() / 3]);
    let mut rng = realist_testkit::SplitMix(39);
    let garbage: Vec<u8> = (0..4096).map(|_| rng.next_u64() as u8).collect();
    tmp.write("in/bad/garbage.obj", garbage);

    let o = run(&tmp.0, &["in", "--size", "96x72", "--out", "out"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("2 of 5 item(s) failed"), "{err}");
    let lines = manifest_lines(&tmp.0.join("out"));
    assert_eq!(lines.len(), 5);
    let mut failed = items_with(&lines, "failed");
    failed.sort();
    assert_eq!(failed, ["bad/garbage.obj", "bad/truncated.glb"]);
    for l in &lines {
        let item = l["item"].as_str().unwrap();
        if l["status"] == "failed" {
            let e = l["error"].as_str().unwrap();
            let name = item.rsplit('/').next().unwrap();
            assert!(e.contains(name), "the error names the file: {e}");
            assert!(e.len() > name.len() + 20, "and the problem: {e}");
            assert_eq!(l["outputs"], serde_json::json!([]));
        } else {
            assert_eq!(l["status"], "ok", "{l}");
            assert_eq!(l["error"], Value::Null);
            let outputs = l["outputs"].as_array().unwrap();
            assert_eq!(outputs.len(), 1);
            assert!(tmp
                .0
                .join("out")
                .join(outputs[0].as_str().unwrap())
                .is_file());
        }
    }
}

/// A model that needs no shared data.
fn cube(tmp: &TempDir, name: &str) -> PathBuf {
    let mut obj = String::new();
    for v in 0..8 {
        let c = |b: i32| if v & b != 0 { 1 } else { -1 };
        obj += &format!("v {} {} {}\n", c(1), c(2), c(4));
    }
    for f in [
        "1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6",
    ] {
        obj += &format!("f {f}\n");
    }
    tmp.write(name, obj)
}

#[test]
fn shard_values_are_checked() {
    let tmp = TempDir::new("batch-args");
    cube(&tmp, "in/cube.obj");
    for (bad, why) in [
        ("0/2", "numbered from 1"),
        ("3/2", "only 2 shard"),
        ("1/0", "at least 1"),
        ("x", "I/N"),
        ("1/x", "not a whole number"),
    ] {
        let o = run(&tmp.0, &["in", "--shard", bad]);
        let err = stderr(&o);
        assert!(!o.status.success(), "--shard {bad} accepted");
        assert!(
            err.contains("--shard") && err.contains(why),
            "--shard {bad}: {err}"
        );
    }
    assert!(!tmp.0.join("realist-batch").exists(), "nothing written");
    // Other mistakes are one error before any item runs.
    for args in [
        vec!["in", "--turntable", "0"],
        vec!["in", "--size", "big"],
        vec!["in", "--", "--no-such-option"],
        vec!["in", "--thumbnail", "--size", "96x72"],
        vec!["nothing-here"],
    ] {
        let o = run(&tmp.0, &args);
        assert!(!o.status.success(), "{args:?} accepted");
        assert!(!stderr(&o).is_empty());
        assert!(
            !tmp.0.join("realist-batch").is_dir()
                || manifest_lines(&tmp.0.join("realist-batch")).is_empty()
        );
    }
}

#[test]
fn an_item_over_its_time_is_killed() {
    let tmp = TempDir::new("batch-timeout");
    cube(&tmp, "in/cube.obj");
    // Starting a process alone takes longer than a microsecond.
    let o = run(&tmp.0, &["in", "--turntable", "4", "--timeout", "0.000001"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let lines = manifest_lines(&tmp.0.join("realist-batch"));
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0]["status"], "timeout");
    assert!(lines[0]["error"].as_str().unwrap().contains("cube.obj"));
    // A restart does it again, and with time it is done.
    let o = run(&tmp.0, &["in", "--turntable", "4", "--size", "64x48"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("; 0 skipped"), "{}", stderr(&o));
    assert!(tmp.0.join("realist-batch/cube/turntable-3.png").is_file());
    assert!(!tmp
        .0
        .join("realist-batch/cube/turntable-0.png.tmp")
        .exists());
}

#[test]
fn thumbnails() {
    let tmp = TempDir::new("batch-thumbnail");
    let has = Command::new(BIN)
        .args(["help", "thumbnail"])
        .output()
        .unwrap()
        .status
        .success();
    if !has {
        eprintln!("this realist has no `thumbnail` command: the batch thumbnail test is skipped");
        let o = run(&tmp.0, &["in", "--thumbnail"]);
        assert!(
            stderr(&o).contains("no `thumbnail` command"),
            "{}",
            stderr(&o)
        );
        return;
    }
    cube(&tmp, "in/cube.obj");
    let o = run(&tmp.0, &["in", "--thumbnail", "--size", "128"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(tmp.0.join("realist-batch/cube/thumbnail-128.png")).unwrap();
    assert_eq!(img.width().max(img.height()), 128);
}
