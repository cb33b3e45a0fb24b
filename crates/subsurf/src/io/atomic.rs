//! Atomic file output: write a temporary file next to the target, rename it into place.
use std::ffi::{OsStr, OsString};
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// Distinguishes the temporary files of one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// The temporary files this process has created and not yet renamed or removed, for
/// [`remove_temporary_files`], and whether that has run (no more are created then).
static TEMPORARIES: Mutex<Temporaries> = Mutex::new(Temporaries {
    paths: Vec::new(),
    stopped: false,
});

struct Temporaries {
    paths: Vec<PathBuf>,
    stopped: bool,
}

/// The registry, also after a panic while it was held (its state is then still valid: a
/// list of paths and a flag).
fn temporaries() -> MutexGuard<'static, Temporaries> {
    TEMPORARIES.lock().unwrap_or_else(|p| p.into_inner())
}

/// The longest file name most file systems take (POSIX `NAME_MAX` on Linux, macOS and the
/// BSDs; NTFS counts UTF-16 units, of which a byte is at most one).
const NAME_MAX: usize = 255;

/// Writes `path` through a temporary file in the same directory, renamed into place only
/// when `write` succeeds; on any error the temporary file is removed.
///
/// The temporary file is `.{file name}.tmp-{pid}-{counter}` next to `path` (the file name
/// shortened when that would exceed 255 bytes), so the rename stays on one file system and
/// is atomic: `path` holds either its old contents (or does not exist) or the complete new
/// file, never a partial one. The data is not `fsync`ed. The directory is not created.
///
/// A symbolic link at `path` is followed: the file it points to is replaced, not the link.
/// A `path` that exists and is not a regular file (a device such as `/dev/null` or
/// `/dev/stdout`, a named pipe, a socket) is written in place, since such files cannot be
/// replaced without breaking them (renaming onto `/dev/null` as root would turn the device
/// into an ordinary file); output to them is then not atomic. The permissions of a replaced
/// regular file are kept.
///
/// Several files that must appear together or not at all are written with
/// [`PendingFile`] instead, and renamed into place once all are complete.
///
/// # Errors
/// Errors creating the temporary file (for example when the directory does not exist),
/// errors returned by `write`, and errors flushing or renaming. The temporary file is
/// removed in every case, also when `write` panics.
pub fn write_atomically<F>(path: &Path, write: F) -> io::Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> io::Result<()>,
{
    let mut file = PendingFile::create(path)?;
    write(file.writer())?;
    file.finish()?.commit()
}

/// A file being written: a temporary file beside its destination, renamed into place by
/// [`Finished::commit`], removed if dropped before (on an error or a panic) or by
/// [`remove_temporary_files`] (on a signal).
///
/// ```
/// # fn main() -> std::io::Result<()> {
/// use std::io::Write;
/// use subsurf::io::PendingFile;
/// let dir = tempfile::tempdir()?;
/// // Both files appear, or neither.
/// let mut a = PendingFile::create(&dir.path().join("a.txt"))?;
/// a.writer().write_all(b"first")?;
/// let mut b = PendingFile::create(&dir.path().join("b.txt"))?;
/// b.writer().write_all(b"second")?;
/// let (a, b) = (a.finish()?, b.finish()?);
/// assert!(!dir.path().join("a.txt").exists());
/// a.commit()?;
/// b.commit()?;
/// assert_eq!(std::fs::read_to_string(dir.path().join("b.txt"))?, "second");
/// # Ok(())
/// # }
/// ```
pub struct PendingFile {
    out: BufWriter<File>,
    /// The temporary file; `None` when writing in place (devices, pipes).
    temp: Option<Temporary>,
    target: PathBuf,
}

/// A [`PendingFile`] written completely and closed, not yet in place.
#[must_use = "a finished file is removed unless committed"]
pub struct Finished {
    temp: Option<Temporary>,
    target: PathBuf,
}

