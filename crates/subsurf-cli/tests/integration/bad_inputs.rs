//! Malformed and extreme inputs: every subcommand that reads an OBJ, on every file of the
//! corpus `crates/subsurf/tests/bad/`, must finish (a hang guard kills a run after 120 s; no
//! test here asserts how fast a run is, since the machine may be busy), exit with the status listed
//! in `expected.tsv` (1 for bad input) with a message naming the file and the line or
//! element, never panic, and on failure leave nothing behind (no output file, no temporary
//! file, nothing on standard output).
//!
//! Rows of `expected.tsv` marked `bug` describe known bugs (the behaviour wanted once they
//! are fixed; none at the moment); they are checked by the ignored test `known_bugs`
//! (`cargo test -p subsurf-cli --test integration bad_inputs:: -- --ignored`).

use crate::common;
use common::*;

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// The hang guard: a run still going after this long is killed and the test fails. It is
/// not a speed requirement (tests run on busy machines; cost is checked by counting work,
/// `crates/subsurf/tests/work_counts.rs`): every run here takes well under a second alone.
const TIME_LIMIT: Duration = Duration::from_secs(120);

/// Every subcommand that reads an OBJ (`render` only when the binary has it).
const ALL_COMMANDS: [&str; 6] = [
    "info",
    "subdivide",
    "limit",
    "tessellate",
    "bench",
    "render",
];

/// The commands of the papers' methods that read an OBJ mesh, run over the corpus by
/// [`paper_commands_refuse_broken_files_like_the_others`] and
/// [`paper_commands_never_crash_on_the_corpus`].
const PAPER_COMMANDS: [&str; 3] = ["spline", "regularity", "g2"];

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../subsurf/tests/bad")
}

/// What one run of the binary did.
struct Run {
    /// Exit status; `None` when killed (time limit) or ended by a signal.
    code: Option<i32>,
    stdout: Vec<u8>,
    stderr: String,
    timed_out: bool,
    elapsed: Duration,
}

/// Runs `subsurf args` in `dir` (standard input from `stdin`, else empty), killing it after
/// [`TIME_LIMIT`].
fn run_limited(dir: &Path, args: &[String], stdin: Option<Vec<u8>>) -> Run {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_subsurf"))
        .current_dir(dir)
        .args(args)
        .stdin(if stdin.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot run subsurf");
    let feeder = stdin.map(|bytes| {
        let mut pipe = child.stdin.take().expect("piped stdin");
        std::thread::spawn(move || {
            use std::io::Write;
            // The child may exit before reading everything: ignore broken pipes.
            let _ = pipe.write_all(&bytes);
        })
    });
    let mut out = child.stdout.take().expect("piped stdout");
    let mut err = child.stderr.take().expect("piped stderr");
    let out_reader = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = out.read_to_end(&mut v);
        v
    });
    let err_reader = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = err.read_to_end(&mut v);
        v
    });
    let mut timed_out = false;
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for subsurf") {
            break status;
        }
        if start.elapsed() > TIME_LIMIT {
            timed_out = true;
            let _ = child.kill();
            break child.wait().expect("wait for killed subsurf");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let elapsed = start.elapsed();
    if let Some(f) = feeder {
        let _ = f.join();
    }
    Run {
        code: if timed_out { None } else { status.code() },
        stdout: out_reader.join().unwrap_or_default(),
        stderr: String::from_utf8_lossy(&err_reader.join().unwrap_or_default()).into_owned(),
        timed_out,
        elapsed,
    }
}

/// Whether the binary has a `render` subcommand (it is being added).
fn has_command(name: &str) -> bool {
    static HELP: OnceLock<String> = OnceLock::new();
    let help = HELP.get_or_init(|| {
        let o = Command::new(env!("CARGO_BIN_EXE_subsurf"))
            .arg("--help")
            .output()
            .expect("cannot run subsurf --help");
        String::from_utf8_lossy(&o.stdout).into_owned()
    });
    help.lines()
        .any(|l| l.split_whitespace().next() == Some(name) && l.starts_with("  "))
}

