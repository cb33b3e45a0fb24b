//! A run stopped by SIGINT, SIGTERM or SIGHUP leaves nothing behind: no temporary file of
//! an output being written, no directory it created. The process still ends by the signal.
#![cfg(unix)]

use crate::common::*;

use std::fs;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How long to wait for the state the test needs before giving up (a hang guard, not a
/// speed requirement).
const GUARD: Duration = Duration::from_secs(120);

fn spawn(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_subsurf"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("cannot run subsurf")
}

/// Whether `dir` holds a temporary output file (`.NAME.tmp-PID-N`).
fn has_temporary(dir: &Path) -> bool {
    fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .any(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        })
        .unwrap_or(false)
}

fn send(child: &Child, signal: libc::c_int) {
    // SAFETY: `kill` with the id of our own child process.
    let sent = unsafe { libc::kill(child.id() as libc::pid_t, signal) };
    assert_eq!(sent, 0, "cannot send signal {signal}");
}

/// `repose` stopped while it waits for its second pose (a named pipe nobody writes to):
/// the first pose's output is written to a temporary file in a directory the run created;
/// after the signal neither is left, and the process ended by the signal.
#[test]
fn a_stopped_repose_leaves_nothing() {
    for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        let dir = dir_with(&[("hut.obj", HUT), ("a.obj", HUT)]);
        let fifo = dir.path().join("b.obj");
        let made = Command::new("mkfifo").arg(&fifo).status();
        if !matches!(made, Ok(s) if s.success()) {
            return; // no mkfifo on this system
        }
        let mut child = spawn(
            dir.path(),
            &["repose", "hut.obj", "a.obj", "b.obj", "-o", "out/new"],
        );
        let out = dir.path().join("out/new");
        let start = Instant::now();
        while !has_temporary(&out) {
            assert!(
                start.elapsed() < GUARD && child.try_wait().expect("wait").is_none(),
                "repose never wrote its first pose"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
        send(&child, signal);
        let status = child.wait().expect("wait for subsurf");
        assert_eq!(status.signal(), Some(signal), "{status:?}");
        assert_eq!(listing(dir.path()), ["a.obj", "b.obj", "hut.obj"]);
    }
}

/// `subdivide` stopped while it writes a large output: no temporary file is left.
#[test]
fn a_stopped_subdivide_leaves_nothing() {
    for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        let dir = dir_with(&[("cube.obj", CUBE)]);
        // About 1.6 M quads: the output takes a while to write.
        let mut child = spawn(
            dir.path(),
            &["subdivide", "cube.obj", "-o", "out.obj", "-l", "9", "-q"],
        );
        let start = Instant::now();
        while !has_temporary(dir.path()) {
            let finished = child.try_wait().expect("wait").is_some();
            assert!(
                start.elapsed() < GUARD && !finished,
                "subdivide finished before its output was seen being written"
            );
            std::thread::sleep(Duration::from_millis(1));
        }
        send(&child, signal);
        let status = child.wait().expect("wait for subsurf");
        assert_eq!(status.signal(), Some(signal), "{status:?}");
        assert_eq!(listing(dir.path()), ["cube.obj"]);
    }
}
