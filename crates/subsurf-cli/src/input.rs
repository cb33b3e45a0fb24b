//! Reading the input mesh from a file or standard input.

use std::io::Read;
use std::path::Path;

use anyhow::{bail, Context, Result};
use subsurf::io::obj::{parse_obj, ObjFile};
use subsurf::mesh::TopologyWarning;

/// A parsed input and the name used for it in messages.
pub struct Input {
    /// The file name as given, or `<stdin>`.
    pub name: String,
    /// The parsed file.
    pub obj: ObjFile,
}

impl Input {
    /// Reads and parses `arg` (`-` for standard input). Errors name the file; parse errors
    /// also name the line.
    pub fn read(arg: &Path) -> Result<Self> {
        let (name, bytes) = if arg == Path::new("-") {
            let mut bytes = Vec::new();
            std::io::stdin()
                .lock()
                .read_to_end(&mut bytes)
                .context("cannot read standard input")?;
            ("<stdin>".to_owned(), bytes)
        } else {
            let name = arg.display().to_string();
            let bytes = std::fs::read(arg).with_context(|| format!("cannot read {name}"))?;
            (name, bytes)
        };
        // `ObjError` already reads `file:line: message`; no context needed.
        let obj = parse_obj(&bytes, &name)?;
        Ok(Self { name, obj })
    }

    /// Like [`read`](Self::read), for the commands that compute a surface: an input without
    /// faces has none, and is far more often the wrong file (an empty one, a `.mtl`, an ASCII
    /// STL: OBJ readers skip statements they do not know) than a wish for empty output, so it
    /// is an error rather than an empty result.
    pub fn read_surface(arg: &Path) -> Result<Self> {
        let input = Self::read(arg)?;
        if input.obj.mesh.num_faces() == 0 {
            bail!(
                "{}: no faces (no 'f' lines), so there is no surface; is this an OBJ file?",
                input.name
            );
        }
        Ok(input)
    }

    /// Rejects what OpenSubdiv would accept but a strict pipeline should not: faces that
    /// repeat a vertex, non-manifold edges and vertices, inconsistently oriented faces.
    /// The error names the file and, where it concerns a face, its line.
    pub fn check_strict(&self) -> Result<()> {
        let Err(e) = self.obj.mesh.check_strict() else {
            return Ok(());
        };
        // In the file's terms: faces and vertices numbered from 1, with the line.
        let (line, message) = self.obj.describe_error(&e);
        match line {
            Some(l) => bail!("{}:{l}: {message} (--strict)", self.name),
            None => bail!("{}: {message} (--strict)", self.name),
        }
    }

    /// A warning of the mesh layer in the file's terms: faces and vertices numbered from 1,
    /// with the line where one is known (`FILE:LINE: message`).
    pub fn warning(&self, w: &TopologyWarning) -> String {
        match self.obj.describe_warning(w) {
            (Some(l), message) => format!("{}:{l}: {message}", self.name),
            (None, message) => format!("{}: {message}", self.name),
        }
    }

    /// The warnings every command gives about its input, in the file's terms: one per tag
    /// that was read but is not honoured, then those of
    /// [`PolyMesh::warnings`](subsurf::mesh::PolyMesh::warnings) (faces that repeat a
    /// vertex, creases on no edge).
    pub fn warnings(&self) -> impl Iterator<Item = String> + '_ {
        let tags = self.obj.unsupported_tags.iter().map(|t| {
            format!(
                "{}:{}: tag '{}' is not supported and was ignored",
                self.name, t.line, t.name
            )
        });
        tags.chain(
            self.obj
                .mesh
                .warnings()
                .into_iter()
                .map(|w| self.warning(&w)),
        )
    }

    /// A warning of a job's topology in the file's terms, unless [`warnings`](Self::warnings)
    /// gives it already.
    pub fn topology_warning(&self, w: &TopologyWarning) -> Option<String> {
        match w {
            TopologyWarning::DegenerateFaces { .. } | TopologyWarning::CreaseEdgeMissing { .. } => {
                None
            }
            _ => Some(self.warning(w)),
        }
    }
}