/// The command line for `command` on `input`, writing to `out` (when it writes a file),
/// and the output file's name.
fn command_args(command: &str, input: &str, out: Option<&str>) -> (Vec<String>, Option<String>) {
    let (args, default_out): (Vec<&str>, Option<&str>) = match command {
        "info" => (vec!["info", input], None),
        "subdivide" => (vec!["subdivide", input, "-l", "1"], Some("out.obj")),
        "limit" => (vec!["limit", input, "--grid", "2"], Some("out.tsv")),
        "tessellate" => (vec!["tessellate", input, "--rate", "2"], Some("out.obj")),
        "bench" => (vec!["bench", input, "-l", "1", "--reps", "1"], None),
        "render" => (vec!["render", input, "--size", "80x60"], Some("out.png")),
        "spline" => (vec!["spline", input, "--rate", "2"], Some("out.obj")),
        "regularity" => (vec!["regularity", input, "--sample", "3"], None),
        "g2" => (vec!["g2", input, "--rate", "2"], Some("out.obj")),
        other => panic!("unknown subcommand {other} in expected.tsv"),
    };
    let mut args: Vec<String> = args.into_iter().map(String::from).collect();
    let out_name = default_out.map(|d| out.unwrap_or(d).to_owned());
    if let Some(o) = &out_name {
        args.push("-o".into());
        args.push(o.clone());
    }
    (args, out_name.filter(|o| o != "-"))
}

/// One row of `expected.tsv`.
#[derive(Clone, Debug)]
struct Row {
    line: usize,
    file: String,
    commands: Vec<String>,
    flags: Vec<String>,
    exit: i32,
    bug: bool,
    expected: Vec<String>,
}

fn rows() -> Vec<Row> {
    let path = corpus_dir().join("expected.tsv");
    let text = fs::read_to_string(&path).expect("read expected.tsv");
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() || line.starts_with('#') {
            continue;
        }
        let cols: Vec<&str> = line.split('\t').collect();
        assert!(
            cols.len() >= 6,
            "expected.tsv:{}: needs 6 or more tab-separated columns: {line:?}",
            i + 1
        );
        let commands = match cols[1] {
            "all" => ALL_COMMANDS.iter().map(|c| c.to_string()).collect(),
            list => list.split(',').map(|c| c.trim().to_owned()).collect(),
        };
        let flags = match cols[2] {
            "-" => Vec::new(),
            f => f.split_whitespace().map(String::from).collect(),
        };
        let exit = cols[3]
            .parse()
            .unwrap_or_else(|_| panic!("expected.tsv:{}: bad exit status", i + 1));
        let bug = match cols[4] {
            "ok" => false,
            "bug" => true,
            s => panic!(
                "expected.tsv:{}: status must be ok or bug, not {s:?}",
                i + 1
            ),
        };
        let expected = cols[5..]
            .iter()
            .filter(|s| **s != "-" && !s.is_empty())
            .map(|s| s.to_string())
            .collect();
        rows.push(Row {
            line: i + 1,
            file: cols[0].to_owned(),
            commands,
            flags,
            exit,
            bug,
            expected,
        });
    }
    rows
}

