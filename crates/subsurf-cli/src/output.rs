//! Where results go: standard output or a file written atomically.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{bail, Context, Result};
use subsurf::io::{write_atomically, TessellationFormat};

/// An output destination.
pub enum Output {
    /// `-`: buffered standard output.
    Stdout,
    /// A file, replaced only when writing succeeded completely.
    File(PathBuf),
}

impl Output {
    /// `-` is standard output, anything else a file.
    pub fn new(arg: &Path) -> Self {
        if arg == Path::new("-") {
            Self::Stdout
        } else {
            Self::File(arg.to_path_buf())
        }
    }

    /// The destination as it appears in messages.
    pub fn name(&self) -> String {
        match self {
            Self::Stdout => "<stdout>".to_owned(),
            Self::File(p) => p.display().to_string(),
        }
    }

    /// Fails early (before any expensive work) when a file cannot possibly be written
    /// because its directory is missing or the path is a directory.
    pub fn check(&self) -> Result<()> {
        let Self::File(path) = self else {
            return Ok(());
        };
        if path.is_dir() {
            bail!("cannot write {}: it is a directory", path.display());
        }
        let dir = directory(path);
        match fs::metadata(dir) {
            Ok(m) if m.is_dir() => Ok(()),
            Ok(_) => bail!(
                "cannot write {}: {} is not a directory",
                path.display(),
                dir.display()
            ),
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                bail!(
                    "cannot write {}: directory {} does not exist",
                    path.display(),
                    dir.display()
                )
            }
            Err(e) => Err(e).with_context(|| format!("cannot write {}", path.display())),
        }
    }

    /// Fails early when a file of at least `bytes` cannot fit in the space free on its file
    /// system (Linux `statvfs`; elsewhere, and for standard output, nothing is checked):
    /// `NAME: WHAT writes at least X MiB to OUT, more than the Y MiB free there; HINT`.
    /// For jobs that stream their output, which their memory guard no longer bounds.
    pub fn check_space(&self, name: &str, what: &str, bytes: u64, hint: &str) -> Result<()> {
        let Self::File(path) = self else {
            return Ok(());
        };
        match free_space(directory(path)) {
            Some(free) if bytes > free => bail!(
                "{name}: {what} writes at least {} to {}, more than the {} free there; {hint}",
                crate::memory::size(bytes),
                path.display(),
                crate::memory::size(free),
            ),
            _ => Ok(()),
        }
    }

    /// Writes with `write`. A file is written to a temporary file first and renamed into
    /// place, so on error nothing (or the previous file) is at the destination.
    pub fn write<F>(&self, write: F) -> Result<()>
    where
        F: FnOnce(&mut dyn Write) -> io::Result<()>,
    {
        match self {
            Self::Stdout => {
                let mut w = BufWriter::with_capacity(1 << 16, io::stdout().lock());
                write(&mut w)
                    .and_then(|()| w.flush())
                    .context("cannot write to standard output")
            }
            Self::File(path) => write_atomically(path, |w| write(w))
                .with_context(|| format!("cannot write {}", path.display())),
        }
    }
}

/// The directory a file `path` is written in (`.` for a bare file name).
fn directory(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Bytes free to an unprivileged writer on the file system of `dir` (`statvfs`'s
/// `f_bavail × f_frsize`), if known.
#[cfg(target_os = "linux")]
fn free_space(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    let mut st = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: `c` is NUL-terminated and `st` is writable; `statvfs` fills it on success.
    let st = unsafe {
        if libc::statvfs(c.as_ptr(), st.as_mut_ptr()) != 0 {
            return None;
        }
        st.assume_init()
    };
    #[allow(clippy::useless_conversion)] // The field types differ between targets.
    u64::from(st.f_bavail).checked_mul(u64::from(st.f_frsize))
}

/// Not known here: nothing is checked.
#[cfg(not(target_os = "linux"))]
fn free_space(_dir: &Path) -> Option<u64> {
    None
}

/// Writes `text` to standard output and flushes it: `print!` that returns an error (a
/// full disk, a closed pipe: `main` takes a broken pipe for success) instead of panicking.
pub fn print(text: &str) -> Result<()> {
    let mut out = io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .context("cannot write to standard output")
}

/// Writes a line to standard error: `eprintln!` without its panic when standard error
/// cannot be written (full or closed), where the message cannot be reported anyway.
pub fn eprint_line(line: &str) {
    let mut err = io::stderr().lock();
    let _ = err
        .write_all(line.as_bytes())
        .and_then(|()| err.write_all(b"\n"));
}

/// Directories [`create_dir_all`] made, outermost first, until the run succeeds.
static CREATED_DIRS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Creates `dir` and its missing parents, remembering which it made, so that a run that
/// fails or is stopped removes them again ([`remove_created_dirs`]) and leaves nothing.
pub fn create_dir_all(dir: &Path) -> Result<()> {
    let mut missing = Vec::new();
    let mut d = dir;
    while !d.as_os_str().is_empty() && fs::symlink_metadata(d).is_err() {
        missing.push(d.to_path_buf());
        match d.parent() {
            Some(p) => d = p,
            None => break,
        }
    }
    for d in missing.into_iter().rev() {
        match fs::create_dir(&d) {
            Ok(()) => CREATED_DIRS
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .push(d),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && d.is_dir() => {}
            Err(e) => {
                remove_created_dirs();
                return Err(e).with_context(|| format!("cannot create directory {}", d.display()));
            }
        }
    }
    Ok(())
}

/// Removes the directories [`create_dir_all`] made, innermost first, where they are still
/// empty (a failed or stopped run wrote nothing to them).
pub fn remove_created_dirs() {
    let mut dirs = CREATED_DIRS.lock().unwrap_or_else(|p| p.into_inner());
    while let Some(d) = dirs.pop() {
        let _ = fs::remove_dir(d);
    }
}

/// A file format an output is written in, told by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// Binary PLY (`.ply`).
    Ply,
    /// Binary STL (`.stl`).
    Stl,
    /// Binary glTF 2.0 (`.glb`).
    Glb,
    /// PNG picture (`.png`).
    Png,
    /// SVG drawing (`.svg`).
    Svg,
    /// JSON (`.json`).
    Json,
    /// IGES 5.3 (`.igs`, `.iges`).
    Iges,
    /// Rows of numbers as text (`.txt`, `.tsv`, `.dat`).
    Text,
}

impl Format {
    /// The extensions of the format, the usual one first.
    fn extensions(self) -> &'static [&'static str] {
        match self {
            Self::Obj => &["obj"],
            Self::Ply => &["ply"],
            Self::Stl => &["stl"],
            Self::Glb => &["glb"],
            Self::Png => &["png"],
            Self::Svg => &["svg"],
            Self::Json => &["json"],
            Self::Iges => &["igs", "iges"],
            Self::Text => &["txt", "tsv", "dat"],
        }
    }
}

