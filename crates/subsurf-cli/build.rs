//! Asks the linker to place the functions that common jobs run (`hot-text.txt`, made by
//! `scripts/hot-text.sh`) together at the start of the binary's code.
//!
//! The kernel maps a program's code 64 KiB at a time around each page it touches, so with
//! the functions spread over the whole binary nearly all of its ~4 MB is resident even when
//! a job runs 1 MB of it; on small meshes that is most of a process's peak memory. Grouped,
//! `subsurf bench catmark_cube.obj --limit-grid 8 --threads 1` peaks at 4.5 MiB instead of
//! 6.5 (`osd-oracle benchlimit`: 5.3; `scripts/hot-text.sh` says how the list is made).
//!
//! The list is a hint. Only LLD (Rust's default linker on x86-64 Linux) takes it, so this
//! script first links an empty program with the same target, linker and flags, and passes
//! the list on only when that works. Names the binary lacks (another toolchain, changed
//! code) are skipped silently, and the layout then is the linker's usual one: nothing but
//! the resident memory depends on the list.

use std::env;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn main() {
    println!("cargo:rerun-if-changed=hot-text.txt");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=RUSTC_LINKER");

    let Some(manifest) = env::var_os("CARGO_MANIFEST_DIR") else {
        return;
    };
    let list = PathBuf::from(manifest).join("hot-text.txt");
    // `-Wl,` splits its argument at commas.
    if !list.is_file() || list.to_string_lossy().contains(',') {
        return;
    }
    let args = [
        format!("-Wl,--symbol-ordering-file={}", list.display()),
        "-Wl,--no-warn-symbol-ordering".to_string(),
    ];
    if linker_accepts(&args) {
        for arg in &args {
            println!("cargo:rustc-link-arg-bin=subsurf={arg}");
        }
    }
}

/// Whether rustc, with this build's target, linker and flags, links an empty program with
/// `link_args` added.
fn linker_accepts(link_args: &[String]) -> bool {
    let (Some(rustc), Some(out_dir), Ok(target)) = (
        env::var_os("RUSTC"),
        env::var_os("OUT_DIR"),
        env::var("TARGET"),
    ) else {
        return false;
    };
    let out_dir = Path::new(&out_dir);
    let source = out_dir.join("probe.rs");
    if std::fs::write(&source, "fn main() {}\n").is_err() {
        return false;
    }
    let mut cmd = Command::new(rustc);
    cmd.arg("--target")
        .arg(&target)
        .arg("--crate-type=bin")
        .arg("-o")
        .arg(out_dir.join("probe"))
        .arg(&source)
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    if let Some(linker) = env::var_os("RUSTC_LINKER") {
        cmd.arg("-C")
            .arg(format!("linker={}", linker.to_string_lossy()));
    }
    // The flags cargo passes to rustc (RUSTFLAGS, build.rustflags), which may pick the linker.
    if let Ok(flags) = env::var("CARGO_ENCODED_RUSTFLAGS") {
        cmd.args(flags.split('\x1f').filter(|f| !f.is_empty()));
    }
    for arg in link_args {
        cmd.arg("-C").arg(format!("link-arg={arg}"));
    }
    cmd.status().is_ok_and(|status| status.success())
}