/// Runs `command` of `row` on a copy of its file in a fresh directory; returns the problems.
fn check(row: &Row, command: &str) -> Vec<String> {
    let dir = tempfile::tempdir().expect("temp dir");
    fs::copy(corpus_dir().join(&row.file), dir.path().join(&row.file)).expect("copy corpus file");
    let (mut args, out) = command_args(command, &row.file, None);
    args.extend(row.flags.iter().cloned());
    let run = run_limited(dir.path(), &args, None);
    let what = format!("expected.tsv:{} `subsurf {}`", row.line, args.join(" "));
    let mut problems = Vec::new();
    let mut fail = |m: String| {
        problems.push(format!(
            "{what}: {m}\n    stderr: {}",
            run.stderr.trim_end()
        ))
    };
    if run.timed_out {
        fail(format!("still running after {TIME_LIMIT:?}; killed"));
        return problems;
    }
    if run.stderr.contains("panicked") {
        fail("panicked".into());
    }
    if run.code != Some(row.exit) {
        fail(format!("exit status {:?}, expected {}", run.code, row.exit));
    }
    for e in &row.expected {
        if !run.stderr.contains(e.as_str()) {
            fail(format!("stderr lacks {e:?}"));
        }
    }
    let names = listing(dir.path());
    let stray: Vec<&String> = names
        .iter()
        .filter(|n| **n != row.file && Some(*n) != out.as_ref())
        .collect();
    if !stray.is_empty() {
        fail(format!("left files behind: {stray:?}"));
    }
    if row.exit == 0 {
        if row.expected.is_empty() && run.stderr.contains("error") {
            fail("an error message on success".into());
        }
        if let Some(o) = &out {
            if !names.contains(o) {
                fail(format!("exit 0 but no {o}"));
            }
        }
        if command == "info" && run.stdout.is_empty() {
            fail("info printed nothing".into());
        }
    } else {
        if out.as_ref().is_some_and(|o| names.contains(o)) {
            fail("failed but wrote its output file".into());
        }
        if !run.stdout.is_empty() {
            fail(format!(
                "failed but wrote {} bytes to stdout",
                run.stdout.len()
            ));
        }
        if !run.stderr.starts_with("error: ") {
            fail("no 'error: ' message".into());
        }
    }
    problems
}

/// Checks every (row, command) pair in parallel; panics listing all problems.
fn check_rows(rows: &[Row]) {
    let jobs: Vec<(&Row, &str)> = rows
        .iter()
        .flat_map(|r| r.commands.iter().map(move |c| (r, c.as_str())))
        .filter(|(_, c)| has_command(c))
        .collect();
    let next = AtomicUsize::new(0);
    let problems = Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get().clamp(1, 4));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(&(row, command)) = jobs.get(i) else {
                    break;
                };
                let p = check(row, command);
                problems.lock().unwrap().extend(p);
            });
        }
    });
    let problems = problems.into_inner().unwrap();
    assert!(
        problems.is_empty(),
        "{} of {} runs misbehaved:\n{}",
        problems.len(),
        jobs.len(),
        problems.join("\n")
    );
}

#[test]
fn corpus_files_behave_as_listed() {
    let rows: Vec<Row> = rows().into_iter().filter(|r| !r.bug).collect();
    assert!(rows.len() > 30, "expected.tsv has only {} rows", rows.len());
    check_rows(&rows);
}

/// Rows marked `bug`: open bugs, the behaviour wanted once they are fixed (none at the
/// moment; the test then checks nothing).
#[test]
#[ignore = "rows of expected.tsv marked bug describe open bugs; they fail until fixed"]
fn known_bugs() {
    let rows: Vec<Row> = rows().into_iter().filter(|r| r.bug).collect();
    check_rows(&rows);
}

/// A closed fan of `n` triangles (or quads) around vertex 1, a vertex of valence `n`.
fn fan(n: usize, quads: bool) -> String {
    let mut t = String::from("v 0 0 0\n");
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        t.push_str(&format!(
            "v {:.6} {:.6} {:.6}\n",
            a.cos(),
            a.sin(),
            0.1 * (3.0 * a).sin()
        ));
    }
    if quads {
        for i in 0..n {
            let a = (i as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
            t.push_str(&format!("v {:.6} {:.6} 0\n", 2.0 * a.cos(), 2.0 * a.sin()));
        }
    }
    for i in 0..n {
        let (a, b) = (i + 2, (i + 1) % n + 2);
        if quads {
            t.push_str(&format!("f 1 {a} {} {b}\n", n + 2 + i));
        } else {
            t.push_str(&format!("f 1 {a} {b}\n"));
        }
    }
    t
}

