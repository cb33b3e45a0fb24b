//! Where results go: standard output or a file written atomically.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use subsurf::io::write_atomically;

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
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
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
