//! Build script of the packages whose tests read the shared test data (`REALIST_SHARED`):
//! sets the cfg `realist_shared` when that variable or `CI` is set. A test that needs the
//! data is marked `#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]`, so
//! without the data `cargo test` reports it as ignored, not as passed; with `CI` set it
//! runs, and fails saying what is missing when the data is not there
//! (`realist_testkit::shared`).

fn main() {
    println!("cargo::rerun-if-env-changed=REALIST_SHARED");
    println!("cargo::rerun-if-env-changed=CI");
    println!("cargo::rustc-check-cfg=cfg(realist_shared)");
    if std::env::var_os("REALIST_SHARED").is_some() || std::env::var_os("CI").is_some() {
        println!("cargo::rustc-cfg=realist_shared");
    }
}