/// A vertex of valence 3000 (triangles and quads around it) and one of 70 000 (`info`,
/// `subdivide`, `limit`): every subcommand finishes (exit 0) before the hang guard. That the
/// cost grows linearly with the valence (it grew quadratically: 12 s at valence 1000, before
/// the limit surface shared one local refinement per high-valence vertex) is checked by
/// counting allocations at two valences, `crates/subsurf/tests/work_counts.rs`.
#[test]
fn high_valence_vertices() {
    let dir = dir_with(&[
        ("tri.obj", &fan(3000, false)),
        ("quad.obj", &fan(3000, true)),
        ("huge.obj", &fan(70_000, false)),
    ]);
    let mut jobs: Vec<(&str, &str)> = ALL_COMMANDS
        .iter()
        .filter(|c| has_command(c))
        .flat_map(|&c| [("tri.obj", c), ("quad.obj", c)])
        .collect();
    jobs.extend([
        ("huge.obj", "info"),
        ("huge.obj", "subdivide"),
        ("huge.obj", "limit"),
    ]);
    for (file, command) in jobs {
        let (args, _) = command_args(command, file, None);
        let run = run_limited(dir.path(), &args, None);
        assert!(
            !run.timed_out && run.code == Some(0),
            "{args:?}: exit {:?} after {:?}: {}",
            run.code,
            run.elapsed,
            run.stderr
        );
    }
}

#[test]
fn every_corpus_file_is_listed() {
    let listed: std::collections::BTreeSet<String> = rows().into_iter().map(|r| r.file).collect();
    let present: std::collections::BTreeSet<String> = listing(&corpus_dir())
        .into_iter()
        .filter(|n| n != "expected.tsv" && n != "README.md")
        .collect();
    let unlisted: Vec<_> = present.difference(&listed).collect();
    let missing: Vec<_> = listed.difference(&present).collect();
    assert!(
        unlisted.is_empty() && missing.is_empty(),
        "files without a row in expected.tsv: {unlisted:?}; rows without a file: {missing:?}"
    );
    for r in rows() {
        for c in &r.commands {
            assert!(
                ALL_COMMANDS.contains(&c.as_str()),
                "expected.tsv:{}: {c}",
                r.line
            );
        }
    }
}

/// The same errors through standard input and output: the message says `<stdin>:LINE:`
/// and nothing reaches standard output.
#[test]
fn bad_input_on_stdin_writes_nothing_to_stdout() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut problems = Vec::new();
    for row in rows()
        .iter()
        .filter(|r| !r.bug && r.exit == 1 && r.flags.is_empty())
    {
        let bytes = fs::read(corpus_dir().join(&row.file)).expect("read corpus file");
        for command in row.commands.iter().filter(|c| has_command(c)) {
            let (args, _) = command_args(command, "-", Some("-"));
            let run = run_limited(dir.path(), &args, Some(bytes.clone()));
            let what = format!("{} | subsurf {}", row.file, args.join(" "));
            if run.timed_out || run.code != Some(1) {
                problems.push(format!(
                    "{what}: exit {:?} (timed out: {})",
                    run.code, run.timed_out
                ));
            }
            if run.stderr.contains("panicked") {
                problems.push(format!("{what}: panicked: {}", run.stderr));
            }
            if !run.stdout.is_empty() {
                problems.push(format!(
                    "{what}: wrote {} bytes to stdout",
                    run.stdout.len()
                ));
            }
            for e in &row.expected {
                let e = e.replace(&format!("{}:", row.file), "<stdin>:");
                if !run.stderr.contains(&e) {
                    problems.push(format!("{what}: stderr lacks {e:?}: {}", run.stderr));
                }
            }
        }
    }
    assert!(
        listing(dir.path()).is_empty(),
        "files left: {:?}",
        listing(dir.path())
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn missing_or_unreadable_input_and_unwritable_output() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    fs::create_dir(dir.path().join("a-directory.obj")).expect("mkdir");
    for command in ALL_COMMANDS.iter().filter(|c| has_command(c)) {
        for (input, message) in [
            ("missing.obj", "cannot read missing.obj"),
            ("a-directory.obj", "cannot read a-directory.obj"),
        ] {
            let (args, _) = command_args(command, input, None);
            let run = run_limited(dir.path(), &args, None);
            assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
            assert!(run.stderr.contains(message), "{args:?}: {}", run.stderr);
            assert!(!run.stderr.contains("panicked"), "{args:?}: {}", run.stderr);
        }
        let (_, default_out) = command_args(command, "cube.obj", None);
        if let Some(name) = default_out {
            let out = format!("no-such-dir/{name}");
            let (args, _) = command_args(command, "cube.obj", Some(&out));
            let run = run_limited(dir.path(), &args, None);
            assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
            assert!(
                run.stderr.contains("no-such-dir"),
                "{args:?}: {}",
                run.stderr
            );
        }
    }
    assert_eq!(listing(dir.path()), ["a-directory.obj", "cube.obj"]);
}

