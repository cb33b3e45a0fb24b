//! Atomic file output: write a temporary file next to the target, rename it into place.
use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes the temporary files of one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `path` through a temporary file in the same directory, renamed into place only
/// when `write` succeeds; on any error the temporary file is removed.
///
/// The temporary file is `.{file name}.tmp-{pid}-{counter}` next to `path`, so the rename
/// stays on one file system and is atomic: `path` holds either its old contents (or does
/// not exist) or the complete new file, never a partial one. The data is not `fsync`ed.
/// The directory is not created.
///
/// A symbolic link at `path` is followed: the file it points to is replaced, not the link.
/// A `path` that exists and is not a regular file (a device such as `/dev/null` or
/// `/dev/stdout`, a named pipe, a socket) is written in place, since such files cannot be
/// replaced without breaking them (renaming onto `/dev/null` as root would turn the device
/// into an ordinary file); output to them is then not atomic. The permissions of a replaced
/// regular file are kept.
///
/// # Errors
/// Errors creating the temporary file (for example when the directory does not exist),
/// errors returned by `write`, and errors flushing or renaming. The temporary file is
/// removed in every case, also when `write` panics.
pub fn write_atomically<F>(path: &Path, write: F) -> io::Result<()>
where
    F: FnOnce(&mut BufWriter<std::fs::File>) -> io::Result<()>,
{
    // Follow a symbolic link to the file it names (which need not exist yet).
    let resolved;
    let path = match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => {
            resolved = resolve_link(path)?;
            resolved.as_path()
        }
        _ => path,
    };
    let existing = fs::metadata(path).ok();
    if let Some(meta) = &existing {
        if !meta.is_file() {
            if meta.is_dir() {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("{} is a directory", path.display()),
                ));
            }
            // A device, pipe or socket: write straight into it.
            let mut out = BufWriter::new(OpenOptions::new().write(true).open(path)?);
            write(&mut out)?;
            return out.flush();
        }
    }
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} does not name a file", path.display()),
        )
    })?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let (file, temp) = create_temp(dir, name)?;
    // Declared before `out`, so dropped after it: the file is closed before removal.
    let mut guard = RemoveOnDrop(Some(temp));
    if let Some(meta) = &existing {
        file.set_permissions(meta.permissions())?;
    }
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    out.flush()?;
    let file = out.into_inner().map_err(io::IntoInnerError::into_error)?;
    drop(file);
    if let Some(temp) = &guard.0 {
        fs::rename(temp, path)?;
    }
    guard.0 = None;
    Ok(())
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

/// Creates a new, uniquely named temporary file in `dir`.
fn create_temp(dir: &Path, name: &std::ffi::OsStr) -> io::Result<(File, PathBuf)> {
    let pid = std::process::id();
    let mut attempts = 0;
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut temp_name = OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".tmp-{pid}-{n}"));
        let temp = dir.join(temp_name);
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => return Ok((file, temp)),
            // A leftover of an earlier process with the same id: try the next name.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempts < 100 => {
                attempts += 1;
            }
            Err(e) => return Err(e),
        }
    }
}

/// Removes the temporary file unless disarmed (by taking the path).
struct RemoveOnDrop(Option<PathBuf>);

impl Drop for RemoveOnDrop {
    fn drop(&mut self) {
        if let Some(path) = self.0.take() {
            let _ = fs::remove_file(path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn a_directory_is_refused() {
        let scratch = scratch();
        let dir = scratch.path();
        let err = write_atomically(dir, |w| w.write_all(b"x")).unwrap_err();
        assert!(err.to_string().contains("is a directory"), "{err}");
    }
}