impl PendingFile {
    /// Creates the temporary file for `path` (see [`write_atomically`] for its name, links,
    /// devices and permissions).
    ///
    /// # Errors
    /// `path` is a directory or names no file, or the temporary file cannot be created.
    pub fn create(path: &Path) -> io::Result<Self> {
        // Follow a symbolic link to the file it names (which need not exist yet).
        let target = match fs::symlink_metadata(path) {
            Ok(m) if m.file_type().is_symlink() => resolve_link(path)?,
            _ => path.to_path_buf(),
        };
        let existing = fs::metadata(&target).ok();
        if let Some(meta) = &existing {
            if meta.is_dir() {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("{} is a directory", target.display()),
                ));
            }
            if !meta.is_file() {
                // A device, pipe or socket: write straight into it.
                let file = OpenOptions::new().write(true).open(&target)?;
                return Ok(Self {
                    out: BufWriter::new(file),
                    temp: None,
                    target,
                });
            }
        }
        let name = target.file_name().ok_or_else(|| {
            io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} does not name a file", target.display()),
            )
        })?;
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let (file, temp) = create_temp(dir, name)?;
        if let Some(meta) = &existing {
            file.set_permissions(meta.permissions())?;
        }
        Ok(Self {
            out: BufWriter::new(file),
            temp: Some(temp),
            target,
        })
    }

    /// Where to write the contents.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        &mut self.out
    }

    /// Flushes and closes the file; it is still beside its destination.
    ///
    /// # Errors
    /// Errors flushing the buffer (the temporary file is then removed).
    pub fn finish(self) -> io::Result<Finished> {
        let Self { out, temp, target } = self;
        let file = out.into_inner().map_err(io::IntoInnerError::into_error)?;
        drop(file);
        Ok(Finished { temp, target })
    }
}

impl Finished {
    /// Renames the file into place (nothing to do for a file written in place).
    ///
    /// # Errors
    /// Errors renaming (the temporary file is then removed).
    pub fn commit(mut self) -> io::Result<()> {
        if let Some(temp) = self.temp.take() {
            // Renamed and unregistered under the registry's lock: a signal's
            // `remove_temporary_files` either removed it before (the rename then fails) or
            // finds it in place, as the output, which it must not remove.
            let mut list = temporaries();
            let Some(i) = list.paths.iter().rposition(|p| *p == temp.0) else {
                return Err(io::Error::new(
                    io::ErrorKind::Interrupted,
                    "stopped: temporary files were removed",
                ));
            };
            let renamed = fs::rename(&temp.0, &self.target);
            if renamed.is_ok() {
                list.paths.swap_remove(i);
            }
            drop(list);
            // Dropped registered (a failed rename), `temp` removes the file; unregistered,
            // it leaves the output alone.
            renamed?;
        }
        Ok(())
    }
}

/// Removes every temporary file of [`write_atomically`] and [`PendingFile`] that this
/// process has open now, and makes every later attempt to create one fail
/// ([`io::ErrorKind::Interrupted`]), so that a run stopped by a signal leaves nothing
/// behind. For a program's signal handling: call it from an ordinary thread that waits for
/// the signal (not from inside a signal handler), then end the process.
pub fn remove_temporary_files() {
    let mut list = temporaries();
    list.stopped = true;
    for path in list.paths.drain(..) {
        let _ = fs::remove_file(path);
    }
}

/// The file a symbolic link finally points to (following chains of links, relative targets
/// taken from the link's directory); the file itself need not exist.
fn resolve_link(link: &Path) -> io::Result<PathBuf> {
    let mut path = link.to_path_buf();
    for _ in 0..40 {
        match fs::symlink_metadata(&path) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = fs::read_link(&path)?;
                path = match path.parent() {
                    Some(dir) if target.is_relative() => dir.join(target),
                    _ => target,
                };
            }
            _ => return Ok(path),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("{}: too many levels of symbolic links", link.display()),
    ))
}

/// The name of a temporary file for `name`: `.{name}.tmp-{pid}-{n}`, with `name` cut
/// short (at a character boundary where it is valid UTF-8) when the whole would be longer
/// than [`NAME_MAX`] bytes.
fn temp_name(name: &OsStr, pid: u32, n: u64) -> OsString {
    let suffix = format!(".tmp-{pid}-{n}");
    let room = NAME_MAX - 1 - suffix.len();
    let mut temp = OsString::from(".");
    if name.len() <= room {
        temp.push(name);
    } else {
        let lossy = name.to_string_lossy();
        let mut end = room;
        while !lossy.is_char_boundary(end) {
            end -= 1;
        }
        temp.push(&lossy[..end.min(lossy.len())]);
    }
    temp.push(suffix);
    temp
}

/// Creates a new, uniquely named temporary file in `dir`, registered for
/// [`remove_temporary_files`] (created and registered under its lock, so that it never
/// misses one).
fn create_temp(dir: &Path, name: &OsStr) -> io::Result<(File, Temporary)> {
    let pid = std::process::id();
    let mut attempts = 0;
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let temp = dir.join(temp_name(name, pid, n));
        let mut list = temporaries();
        if list.stopped {
            return Err(io::Error::new(
                io::ErrorKind::Interrupted,
                "stopped: temporary files were removed",
            ));
        }
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => {
                list.paths.push(temp.clone());
                return Ok((file, Temporary(temp)));
            }
            // A leftover of an earlier process with the same id: try the next name.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempts < 100 => {
                attempts += 1;
            }
            Err(e) => return Err(e),
        }
    }
}