/// The formats of each command's `--output` (and `--plot`, `--control-mesh`): the one list
/// both the up-front check ([`check_extension`]) and the command read.
pub mod formats {
    use super::Format::{self, *};
    /// `subsurf tessellate`.
    pub const TESSELLATE: &[Format] = &[Obj, Ply, Stl, Glb];
    /// `subsurf spline`.
    pub const SPLINE: &[Format] = &[Obj, Ply, Stl, Glb];
    /// `subsurf g2`: tessellations, the patches' control points, IGES surfaces, a picture.
    pub const G2: &[Format] = &[Obj, Ply, Stl, Glb, Json, Iges, Png];
}

impl Format {
    /// The format of output `path`, one of `formats` (the command's list): by its
    /// extension (any case); `-` (standard output) is `dash`.
    ///
    /// # Errors
    /// An extension not in `formats`, or none.
    pub fn of(path: &Path, formats: &[Format], dash: Format) -> anyhow::Result<Format> {
        if path == Path::new("-") {
            return Ok(dash);
        }
        let list = extension_list(formats);
        let Some(ext) = path.extension() else {
            anyhow::bail!(
                "cannot write {}: the output needs an extension {list} (or '-' for {} on \
                 standard output)",
                path.display(),
                dash.name()
            );
        };
        let ext = ext.to_string_lossy().to_ascii_lowercase();
        formats
            .iter()
            .copied()
            .find(|f| f.extensions().contains(&ext.as_str()))
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "cannot write {}: unknown output format '.{ext}' (expected {list})",
                    path.display()
                )
            })
    }

    /// The format's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Obj => "OBJ",
            Self::Ply => "PLY",
            Self::Stl => "STL",
            Self::Glb => "glTF",
            Self::Png => "PNG",
            Self::Svg => "SVG",
            Self::Json => "JSON",
            Self::Iges => "IGES",
            Self::Text => "text",
        }
    }

    /// The library's format for writing a tessellation in this format, if it is one.
    pub fn tessellation(self) -> Option<TessellationFormat> {
        TessellationFormat::from_extension(self.extensions()[0])
    }
}

/// The format of output `path` of a command that writes tessellations only (`formats`, all
/// of them tessellation formats); `-` is OBJ.
///
/// # Errors
/// As [`Format::of`].
pub fn tessellation_format(path: &Path, formats: &[Format]) -> Result<TessellationFormat> {
    let f = Format::of(path, formats, Format::Obj)?;
    f.tessellation()
        .with_context(|| format!("{} is not a tessellation format", f.name()))
}

/// The list `.a, .b or .c` of the extensions of `formats`.
fn extension_list(formats: &[Format]) -> String {
    let all: Vec<String> = formats
        .iter()
        .flat_map(|f| f.extensions())
        .map(|e| format!(".{e}"))
        .collect();
    match all.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// Checks that `path`, an output of a command that writes `formats`, has an extension
/// (any case) of one of them, or none: `-` (standard output) and names without an
/// extension (devices such as `/dev/stdout`) are left to the command, which writes its
/// usual format there or asks for an extension. Any other extension is an error, a usage
/// error (exit 2) before anything runs: `-o out.fbx` must not silently write OBJ.
pub fn check_extension(path: &Path, formats: &[Format]) -> Result<(), String> {
    if path == Path::new("-") {
        return Ok(());
    }
    let Some(ext) = path.extension() else {
        return Ok(());
    };
    let ext = ext.to_string_lossy().to_ascii_lowercase();
    if formats
        .iter()
        .any(|f| f.extensions().contains(&ext.as_str()))
    {
        Ok(())
    } else {
        Err(format!(
            "'.{ext}' is not a format this command writes: it writes {}",
            extension_list(formats)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_name_formats() {
        let all = [Format::Obj, Format::Ply, Format::Glb];
        let f = |s: &str| check_extension(Path::new(s), &all);
        for ok in ["a.obj", "A.PLY", "dir.v2/model.glb", "-", "/dev/stdout"] {
            assert_eq!(f(ok), Ok(()), "{ok}");
        }
        assert_eq!(
            f("out.fbx"),
            Err("'.fbx' is not a format this command writes: it writes .obj, .ply or .glb".into())
        );
        assert_eq!(
            check_extension(Path::new("x.iges"), &[Format::Obj, Format::Iges]),
            Ok(())
        );
        assert_eq!(
            check_extension(Path::new("x.png"), &[Format::Obj]),
            Err("'.png' is not a format this command writes: it writes .obj".into())
        );
    }
}
