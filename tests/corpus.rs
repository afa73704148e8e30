//! Bad input never crashes, hangs or exhausts memory (issue 3). Every case of
//! `$REALIST_SHARED/corpus/gltf-validator` and `$REALIST_SHARED/corpus/obj-malformed`, plus
//! large OBJ files generated here, goes through the `realist` binary in a child process with a
//! 2 GiB address-space limit and a 5 s timeout: `realist info CASE`, then for cases that load
//! `realist render CASE --size 64x64`. A case must exit 0, or exit 1 with a one-line message
//! naming the file. Cases the Khronos validator marks valid must load, or name an unsupported
//! extension. Reported as ignored when `REALIST_SHARED` is unset.

use std::collections::BTreeMap;
use std::io::{BufWriter, Read, Write};
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

const TIMEOUT: Duration = Duration::from_secs(5);
const MEMORY_KIB: u64 = 2 * 1024 * 1024;
const WORKERS: usize = 3;

/// Valid cases (validator: `numErrors` 0) the loader may refuse, with the reason. Empty: every
/// valid case loads. (`root/named_objects.gltf` and `root/unused_objects.gltf`, whose buffer has
/// no `uri` and no GLB chunk, load with that primitive skipped and noted.)
const KNOWN_REFUSED_VALID: &[&str] = &[];

const CLASSES: [&str; 6] = [
    "ok",
    "error",
    "panic",
    "timeout",
    "over-memory",
    "bad-message",
];

struct Case {
    corpus: &'static str,
    path: PathBuf,
    /// `Some(true)` when the validator reports no errors; `None` for OBJ cases.
    valid: Option<bool>,
}

struct Outcome {
    class: &'static str,
    /// The class of `info` alone (whether the case loads).
    info_class: &'static str,
    stderr: String,
}

/// Runs the binary with `args` under the memory limit and timeout; returns class and stderr.
fn run(args: &[&std::ffi::OsStr], name: &str) -> (&'static str, String) {
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {MEMORY_KIB}; exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_realist"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn realist");
    let mut pipe = child.stderr.take().expect("stderr pipe");
    let reader = std::thread::spawn(move || {
        let mut buf = Vec::new();
        let _ = (&mut pipe).take(64 * 1024).read_to_end(&mut buf);
        let _ = std::io::copy(&mut pipe, &mut std::io::sink());
        String::from_utf8_lossy(&buf).into_owned()
    });
    let start = Instant::now();
    let status = loop {
        match child.try_wait().expect("wait for realist") {
            Some(status) => break Some(status),
            None if start.elapsed() > TIMEOUT => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            None => std::thread::sleep(Duration::from_millis(5)),
        }
    };
    let stderr = reader.join().unwrap_or_default();
    let Some(status) = status else {
        return ("timeout", stderr);
    };
    let class = if status.code() == Some(101) || stderr.contains("panicked") {
        "panic"
    } else if stderr.contains("memory allocation") || matches!(status.signal(), Some(6 | 9 | 11)) {
        "over-memory"
    } else if status.code() == Some(0) {
        "ok"
    } else if status.code() == Some(1) {
        let msg = stderr.trim_end();
        if msg.is_empty() || msg.contains('\n') || !msg.contains(name) {
            "bad-message"
        } else {
            "error"
        }
    } else {
        // Any other exit code or signal is a crash as far as this test is concerned.
        "panic"
    };
    (class, stderr)
}

fn run_case(case: &Case, out_png: &Path) -> Outcome {
    let name = case
        .path
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    let file = case.path.as_os_str();
    let (info_class, stderr) = run(&["info".as_ref(), file], &name);
    if info_class != "ok" {
        return Outcome {
            class: info_class,
            info_class,
            stderr,
        };
    }
    let args = [
        "render".as_ref(),
        file,
        "-o".as_ref(),
        out_png.as_os_str(),
        "--size".as_ref(),
        "64x64".as_ref(),
    ];
    let (class, stderr) = run(&args, &name);
    let _ = std::fs::remove_file(out_png);
    Outcome {
        class,
        info_class,
        stderr,
    }
}

/// Every .gltf/.glb under `dir`, recursively, with its validator verdict.
fn gltf_cases(dir: &Path, out: &mut Vec<Case>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("read {}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            gltf_cases(&path, out);
        } else if matches!(
            path.extension().and_then(|e| e.to_str()),
            Some("gltf" | "glb")
        ) {
            let mut report = path.clone().into_os_string();
            report.push(".report.json");
            let text = std::fs::read_to_string(&report)
                .unwrap_or_else(|e| panic!("read {}: {e}", Path::new(&report).display()));
            let json: serde_json::Value = serde_json::from_str(&text).expect("report JSON");
            let errors = json["issues"]["numErrors"]
                .as_u64()
                .expect("issues.numErrors");
            out.push(Case {
                corpus: "gltf-validator",
                path,
                valid: Some(errors == 0),
            });
        }
    }
}