#[test]
fn replay_bench_checks_memory_before_building() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let args: Vec<String> = [
        "bench",
        "cube.obj",
        "-l",
        "12",
        "--replay",
        "--max-memory",
        "1M",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let run = run_limited(dir.path(), &args, None);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("cube.obj: building a re-posing plan to level 12 needs about"),
        "{}",
        run.stderr
    );
}

#[test]
fn memory_guard_refuses_without_writing() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for (levels, extra) in [("12", vec!["--max-memory", "1M"]), ("4294967295", vec![])] {
        let mut args: Vec<String> = ["subdivide", "cube.obj", "-o", "out.obj", "-l", levels]
            .iter()
            .map(|s| s.to_string())
            .collect();
        args.extend(extra.iter().map(|s| s.to_string()));
        let run = run_limited(dir.path(), &args, None);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("cube.obj: refining to level")
                && run.stderr.contains("needs about"),
            "{args:?}: {}",
            run.stderr
        );
    }
    assert_eq!(listing(dir.path()), ["cube.obj"]);
}

/// Without `--max-memory`, jobs that would need far more memory than any machine has
/// (hundreds of gigabytes to terabytes; `tessellate --rate 460`: 2.1 billion vertices, just
/// under the library's cap on the output) are refused up front against the available memory, with
/// the estimate, by every subcommand that allocates from its arguments; `limit`, which
/// streams its rows (168 billion here, at least 3.7 TiB of text), against the disk space.
#[test]
fn memory_guards_without_a_cap() {
    // A 100 × 100 grid of quads.
    let mut grid = String::new();
    for j in 0..=100 {
        for i in 0..=100 {
            grid.push_str(&format!("v {i} {j} 0\n"));
        }
    }
    for j in 0..100 {
        for i in 0..100 {
            let a = j * 101 + i + 1;
            grid.push_str(&format!("f {a} {} {} {}\n", a + 1, a + 102, a + 101));
        }
    }
    let dir = dir_with(&[("grid.obj", &grid)]);
    let cases: [&[&str]; 5] = [
        &["limit", "grid.obj", "-o", "out.tsv", "--grid", "4096"],
        &["tessellate", "grid.obj", "-o", "out.obj", "--rate", "460"],
        &[
            "render",
            "grid.obj",
            "-o",
            "out.png",
            "--limit-rate",
            "1024",
        ],
        &["bench", "grid.obj", "-l", "4294967295"],
        &["bench", "grid.obj", "--limit-grid", "4096"],
    ];
    for case in cases {
        if !has_command(case[0]) {
            continue;
        }
        let args: Vec<String> = case.iter().map(|s| s.to_string()).collect();
        let run = run_limited(dir.path(), &args, None);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        let memory =
            run.stderr.contains("needs about") && run.stderr.contains("(the memory available)");
        let disk = case[0] == "limit"
            && run.stderr.contains("writes at least")
            && run.stderr.contains("free there; use a smaller --grid");
        assert!(
            run.stderr.starts_with("error: grid.obj: ") && (memory || disk),
            "{args:?}: {}",
            run.stderr
        );
        assert!(run.stdout.is_empty(), "{args:?}");
    }
    assert_eq!(listing(dir.path()), ["grid.obj"]);
}