/// A registered temporary file, removed (and unregistered) when dropped.
struct Temporary(PathBuf);

impl Temporary {
    /// Unregisters the file without removing it (renamed into place); `false` when it is
    /// no longer registered ([`remove_temporary_files`] removed it).
    fn forget(&self) -> bool {
        let mut list = temporaries();
        match list.paths.iter().rposition(|p| *p == self.0) {
            Some(i) => {
                list.paths.swap_remove(i);
                true
            }
            None => false,
        }
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if self.forget() {
            let _ = fs::remove_file(&self.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// An empty directory, removed with everything in it when the guard drops.
    fn scratch() -> tempfile::TempDir {
        tempfile::tempdir().unwrap()
    }

    #[test]
    fn replaces_a_file_and_leaves_no_temporary() {
        let scratch = scratch();
        let dir = scratch.path();
        let path = dir.join("out.txt");
        fs::write(&path, "old").unwrap();
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(fs::read_dir(dir).unwrap().count(), 1);
    }

    #[test]
    fn a_failed_write_keeps_the_old_contents() {
        let scratch = scratch();
        let dir = scratch.path();
        let path = dir.join("out.txt");
        fs::write(&path, "old").unwrap();
        let err = write_atomically(&path, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        });
        assert!(err.is_err());
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(fs::read_dir(dir).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn follows_symbolic_links_and_keeps_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let scratch = scratch();
        let dir = scratch.path();
        let target = dir.join("target.txt");
        fs::write(&target, "old").unwrap();
        fs::set_permissions(&target, fs::Permissions::from_mode(0o640)).unwrap();
        let link = dir.join("link.txt");
        std::os::unix::fs::symlink("target.txt", &link).unwrap();
        write_atomically(&link, |w| w.write_all(b"new")).unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
        let mode = fs::metadata(&target).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
    }

    /// A named pipe (like `/dev/null` or `/dev/stdout`, not a regular file) is written in
    /// place; replacing it would turn it into an ordinary file.
    #[cfg(unix)]
    #[test]
    fn writes_into_a_named_pipe_in_place() {
        use std::os::unix::fs::FileTypeExt;
        let scratch = scratch();
        let dir = scratch.path();
        let fifo = dir.join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !matches!(made, Ok(s) if s.success()) {
            return; // no mkfifo on this system
        }
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || fs::read_to_string(fifo).unwrap())
        };
        write_atomically(&fifo, |w| w.write_all(b"through the pipe")).unwrap();
        assert_eq!(reader.join().unwrap(), "through the pipe");
        assert!(fs::metadata(&fifo).unwrap().file_type().is_fifo());
    }

    /// A name of 255 bytes, the longest a file system takes, still gets a temporary file
    /// (its name shortened); nothing else is left in the directory.
    #[test]
    fn the_longest_names_are_written() {
        let scratch = scratch();
        let dir = scratch.path();
        for name in ["a".repeat(255), format!("{}.obj", "é".repeat(124))] {
            let path = dir.join(&name);
            write_atomically(&path, |w| w.write_all(b"x")).unwrap();
            assert_eq!(fs::read_to_string(&path).unwrap(), "x");
            fs::remove_file(&path).unwrap();
        }
        assert_eq!(fs::read_dir(dir).unwrap().count(), 0);
    }

    /// Files finished but not committed, or not finished, are removed when dropped.
    /// (`remove_temporary_files` acts on the whole process, so it is tested from a process
    /// of its own: the command-line tests stop `subsurf` by signals while it writes.)
    #[test]
    fn uncommitted_files_leave_nothing() {
        let scratch = scratch();
        let dir = scratch.path();
        let mut a = PendingFile::create(&dir.join("a")).unwrap();
        a.writer().write_all(b"a").unwrap();
        let a = a.finish().unwrap();
        let mut b = PendingFile::create(&dir.join("b")).unwrap();
        b.writer().write_all(b"b").unwrap();
        assert_eq!(fs::read_dir(dir).unwrap().count(), 2);
        drop(a);
        drop(b);
        assert_eq!(fs::read_dir(dir).unwrap().count(), 0);
    }

    #[test]
    fn a_directory_is_refused() {
        let scratch = scratch();
        let dir = scratch.path();
        let err = write_atomically(dir, |w| w.write_all(b"x")).unwrap_err();
        assert!(err.to_string().contains("is a directory"), "{err}");
    }
}
