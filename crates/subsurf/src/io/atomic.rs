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
/// # Errors
/// Errors creating the temporary file (for example when the directory does not exist),
/// errors returned by `write`, and errors flushing or renaming. The temporary file is
/// removed in every case, also when `write` panics.
pub fn write_atomically<F>(path: &Path, write: F) -> io::Result<()>
where
    F: FnOnce(&mut BufWriter<std::fs::File>) -> io::Result<()>,
{
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