/// A face with 70 000 vertices exceeds the 65 535 a face may have: refused at its line.
#[test]
fn face_with_too_many_vertices() {
    let n = 70_000;
    let mut text = String::with_capacity(n * 24);
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        text.push_str(&format!("v {:.5} {:.5} 0\n", a.cos(), a.sin()));
    }
    text.push('f');
    for i in 1..=n {
        text.push_str(&format!(" {i}"));
    }
    text.push('\n');
    let dir = dir_with(&[("big-face.obj", &text)]);
    for command in ALL_COMMANDS.iter().filter(|c| has_command(c)) {
        let (args, _) = command_args(command, "big-face.obj", None);
        let run = run_limited(dir.path(), &args, None);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(
            run.stderr.contains(
                "big-face.obj:70001: f: face has 70000 vertices; a face may have at most 65535"
            ),
            "{args:?}: {}",
            run.stderr
        );
        assert!(!run.stderr.contains("panicked"), "{args:?}: {}", run.stderr);
    }
    assert_eq!(listing(dir.path()), ["big-face.obj"]);
}

/// The text of a 1200-quad strip followed by one quad whose coordinates are finite but so
/// large that refinement overflows them.
fn strip_then_overflowing_quad() -> String {
    let n = 1200;
    let mut t = String::new();
    for i in 0..=n {
        let x = i as f64 / 7.0;
        t.push_str(&format!("v {x} 0.1 0\nv {x} 1.1 0.3\n"));
    }
    for i in 0..n {
        let a = 2 * i + 1;
        t.push_str(&format!("f {a} {} {} {}\n", a + 2, a + 3, a + 1));
    }
    t.push_str("v 1.5e308 0 5\nv 1.5e308 1 5\nv 1e308 1 5\nv 1e308 0 5\nf -4 -3 -2 -1\n");
    t
}

#[test]
fn non_finite_result_writes_nothing_to_stdout() {
    let dir = tempfile::tempdir().expect("temp dir");
    let args: Vec<String> = ["subdivide", "-", "-o", "-", "-l", "1"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let run = run_limited(
        dir.path(),
        &args,
        Some(strip_then_overflowing_quad().into_bytes()),
    );
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stdout.is_empty(),
        "{} bytes written to stdout before the error: {}",
        run.stdout.len(),
        run.stderr
    );
}

#[test]
fn limit_normals_do_not_depend_on_scale() {
    assert_no_zero_normals("cube_scaled_1e-100.obj");
}

#[test]
fn limit_normals_at_tiny_scales() {
    assert_no_zero_normals("cube_scaled_1e-200.obj");
}

/// `subdivide --limit` and `tessellate` on the corpus file `file` write no `vn 0 0 0`.
fn assert_no_zero_normals(file: &str) {
    let dir = tempfile::tempdir().expect("temp dir");
    fs::copy(corpus_dir().join(file), dir.path().join(file)).expect("copy");
    for args in [
        vec!["subdivide", file, "-o", "-", "-l", "1", "--limit"],
        vec!["tessellate", file, "-o", "-", "--rate", "2"],
    ] {
        let args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        let run = run_limited(dir.path(), &args, None);
        assert_eq!(run.code, Some(0), "{args:?}: {}", run.stderr);
        let text = String::from_utf8_lossy(&run.stdout);
        let zero = text
            .lines()
            .filter(|l| l.starts_with("vn "))
            .filter(|l| {
                l.split_whitespace()
                    .skip(1)
                    .all(|x| x.parse::<f64>().is_ok_and(|x| x == 0.0))
            })
            .count();
        assert_eq!(zero, 0, "{args:?}: {zero} zero normals");
    }
}

