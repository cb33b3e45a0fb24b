//! Reading the input mesh (OBJ, PLY or glTF, told apart by content) from a file or
//! standard input, within the job's memory limit.

use std::path::Path;

use anyhow::{bail, Result};
use subsurf::io::ObjFile;
use subsurf::io::{read_mesh, read_mesh_from, MeshFormat, ReadMeshError};
use subsurf::mesh::{MeshError, TopologyWarning};

/// A parsed input and the name used for it in messages.
pub struct Input {
    /// The file name as given, or `<stdin>`.
    pub name: String,
    /// The parsed file (for PLY: the mesh, and the lines of an ASCII file's faces; for
    /// glTF: the welded mesh).
    pub obj: ObjFile,
    /// The format it was read from.
    pub format: MeshFormat,
    /// What the file holds and the mesh leaves out (PLY's other properties and elements,
    /// glTF's normals, materials, ...).
    pub ignored: Vec<String>,
}

impl Input {
    /// Reads and parses `arg` (`-` for standard input) in blocks, each checked as it
    /// arrives, refused (naming the file) when the input and the mesh parsed from it would
    /// need more than `max` bytes (`--max-memory`) or, without it, than the memory the
    /// system reports as available. Errors name the file (`<stdin>` for standard input);
    /// parse errors also name the line.
    pub fn read(arg: &Path, max: Option<u64>) -> Result<Self> {
        let limit = max.or_else(crate::memory::available);
        let read = if arg == Path::new("-") {
            read_mesh_from(std::io::stdin().lock(), "<stdin>", None, limit)
        } else {
            read_mesh(arg, limit)
        };
        let file = match read {
            Ok(file) => file,
            Err(ReadMeshError::TooLarge {
                name,
                needed,
                limit,
                whole,
            }) => {
                // Before the input is read whole, its bytes so far are a low estimate.
                return Err(crate::memory::too_large(
                    &name,
                    "reading the mesh",
                    (needed, !whole),
                    limit,
                    max.is_some(),
                    match max {
                        Some(_) => "raise --max-memory, or read a smaller input",
                        None => "free memory, or read a smaller input",
                    },
                ));
            }
            // The error already names the file (and the line).
            Err(e) => return Err(e.into()),
        };
        let name = match arg == Path::new("-") {
            true => "<stdin>".to_owned(),
            false => arg.display().to_string(),
        };
        Ok(Self {
            name,
            obj: file.obj,
            format: file.format,
            ignored: file.ignored,
        })
    }

    /// Like [`read`](Self::read), for the commands that compute a surface: an input without
    /// faces has none, and is far more often the wrong file (an empty one, a `.mtl`, an ASCII
    /// STL: OBJ readers skip statements they do not know) than a wish for empty output, so it
    /// is an error rather than an empty result.
    pub fn read_surface(arg: &Path, max: Option<u64>) -> Result<Self> {
        let input = Self::read(arg, max)?;
        if input.obj.mesh.num_faces() == 0 {
            match input.format {
                MeshFormat::Obj => bail!(
                    "{}: no faces (no 'f' lines), so there is no surface; is this an OBJ file?",
                    input.name
                ),
                MeshFormat::Ply(_) => bail!(
                    "{}: no faces (no face element, or no records in it), so there is no \
                     surface",
                    input.name
                ),
                MeshFormat::Gltf { .. } => {
                    bail!("{}: no triangles, so there is no surface", input.name)
                }
            }
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
        match self.describe_error(&e) {
            (Some(l), message) => bail!("{}:{l}: {message} (--strict)", self.name),
            (None, message) => bail!("{}: {message} (--strict)", self.name),
        }
    }

    /// `e` in the file's terms: the line it concerns, if known, and the message with faces
    /// and vertices numbered as the file numbers them (from 1 in OBJ, from 0 in PLY).
    pub fn describe_error(&self, e: &MeshError) -> (Option<usize>, String) {
        self.obj.describe_error_from(e, self.format.first_index())
    }

    /// A warning of the mesh layer in the file's terms: faces and vertices numbered as the
    /// file numbers them, with the line where one is known (`FILE:LINE: message`).
    pub fn warning(&self, w: &TopologyWarning) -> String {
        match self.obj.describe_warning_from(w, self.format.first_index()) {
            (Some(l), message) => format!("{}:{l}: {message}", self.name),
            (None, message) => format!("{}: {message}", self.name),
        }
    }

    /// The warnings every command gives about its input, in the file's terms: one per tag
    /// that was read but is not honoured, one for what a PLY file holds besides the mesh
    /// (other properties and elements, not used), then those of
    /// [`PolyMesh::warnings`](subsurf::mesh::PolyMesh::warnings) (faces that repeat a
    /// vertex, creases on no edge).
    pub fn warnings(&self) -> impl Iterator<Item = String> + '_ {
        let tags = self.obj.unsupported_tags.iter().map(|t| {
            format!(
                "{}:{}: tag '{}' is not supported and was ignored",
                self.name, t.line, t.name
            )
        });
        let ignored = (!self.ignored.is_empty()).then(|| {
            format!(
                "{}: not used, so ignored: {}",
                self.name,
                self.ignored.join("; ")
            )
        });
        let mesh = self
            .obj
            .mesh
            .warnings()
            .into_iter()
            .map(|w| self.warning(&w));
        tags.chain(ignored).chain(mesh)
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