/// Writes the large OBJ cases of the corpus README into `dir`.
fn generate_large(dir: &Path) -> Vec<Case> {
    let write = |name: &str, body: &dyn Fn(&mut dyn Write) -> std::io::Result<()>| {
        let path = dir.join(name);
        let mut w = BufWriter::new(std::fs::File::create(&path).expect("create large case"));
        body(&mut w)
            .and_then(|()| w.flush())
            .expect("write large case");
        Case {
            corpus: "obj-generated",
            path,
            valid: None,
        }
    };
    const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let n = 2_000_000;
    vec![
        write("comment_64mib.obj", &|w| {
            w.write_all(b"# ")?;
            w.write_all(&vec![b'x'; 64 << 20])?;
            write!(w, "\n{TRI}")
        }),
        write("face_2m_verts.obj", &|w| {
            for i in 0..n {
                let a = i as f64 * std::f64::consts::TAU / n as f64;
                writeln!(w, "v {:.7} {:.7} 0", libm::cos(a), libm::sin(a))?;
            }
            w.write_all(b"f")?;
            for i in 1..=n {
                write!(w, " {i}")?;
            }
            w.write_all(b"\n")
        }),
        write("objects_1m.obj", &|w| {
            for i in 0..1_000_000 {
                writeln!(w, "o obj{i}")?;
            }
            writeln!(w, "{TRI}f 3 2 1")
        }),
        write("v_1m_numbers.obj", &|w| {
            w.write_all(b"v")?;
            for i in 0..1_000_000 {
                write!(w, " {}", i % 7)?;
            }
            write!(w, "\n{TRI}")
        }),
    ]
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn every_corpus_case_fails_cleanly() {
    let shared = realist_testkit::shared("the corpus test");
    let corpus = shared.join("corpus");
    let (gltf_dir, obj_dir) = (corpus.join("gltf-validator"), corpus.join("obj-malformed"));
    for dir in [&gltf_dir, &obj_dir] {
        assert!(
            dir.is_dir(),
            "REALIST_SHARED is set but {} is missing",
            dir.display()
        );
    }
    let mut cases = Vec::new();
    gltf_cases(&gltf_dir, &mut cases);
    assert!(cases.len() >= 300, "only {} glTF cases found", cases.len());
    let mut objs: Vec<PathBuf> = std::fs::read_dir(&obj_dir)
        .expect("read obj-malformed")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    objs.sort();
    assert!(!objs.is_empty(), "no .obj in {}", obj_dir.display());
    cases.extend(objs.into_iter().map(|path| Case {
        corpus: "obj-malformed",
        path,
        valid: None,
    }));

    let tmp = std::env::temp_dir().join(format!("realist-corpus-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("create temp dir");
    let started = Instant::now();
    cases.extend(generate_large(&tmp));
    eprintln!("generated large OBJ cases in {:.1?}", started.elapsed());

    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Outcome>>> = Mutex::new((0..cases.len()).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..WORKERS {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(case) = cases.get(i) else { break };
                let outcome = run_case(case, &tmp.join(format!("{i}.png")));
                results.lock().unwrap()[i] = Some(outcome);
            });
        }
    });
    let _ = std::fs::remove_dir_all(&tmp);
    let results: Vec<Outcome> = results
        .into_inner()
        .unwrap()
        .into_iter()
        .map(|o| o.expect("case ran"))
        .collect();
    eprintln!("ran {} cases in {:.1?}", cases.len(), started.elapsed());

    let mut table: BTreeMap<&str, BTreeMap<&str, usize>> = BTreeMap::new();
    let mut failures = Vec::new();
    eprintln!(
        "\n{:<16}{}",
        "corpus",
        CLASSES.map(|c| format!("{c:>13}")).concat()
    );
    for (case, out) in cases.iter().zip(&results) {
        *table
            .entry(case.corpus)
            .or_default()
            .entry(out.class)
            .or_default() += 1;
    }
    for (corpus, counts) in &table {
        let row = CLASSES.map(|c| format!("{:>13}", counts.get(c).copied().unwrap_or(0)));
        eprintln!("{corpus:<16}{}", row.concat());
    }
    eprintln!();
    for (case, out) in cases.iter().zip(&results) {
        let shown = case.path.display();
        if case.corpus == "obj-generated" {
            let name = case.path.file_name().unwrap().to_string_lossy();
            eprintln!("generated {name}: {} {}", out.class, out.stderr.trim_end());
        }
        if !matches!(out.class, "ok" | "error") {
            eprintln!("{}: {shown}\n    {}", out.class, out.stderr.trim_end());
            failures.push(format!("{}: {shown}", out.class));
        }
        if case.valid != Some(true) || out.info_class == "ok" {
            continue;
        }
        let known = KNOWN_REFUSED_VALID.iter().any(|k| case.path.ends_with(k));
        let why = out.stderr.trim_end();
        if known {
            eprintln!("valid but refused (known): {shown}\n    {why}");
        } else if out.stderr.contains("extension") {
            eprintln!("valid but refused (extension): {shown}\n    {why}");
        } else {
            eprintln!("valid but refused: {shown}\n    {why}");
            failures.push(format!("valid but refused: {shown}"));
        }
    }
    for known in KNOWN_REFUSED_VALID {
        let loads = cases
            .iter()
            .zip(&results)
            .any(|(c, o)| c.path.ends_with(known) && o.info_class == "ok");
        if loads {
            eprintln!("note: {known} now loads; remove it from KNOWN_REFUSED_VALID");
        }
    }
    assert!(
        failures.is_empty(),
        "{} corpus failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