#[test]
fn limit_output_is_finite_or_an_error() {
    for file in [
        "far_vertex_1e95.obj",
        "fuzz_limit_eval_far_vertex.obj",
        "huge_coordinates.obj",
    ] {
        let dir = tempfile::tempdir().expect("temp dir");
        fs::copy(corpus_dir().join(file), dir.path().join(file)).expect("copy");
        let args: Vec<String> = ["limit", file, "--grid", "2", "-o", "-"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let run = run_limited(dir.path(), &args, None);
        match run.code {
            Some(0) => {
                let text = String::from_utf8_lossy(&run.stdout);
                let bad = text
                    .lines()
                    .filter(|l| {
                        l.split_whitespace()
                            .any(|x| x.parse::<f64>().is_ok_and(|x| !x.is_finite()))
                    })
                    .count();
                assert_eq!(bad, 0, "{file}: {bad} rows with NaN or inf:\n{text}");
            }
            Some(1) => assert!(run.stderr.contains(file), "{file}: {}", run.stderr),
            other => panic!("{file}: exit {other:?}: {}", run.stderr),
        }
    }
}

/// Every row that all the surface commands refuse (exit 1, a message with file and line,
/// nothing written) is refused the same way by the papers' commands. (`info` only reports,
/// so it accepts a file without faces.)
#[test]
fn paper_commands_refuse_broken_files_like_the_others() {
    let rows: Vec<Row> = rows()
        .into_iter()
        .filter(|r| !r.bug && r.exit == 1 && r.flags.is_empty())
        .filter(|r| {
            ALL_COMMANDS
                .iter()
                .filter(|&&c| c != "info")
                .all(|c| r.commands.iter().any(|rc| rc == c))
        })
        .map(|mut r| {
            r.commands = PAPER_COMMANDS.iter().map(|c| c.to_string()).collect();
            r
        })
        .collect();
    assert!(rows.len() > 30, "only {} rows", rows.len());
    check_rows(&rows);
}

/// On the files every mesh command accepts (odd but valid meshes: CRLF, non-manifold,
/// tiny scales, a vertex of valence 1000, ...) the papers' commands finish in time without
/// a panic: exit 0, 1 with an `error:` message and no output file (for example a spline
/// surface of an open mesh whose faces all touch the boundary), or 3 (regularity: not
/// certified).
#[test]
fn paper_commands_never_crash_on_the_corpus() {
    let rows: Vec<Row> = rows()
        .into_iter()
        .filter(|r| !r.bug && r.exit == 0 && r.flags.is_empty())
        .collect();
    let mut files: Vec<String> = rows.iter().map(|r| r.file.clone()).collect();
    files.sort();
    files.dedup();
    let mut problems = Vec::new();
    for file in &files {
        for command in PAPER_COMMANDS {
            let dir = tempfile::tempdir().expect("temp dir");
            fs::copy(corpus_dir().join(file), dir.path().join(file)).expect("copy corpus file");
            let (args, out) = command_args(command, file, None);
            let run = run_limited(dir.path(), &args, None);
            let what = format!("`subsurf {}`", args.join(" "));
            let wrote = out
                .as_ref()
                .is_some_and(|o| listing(dir.path()).contains(o));
            if run.timed_out {
                problems.push(format!("{what}: still running after {TIME_LIMIT:?}"));
            } else if run.stderr.contains("panicked") {
                problems.push(format!("{what}: panicked: {}", run.stderr));
            } else {
                match run.code {
                    Some(0) | Some(3) => {}
                    Some(1) if run.stderr.lines().any(|l| l.starts_with("error: ")) && !wrote => {}
                    code => problems.push(format!(
                        "{what}: exit {code:?} (wrote output: {wrote}): {}",
                        run.stderr.trim_end()
                    )),
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn bench_refuses_zero_repetitions_and_empty_grids() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    for (flags, needle) in [
        (&["--reps", "0"][..], "--reps"),
        (&["--limit-grid", "0"], "--limit-grid"),
        (&["--limit-grid", "5000"], "--limit-grid"),
    ] {
        let mut args = vec!["bench".to_string(), "cube.obj".to_string()];
        args.extend(flags.iter().map(|s| s.to_string()));
        let run = run_limited(dir.path(), &args, None);
        assert_eq!(run.code, Some(2), "{flags:?}: {}", run.stderr);
        assert!(run.stderr.contains(needle), "{flags:?}: {}", run.stderr);
        assert!(run.stdout.is_empty(), "{flags:?}: {:?}", run.stdout);
    }
}
