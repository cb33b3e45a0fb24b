//! The OBJ reader: one pass over the lines, with the checks that need the whole file
//! (forward references to vertices, tag indices) done at the end. Files of two chunks
//! ([`CHUNK_BYTES`]) or more are read in chunks in parallel on the current rayon pool up
//! to the first tag, continued line or error, and the rest in one pass: the same result
//! ([`parallel_prefix`]).

use super::{FileOptions, ObjError, ObjFile, UnsupportedTag};
use crate::mesh::{
    BoundaryInterpolation, Corner, Crease, CreaseMethod, EdgeInterval, FaceGroups, FaceVarying,
    FaceVaryingInterpolation, GroupState, KnotTagError, KnotTags, MeshError, PolyMesh,
    SideInterval, Tags, TriangleSubdivision, VertexWeight, SHARPNESS_INFINITE,
};
use std::path::Path;
use std::str::SplitAsciiWhitespace;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Reads an OBJ file.
///
/// The whole file is read into memory and parsed with [`parse_obj`]; the path as displayed
/// is the source name in errors.
///
/// # Errors
/// An [`ObjError`] without a line when the file cannot be read
/// (`cannot read FILE: <OS message>`), else the errors of [`parse_obj`].
pub fn read_obj(path: &Path) -> Result<ObjFile, ObjError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| ObjError {
        source_name: name.clone(),
        line: None,
        message: format!("cannot read {name}: {e}"),
    })?;
    parse_obj(&bytes, &name)
}

/// Parses OBJ bytes; `source_name` is used in errors.
///
/// See the module documentation for what is read. Never panics; allocations grow
/// only with what the input contains, never with numbers written in it. Inputs of 4 MiB
/// or more are read in chunks of 2 MiB in parallel on the current rayon pool, as far as
/// they hold only vertices, faces, comments and statements that carry nothing (tags are
/// usually at the end), with the same result as one pass, errors included (the gain on a
/// large scan is in BENCHMARKS.md, "Reading and writing text").
///
/// # Errors
/// The first problem found, as an [`ObjError`] naming `source_name` and the 1-based line:
/// lines that are not UTF-8 text, malformed or non-finite numbers, missing coordinates,
/// malformed, zero or out-of-range indices, faces with fewer than 3 vertices, and
/// malformed or out-of-range tags. A face that lists a vertex twice is kept (a degenerate
/// face, as OpenSubdiv accepts it; the mesh layer reports it as a warning).
pub fn parse_obj(bytes: &[u8], source_name: &str) -> Result<ObjFile, ObjError> {
    parse_obj_in(bytes, source_name, CHUNK_BYTES, None).map_err(|f| match f {
        Refusal::Obj(e) => e,
        Refusal::TooLarge { .. } => unreachable!("no memory limit was given"),
    })
}

/// Why [`parse_obj_within`] gave no file.
#[derive(Debug)]
pub(crate) enum Refusal {
    /// The file is not valid OBJ.
    Obj(ObjError),
    /// Holding the file and the mesh read from it would take about `needed` bytes, more
    /// than the limit.
    TooLarge { needed: u64 },
}

/// [`parse_obj`], refused before the mesh is built when the input's bytes and the lists
/// read from them would need more than `limit` bytes ([`parse_memory`]).
pub(crate) fn parse_obj_within(
    bytes: &[u8],
    source_name: &str,
    limit: u64,
) -> Result<ObjFile, Refusal> {
    parse_obj_in(bytes, source_name, CHUNK_BYTES, Some(limit))
}

/// Files of at least two chunks of this many bytes are read by [`parallel_prefix`] (2 MiB):
/// large enough that handing a chunk to another thread costs little next to reading it.
const CHUNK_BYTES: usize = 1 << 21;

/// [`parse_obj`], reading files of two `chunk`s or more in chunks of about `chunk` bytes
/// on the current rayon pool (when it has more than one thread); with a `limit`, refused
/// as [`parse_obj_within`] says.
fn parse_obj_in(
    bytes: &[u8],
    source_name: &str,
    chunk: usize,
    limit: Option<u64>,
) -> Result<ObjFile, Refusal> {
    let parallel = bytes.len() / 2 >= chunk && rayon::current_num_threads() > 1;
    // The counts size the chunks' lists and the estimate of the memory needed.
    let chunks = (parallel || limit.is_some()).then(|| Chunks::new(bytes, chunk));
    if let (Some(limit), Some(chunks)) = (limit, &chunks) {
        let needed = parse_memory(bytes.len(), &chunks.counted);
        if needed > limit {
            return Err(Refusal::TooLarge { needed });
        }
    }
    let prefix = chunks
        .filter(|_| parallel)
        .and_then(|c| parallel_prefix(bytes, &c));
    let (mut parser, lines) = match prefix {
        Some(prefix) => prefix,
        None => (
            Parser::default(),
            PhysicalLines {
                rest: bytes,
                line: 0,
            },
        ),
    };
    parse_lines(&mut parser, lines, source_name).map_err(Refusal::Obj)?;
    parser.finish(source_name).map_err(Refusal::Obj)
}

/// An upper bound of the memory that reading `len` bytes whose chunks hold `counted`
/// takes at its peak: the bytes, and twice the lists read from them (24 bytes per vertex,
/// texture coordinate and normal, 8 per face for its offset and line, 12 per corner for
/// its vertex, texture coordinate and normal indices), since each chunk's lists are
/// joined into lists of the whole file (and a list read in one pass grows by doubling).
fn parse_memory(len: usize, counted: &[ChunkCounts]) -> u64 {
    let lists: u64 = counted
        .iter()
        .map(|c| {
            let elements: usize = c.elements.iter().sum();
            24 * elements as u64 + 8 * c.faces as u64 + 12 * c.corners as u64
        })
        .sum();
    (len as u64).saturating_add(lists.saturating_mul(2))
}

/// Reads `lines` into `parser`, a statement per logical line.
fn parse_lines(
    parser: &mut Parser,
    mut lines: PhysicalLines<'_>,
    source_name: &str,
) -> Result<(), ObjError> {
    let err = |line: usize, message: String| ObjError {
        source_name: source_name.to_owned(),
        line: Some(line),
        message,
    };
    let mut joined = String::new();
    while let Some((first, raw)) = lines.next() {
        let (data, continues) = line_data(raw, first).map_err(|m| err(first, m))?;
        match continues {
            false => parser.statement(data, first).map_err(|m| err(first, m))?,
            true => {
                // A logical line made of several physical lines: join them with spaces.
                joined.clear();
                joined.push_str(data);
                joined.push(' ');
                while let Some((no, raw)) = lines.next() {
                    let (data, continues) = line_data(raw, no).map_err(|m| err(no, m))?;
                    joined.push_str(data);
                    if !continues {
                        break;
                    }
                    joined.push(' ');
                }
                parser
                    .statement(&joined, first)
                    .map_err(|m| err(first, m))?;
            }
        }
    }
    Ok(())
}

/// Vertices, texture coordinates and normals (defined by a chunk, as [`element_counts`]
/// finds them, or before it).
type Counts = [usize; 3];

/// What [`element_counts`] finds in a chunk: its physical lines, its vertices, texture
/// coordinates and normals, its faces and their corners.
#[derive(Clone, Copy, Default)]
struct ChunkCounts {
    lines: usize,
    elements: Counts,
    faces: usize,
    corners: usize,
    /// Whether a line holds a `\r` that is not its last byte: a line end of its own
    /// ([`PhysicalLines`]), which the counts by `\n` miss, so the chunks are not used.
    lone_cr: bool,
}

/// A file cut into chunks of about a given size, each after a line feed, and what
/// [`element_counts`] finds in each (counted in parallel).
struct Chunks<'a> {
    /// The offset of each chunk.
    starts: Vec<usize>,
    /// The chunks.
    pieces: Vec<&'a [u8]>,
    /// What each holds.
    counted: Vec<ChunkCounts>,
}

impl<'a> Chunks<'a> {
    fn new(bytes: &'a [u8], chunk: usize) -> Self {
        use rayon::prelude::*;
        let mut starts = vec![0usize];
        while let Some(&last) = starts.last() {
            let Some(cut) = bytes.get(last.saturating_add(chunk)..).and_then(|rest| {
                let nl = rest.iter().position(|&b| b == b'\n')?;
                Some(last + chunk + nl + 1)
            }) else {
                break;
            };
            if cut >= bytes.len() {
                break;
            }
            starts.push(cut);
        }
        let pieces: Vec<&[u8]> = (starts.iter().enumerate())
            .map(|(i, &a)| &bytes[a..starts.get(i + 1).copied().unwrap_or(bytes.len())])
            .collect();
        let counted = pieces.par_iter().map(|c| element_counts(c)).collect();
        Self {
            starts,
            pieces,
            counted,
        }
    }
}

/// Reads the `chunks` of `bytes` in parallel, and returns what one pass would have read
/// up to the start of the first chunk that holds anything else than plain `v`, `vt`, `vn`
/// and `f` statements, comments and statements that carry nothing (`g`, `usemtl`, ...),
/// with the lines from there on; or `None` (read it all on one thread) if the chunks
/// cannot be joined (a line ends in a lone `\r`, or a chunk read other counts).
///
/// A chunk is read by a [`Parser`] of its own that knows how many elements the chunks
/// before it define (counted first, in parallel, by [`element_counts`]), so that its face
/// indices, relative ones included, resolve as in one pass; the chunk stops at a tag (`t`),
/// a line continued by a backslash or any error. The chunks before the first that stopped
/// are joined (their lists appended in order, the face corner offsets moved, the deferred
/// forward references kept as one pass keeps them), after checking that each defined as
/// many elements as counted. The rest, from the start of the chunk that stopped, is left
/// to [`parse_lines`], which reports its errors at their lines as one pass does: the
/// result, error or not, is the same as one pass's (test
/// `chunks_read_as_one_pass_reads`).
fn parallel_prefix<'a>(
    bytes: &'a [u8],
    chunks: &Chunks<'a>,
) -> Option<(Parser, PhysicalLines<'a>)> {
    use rayon::prelude::*;
    let Chunks {
        starts,
        pieces: chunks,
        counted,
    } = chunks;
    if counted.iter().any(|c| c.lone_cr) {
        return None;
    }
    // The line before each chunk's first, and the elements before it.
    let mut before = Vec::with_capacity(chunks.len());
    let (mut line, mut base) = (0usize, [0usize; 3]);
    for c in counted {
        before.push((line, base));
        line += c.lines;
        for (b, c) in base.iter_mut().zip(c.elements) {
            *b += c;
        }
    }
    // Each chunk's lists are allocated here, on the calling thread, for what it counted
    // (and the joined ones for the whole file): memory that a worker thread allocated
    // would stay with it after the chunks are joined, and a refinement that follows on
    // this thread could not reuse it (10 % more peak memory for a 0.96 M-quad file).
    let parsers: Vec<Parser> = (before.iter().zip(counted))
        .map(|(&(_, base), &c)| Parser::with_capacity(base, c))
        .collect();
    let stopped = AtomicUsize::new(usize::MAX);
    let parsed: Vec<(Parser, bool)> = (parsers.into_par_iter().zip(chunks).zip(&before))
        .enumerate()
        .map(|(i, ((p, c), &(line, _)))| read_chunk(p, c, line, i, &stopped))
        .collect();
    let total = counted
        .iter()
        .fold(ChunkCounts::default(), |a, c| ChunkCounts {
            lines: 0,
            elements: [0, 1, 2].map(|k| a.elements[k] + c.elements[k]),
            faces: a.faces + c.faces,
            corners: a.corners + c.corners,
            lone_cr: false,
        });
    let mut joined = Parser::with_capacity([0; 3], total);
    let mut next = 0;
    for ((p, complete), c) in parsed.into_iter().zip(counted) {
        if !complete {
            break;
        }
        if (p.base.iter().zip(p.counts()).map(|(b, n)| n - b)).ne(c.elements) {
            return None;
        }
        joined.append(p)?;
        next += 1;
    }
    let (rest, line) = match starts.get(next) {
        Some(&start) => (&bytes[start..], before[next].0),
        None => (&[][..], 0),
    };
    Some((joined, PhysicalLines { rest, line }))
}

/// The physical lines of a chunk, the `v`, `vt` and `vn` statements among them (lines
/// whose first word, after ASCII whitespace, is one of these keywords, followed by
/// whitespace or the end of the line), and the `f` and `fo` statements and their words
/// (corners) on those lines. A line that is not such a statement for the [`Parser`] (a
/// continued line, say) stops its chunk's reading anyway, and a chunk whose counts of
/// elements differ from what its parser read is not joined; faces and corners only size
/// its lists.
fn element_counts(chunk: &[u8]) -> ChunkCounts {
    let mut counts = ChunkCounts::default();
    // A byte order mark starts the first line of a file (which the parser skips).
    let text = chunk.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(chunk);
    for line in text.split(|&b| b == b'\n') {
        counts.lines += 1;
        counts.lone_cr |= line
            .split_last()
            .is_some_and(|(_, head)| head.contains(&b'\r'));
        let start = line.iter().position(|b| !b.is_ascii_whitespace());
        let word = start.map_or(&[][..], |s| &line[s..]);
        let ends = |rest: &[u8]| rest.first().is_none_or(u8::is_ascii_whitespace);
        match word {
            [b'v', rest @ ..] if ends(rest) => counts.elements[0] += 1,
            [b'v', b't', rest @ ..] if ends(rest) => counts.elements[1] += 1,
            [b'v', b'n', rest @ ..] if ends(rest) => counts.elements[2] += 1,
            [b'f', rest @ ..] | [b'f', b'o', rest @ ..] if ends(rest) => {
                counts.faces += 1;
                let mut inside = false;
                for &b in rest.iter().take_while(|&&b| b != b'#') {
                    let word = !b.is_ascii_whitespace();
                    counts.corners += usize::from(word && !inside);
                    inside = word;
                }
            }
            _ => {}
        }
    }
    // `split` yields a last, empty piece after the chunk's final line feed.
    if chunk.last() == Some(&b'\n') {
        counts.lines -= 1;
    }
    counts
}

/// Reads one chunk (whose first line follows line `line`) into `parser`, a parser of its
/// own; `false` with it if the chunk holds a tag, a continued line or an error (its parser
/// is then not used).
///
/// `stopped` is the least index of a chunk that stopped so far: chunk `index` gives up
/// (every [`LINES_PER_CHECK`] lines) once an earlier one has stopped, since nothing after
/// that is joined. A file with a tag in its first lines is then read by one pass, about as
/// fast as a reader without chunks, where reading every chunk to its end would cost more
/// (BENCHMARKS.md, "Reading and writing text").
fn read_chunk(
    mut parser: Parser,
    chunk: &[u8],
    line: usize,
    index: usize,
    stopped: &AtomicUsize,
) -> (Parser, bool) {
    let mut lines = PhysicalLines { rest: chunk, line };
    let mut read = 0usize;
    while let Some((no, raw)) = lines.next() {
        read += 1;
        if read.is_multiple_of(LINES_PER_CHECK) && stopped.load(Ordering::Relaxed) < index {
            return (parser, false);
        }
        let Ok((data, false)) = line_data(raw, no) else {
            stopped.fetch_min(index, Ordering::Relaxed);
            return (parser, false);
        };
        let tag = data.split_ascii_whitespace().next() == Some("t");
        if tag || parser.statement(data, no).is_err() {
            stopped.fetch_min(index, Ordering::Relaxed);
            return (parser, false);
        }
    }
    (parser, true)
}

/// Lines a chunk reads between looks at whether an earlier chunk stopped.
const LINES_PER_CHECK: usize = 1024;

/// Splits input into physical lines, numbered from 1. A line ends at `\n`, `\r\n` or a
/// `\r` not followed by `\n` (the line end of old Mac OS files), which is not part of it.
pub(crate) struct PhysicalLines<'a> {
    pub(crate) rest: &'a [u8],
    pub(crate) line: usize,
}

impl<'a> PhysicalLines<'a> {
    pub(crate) fn next(&mut self) -> Option<(usize, &'a [u8])> {
        if self.rest.is_empty() {
            return None;
        }
        let end = self.rest.iter().position(|&b| b == b'\n' || b == b'\r');
        let (mut line, rest) = match end {
            Some(i) => self.rest.split_at(i),
            None => (self.rest, &[][..]),
        };
        // The terminator: `\n`, `\r`, or `\r\n`.
        let skip = match rest {
            [b'\r', b'\n', ..] => 2,
            [] => 0,
            _ => 1,
        };
        self.rest = &rest[skip..];
        self.line += 1;
        if self.line == 1 {
            line = line.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(line);
        }
        Some((self.line, line))
    }
}

/// The text of one physical line before any `#` comment, and whether the line continues:
/// whether that text ends in a backslash (which is dropped). So `v 1 2 \ # comment`
/// continues, but a comment ending in a backslash does not.
///
/// Lines must be UTF-8 without control characters (tab, form feed and carriage return
/// are whitespace); anything else is taken as a sign of a binary file, and the message
/// is about the first byte of the line that is not text ([`first_non_text`]), so that
/// a line cut right after that byte gives the same message as the whole line (what the
/// reading in blocks of [`crate::io::input`] relies on).
pub(super) fn line_data(raw: &[u8], no: usize) -> Result<(&str, bool), String> {
    let text = match std::str::from_utf8(raw) {
        Ok(text) if !raw.iter().fold(false, |any, &b| any | is_control(b)) => text,
        // Without an early exit above (which keeps the loop from being vectorized), then
        // the first offending byte.
        _ => return Err(non_text_message(raw, no)),
    };
    let data = match text.find('#') {
        Some(i) => text.get(..i).unwrap_or(""),
        None => text,
    };
    match data
        .trim_end_matches(|c: char| c.is_ascii_whitespace())
        .strip_suffix('\\')
    {
        Some(head) => Ok((head, true)),
        None => Ok((data, false)),
    }
}

/// Whether `b` is a control character that text lines may not hold (all but tab, line
/// feed, form feed and carriage return, which are whitespace or line ends), or DEL.
fn is_control(b: u8) -> bool {
    (b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\x0c' | b'\r')) || b == 0x7f
}

/// The position of the first byte of `bytes` that is not text: a control character
/// ([`is_control`]) or the first byte of a sequence that is not UTF-8; `Err(at)` when
/// everything is text but a UTF-8 sequence that `bytes` cuts off at `at` (the rest may
/// come later).
pub(crate) fn first_non_text(bytes: &[u8]) -> Result<Option<usize>, usize> {
    let (valid, utf8) = match std::str::from_utf8(bytes) {
        Ok(_) => (bytes.len(), None),
        Err(e) => (e.valid_up_to(), Some(e)),
    };
    // Control characters are ASCII, so they cannot be inside a UTF-8 sequence. First
    // whether there is one, without an early exit (so that the loop is vectorized).
    let text = &bytes[..valid];
    if text.iter().fold(false, |any, &b| any | is_control(b)) {
        if let Some(at) = text.iter().position(|&b| is_control(b)) {
            return Ok(Some(at));
        }
    }
    match utf8 {
        None => Ok(None),
        Some(e) if e.error_len().is_none() => Err(valid),
        Some(_) => Ok(Some(valid)),
    }
}

/// The message of a line that is not text, about its first byte that is not
/// ([`first_non_text`]; a sequence cut off at the end of the line is not UTF-8 either).
pub(crate) fn non_text_message(raw: &[u8], no: usize) -> String {
    let at = match first_non_text(raw) {
        Ok(Some(at)) => at,
        Ok(None) => return format!("line {no} is not valid UTF-8"),
        Err(at) => at,
    };
    match raw.get(at) {
        Some(&b) if is_control(b) => {
            format!("line {no} contains the control character 0x{b:02x} (is this a binary file?)")
        }
        _ => format!("line {no} is not valid UTF-8"),
    }
}

/// Longest statement keyword taken for one.
const MAX_KEYWORD: usize = 32;

/// Whether `kw` looks like an OBJ statement keyword (`usemtl`, `c_interp`, ...): a letter,
/// then letters, digits or `_`, at most [`MAX_KEYWORD`] bytes.
fn is_keyword(kw: &str) -> bool {
    let b = kw.as_bytes();
    b.len() <= MAX_KEYWORD
        && b.first().is_some_and(u8::is_ascii_alphabetic)
        && b.iter().all(|&c| c.is_ascii_alphanumeric() || c == b'_')
}

/// An OBJ face index as written: 1-based positive or relative negative. `None` inside
/// means the digits overflow `u64`.
#[derive(Clone, Copy)]
enum RawIndex {
    Pos(Option<u64>),
    Neg(Option<u64>),
}

/// Decimal digits to `u64`: `None` if `s` is not all digits (or empty), `Some(None)` on
/// overflow.
fn parse_digits(s: &[u8]) -> Option<Option<u64>> {
    if s.is_empty() || !s.iter().all(u8::is_ascii_digit) {
        return None;
    }
    let mut n: Option<u64> = Some(0);
    for &d in s {
        n = n
            .and_then(|n| n.checked_mul(10))
            .and_then(|n| n.checked_add(u64::from(d - b'0')));
    }
    Some(n)
}

/// `[+-]digits`.
fn parse_index(s: &str) -> Option<RawIndex> {
    match s.as_bytes().split_first() {
        Some((b'-', digits)) => parse_digits(digits).map(RawIndex::Neg),
        Some((b'+', digits)) => parse_digits(digits).map(RawIndex::Pos),
        _ => parse_digits(s.as_bytes()).map(RawIndex::Pos),
    }
}

/// Stored in place of an index that cannot be valid (it does not fit in `u32`); the check
/// at the end of the file reports it.
const INVALID: u32 = u32::MAX;

/// References to elements that did not exist yet when they were read (forward references
/// of faces, tag indices), checked when the whole file is known.
///
/// Only references greater than all earlier ones are kept: the first reference that turns
/// out to be out of range is always one of them, so the list stays short (usually empty).
#[derive(Default)]
struct Deferred {
    /// (0-based index, or `u64::MAX` when it overflows; line; statement).
    refs: Vec<(u64, usize, &'static str)>,
    /// The text of the first overflowing index, for the message.
    overflow_text: Option<String>,
}

impl Deferred {
    fn note(&mut self, index: Option<u64>, text: &str, line: usize, what: &'static str) {
        let index = index.unwrap_or(u64::MAX);
        if index == u64::MAX && self.overflow_text.is_none() {
            self.overflow_text = Some(text.to_owned());
        }
        let greater = match self.refs.last() {
            Some(&(last, _, _)) => index > last,
            None => true,
        };
        if greater {
            self.refs.push((index, line, what));
        }
    }

    /// Appends the references noted after these, keeping those greater than all earlier
    /// ones, as [`Deferred::note`] would have.
    fn append(&mut self, next: Deferred) {
        for r in next.refs {
            if self.refs.last().is_none_or(|last| r.0 > last.0) {
                self.refs.push(r);
            }
        }
        if self.overflow_text.is_none() {
            self.overflow_text = next.overflow_text;
        }
    }

    /// The first reference (in file order) that is out of range for `count` elements:
    /// (index as written, with `base` added; line; statement).
    fn first_out_of_range(&self, count: usize, base: u64) -> Option<(String, usize, &'static str)> {
        let &(index, line, what) = self.refs.iter().find(|r| r.0 >= count as u64)?;
        let shown = match (index, &self.overflow_text) {
            (u64::MAX, Some(text)) => text.clone(),
            _ => index.saturating_add(base).to_string(),
        };
        Some((shown, line, what))
    }
}

/// Per-corner `vt` or `vn` indices, kept only while every corner has one, and the first
/// face (by line) whose corners have none and have some.
struct CornerIndices {
    all: bool,
    indices: Vec<u32>,
    first_without: Option<usize>,
    first_with: Option<usize>,
}

impl Default for CornerIndices {
    fn default() -> Self {
        Self {
            all: true,
            indices: Vec::new(),
            first_without: None,
            first_with: None,
        }
    }
}

impl CornerIndices {
    fn push(&mut self, index: Option<u32>, line: usize) {
        match index {
            Some(_) => {
                self.first_with.get_or_insert(line);
            }
            None => {
                self.first_without.get_or_insert(line);
            }
        }
        if self.all {
            match index {
                Some(i) => self.indices.push(i),
                None => {
                    self.all = false;
                    self.indices = Vec::new();
                }
            }
        }
    }

    /// Appends the indices of the corners read after these.
    fn append(&mut self, next: CornerIndices) {
        self.first_with = self.first_with.or(next.first_with);
        self.first_without = self.first_without.or(next.first_without);
        if !next.all {
            self.all = false;
            self.indices = Vec::new();
        } else if self.all {
            self.indices.extend_from_slice(&next.indices);
        }
    }

    /// When some corners have indices and some have none: the line of the first face of
    /// the second kind.
    fn mixed(&self) -> Option<usize> {
        Some(self.first_with?.max(self.first_without?))
    }

    fn finish(self, corners: usize) -> Option<Vec<u32>> {
        (self.all && corners > 0).then_some(self.indices)
    }
}

/// Everything read so far.
struct Parser {
    /// Vertices, texture coordinates and normals defined before the first line read by
    /// this parser (not 0 only for the chunks of [`parallel_prefix`], which read no tags).
    base: Counts,
    positions: Vec<[f64; 3]>,
    texcoords: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    face_offsets: Vec<u32>,
    face_verts: Vec<u32>,
    face_lines: Vec<u32>,
    face_texcoords: CornerIndices,
    face_normals: CornerIndices,
    forward_vertices: Deferred,
    forward_texcoords: Deferred,
    forward_normals: Deferred,
    tag_vertices: Deferred,
    tag_faces: Deferred,
    tags: Tags,
    options: FileOptions,
    unsupported_tags: Vec<UnsupportedTag>,
    /// `t interval`, `t sideinterval`, `t weight`, and the line of each entry.
    knots: KnotTags,
    knot_lines: KnotLines,
    /// `t facevaryingpropagatecorners 1/0/0 1`: Hbr's flag, which with its "edge and
    /// corner" mode (`corners-plus1`) makes OpenSubdiv's `corners-plus2`.
    propagate_corners: bool,
    /// The `o`, `g` and `usemtl` statements in order: the faces read before each (by this
    /// parser), which, and its text.
    group_events: Vec<(u32, GroupKind, String)>,
    /// The text of the `mtllib` statements.
    material_libraries: Vec<String>,
    /// `s` statements other than `s off` and `s 0`.
    smoothing: usize,
}

/// The statements that set a face's [`GroupState`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum GroupKind {
    Object,
    Group,
    Material,
}

/// Source lines of the [`KnotTags`] entries, list by list.
#[derive(Default)]
struct KnotLines {
    intervals: Vec<usize>,
    side_intervals: Vec<usize>,
    weights: Vec<usize>,
}

impl Default for Parser {
    fn default() -> Self {
        Self {
            base: [0; 3],
            positions: Vec::new(),
            texcoords: Vec::new(),
            normals: Vec::new(),
            face_offsets: vec![0],
            face_verts: Vec::new(),
            face_lines: Vec::new(),
            face_texcoords: CornerIndices::default(),
            face_normals: CornerIndices::default(),
            forward_vertices: Deferred::default(),
            forward_texcoords: Deferred::default(),
            forward_normals: Deferred::default(),
            tag_vertices: Deferred::default(),
            tag_faces: Deferred::default(),
            tags: Tags::default(),
            options: FileOptions::default(),
            unsupported_tags: Vec::new(),
            knots: KnotTags::default(),
            knot_lines: KnotLines::default(),
            propagate_corners: false,
            group_events: Vec::new(),
            material_libraries: Vec::new(),
            smoothing: 0,
        }
    }
}

/// A knot interval: a finite `f64` ≥ 0.
fn knot_interval(tok: &str, name: &str) -> Result<f64, String> {
    match tok.parse::<f64>() {
        Ok(d) if d.is_finite() && d >= 0.0 => Ok(d),
        _ => Err(format!(
            "t {name}: knot interval '{tok}' must be a finite number ≥ 0"
        )),
    }
}

/// The message of a knot tag that does not fit the mesh, for its line.
fn knot_message(e: &KnotTagError) -> String {
    match e {
        KnotTagError::UnknownEdge { what, v0, v1, .. } => format!(
            "t {}: the mesh has no edge between vertices {v0} and {v1}",
            what.replace(' ', "")
        ),
        KnotTagError::EdgeNotInFace { face, v0, v1, .. } => {
            format!("t sideinterval: face {face} has no edge between vertices {v0} and {v1}")
        }
        other => format!("t {}: {other}", other.entry().0.replace(' ', "")),
    }
}

/// Up to `N` numbers (checked finite) followed by `extra` more that are parsed and
/// ignored; returns the values and how many numbers there were.
fn parse_numbers<const N: usize>(
    toks: SplitAsciiWhitespace<'_>,
    kw: &str,
    what: &str,
) -> Result<([f64; N], usize), String> {
    let mut out = [0.0; N];
    let mut n = 0usize;
    for tok in toks {
        let x: f64 = tok
            .parse()
            .map_err(|_| format!("{kw}: '{tok}' is not a number"))?;
        if let Some(slot) = out.get_mut(n) {
            if !x.is_finite() {
                return Err(format!("{kw}: non-finite {what} '{tok}'"));
            }
            *slot = x;
        }
        n += 1;
    }
    Ok((out, n))
}

/// Appends to an element list whose indices must fit in `u32`.
fn push_element(list: &mut Vec<[f64; 3]>, x: [f64; 3], what: &str) -> Result<(), String> {
    if list.len() >= INVALID as usize {
        return Err(format!("too many {what} for 32-bit indices"));
    }
    list.push(x);
    Ok(())
}

/// Resolves one face index against the `count` elements defined so far; positive indices
/// beyond them are noted in `deferred` for the end-of-file check.
fn resolve(
    raw: RawIndex,
    text: &str,
    count: usize,
    line: usize,
    deferred: &mut Deferred,
    noun: &str,
    plural: &str,
) -> Result<u32, String> {
    match raw {
        RawIndex::Pos(Some(0)) | RawIndex::Neg(Some(0)) => Err(format!(
            "f: {noun} index {text} is invalid: OBJ indices start at 1"
        )),
        RawIndex::Pos(Some(n)) => {
            let i = n - 1;
            if i >= count as u64 {
                deferred.note(Some(i), text, line, "f");
            }
            Ok(u32::try_from(i).unwrap_or(INVALID))
        }
        RawIndex::Pos(None) => {
            deferred.note(None, text, line, "f");
            Ok(INVALID)
        }
        RawIndex::Neg(Some(k)) if k <= count as u64 => {
            // `count` fits in u32 (see `push_element`), so this does too.
            Ok(u32::try_from(count as u64 - k).unwrap_or(INVALID))
        }
        RawIndex::Neg(_) => Err(format!(
            "f: relative {noun} index {text} is out of range: only {count} {plural} are \
             defined above this line"
        )),
    }
}

/// A tag line's name, its counts `ni/nf/ns` as written and read, and its line.
struct Tag<'a> {
    name: &'static str,
    counts: &'a str,
    ni: usize,
    nf: usize,
    ns: usize,
    line: usize,
}

impl Tag<'_> {
    /// The message for counts other than `expected`.
    fn bad_counts(&self, expected: &str) -> String {
        format!(
            "t {}: unexpected counts {} (expected {expected})",
            self.name, self.counts
        )
    }
}

/// Parses a non-negative 0-based tag index; indices not (yet) in range are deferred.
fn tag_index(
    tok: &str,
    name: &'static str,
    count: usize,
    line: usize,
    deferred: &mut Deferred,
) -> Result<u32, String> {
    match parse_index(tok) {
        Some(RawIndex::Neg(_)) => Err(format!("t {name}: negative index {tok}")),
        Some(RawIndex::Pos(Some(i))) => {
            if i >= count as u64 {
                deferred.note(Some(i), tok, line, name);
            }
            Ok(u32::try_from(i).unwrap_or(INVALID))
        }
        Some(RawIndex::Pos(None)) => {
            deferred.note(None, tok, line, name);
            Ok(INVALID)
        }
        None => Err(format!("t {name}: '{tok}' is not an integer index")),
    }
}

/// A crease or corner sharpness: an `f32` ≥ 0 (infinity allowed: infinitely sharp).
fn sharpness(tok: &str, name: &str) -> Result<f32, String> {
    let s: f32 = tok
        .parse()
        .map_err(|_| format!("t {name}: sharpness '{tok}' is not a number"))?;
    if s.is_nan() || s < 0.0 {
        return Err(format!(
            "t {name}: sharpness must be a number ≥ 0 (≥ 10 is infinitely sharp), found '{tok}'"
        ));
    }
    Ok(s)
}

/// `ni/nf/ns`.
fn parse_counts(tok: &str) -> Option<(usize, usize, usize)> {
    let mut it = tok.split('/');
    let mut next = || -> Option<usize> {
        let s = it.next()?;
        // Counts too large for memory are kept as usize::MAX: the line cannot hold that many
        // values, which the caller reports.
        let n = parse_digits(s.as_bytes())?.unwrap_or(u64::MAX);
        Some(usize::try_from(n).unwrap_or(usize::MAX))
    };
    let counts = (next()?, next()?, next()?);
    if it.next().is_some() {
        return None;
    }
    Some(counts)
}

impl Parser {
    /// A parser for the lines after `base` elements, its lists allocated for `counts`.
    fn with_capacity(base: Counts, counts: ChunkCounts) -> Parser {
        let [v, t, n] = counts.elements;
        let mut face_offsets = Vec::with_capacity(counts.faces + 1);
        face_offsets.push(0);
        Parser {
            base,
            positions: Vec::with_capacity(v),
            texcoords: Vec::with_capacity(t),
            normals: Vec::with_capacity(n),
            face_offsets,
            face_verts: Vec::with_capacity(counts.corners),
            face_lines: Vec::with_capacity(counts.faces),
            ..Parser::default()
        }
    }

    /// Vertices, texture coordinates and normals defined up to here.
    fn counts(&self) -> Counts {
        let [v, t, n] = self.base;
        [
            v + self.positions.len(),
            t + self.texcoords.len(),
            n + self.normals.len(),
        ]
    }

    /// Appends what `next` read (the lines after this parser's, from where its `base`
    /// says, without tags): `None` if the lists would outgrow 32-bit indices.
    fn append(&mut self, next: Parser) -> Option<()> {
        let corners = u32::try_from(self.face_verts.len()).ok()?;
        let total = |a: usize, b: usize| (a + b < INVALID as usize).then_some(());
        total(self.positions.len(), next.positions.len())?;
        total(self.texcoords.len(), next.texcoords.len())?;
        total(self.normals.len(), next.normals.len())?;
        total(self.face_verts.len(), next.face_verts.len())?;
        self.positions.extend_from_slice(&next.positions);
        self.texcoords.extend_from_slice(&next.texcoords);
        self.normals.extend_from_slice(&next.normals);
        (self.face_offsets).extend(next.face_offsets[1..].iter().map(|&o| o + corners));
        self.face_verts.extend_from_slice(&next.face_verts);
        self.face_lines.extend_from_slice(&next.face_lines);
        self.face_texcoords.append(next.face_texcoords);
        self.face_normals.append(next.face_normals);
        self.forward_vertices.append(next.forward_vertices);
        self.forward_texcoords.append(next.forward_texcoords);
        self.forward_normals.append(next.forward_normals);
        let faces = self.face_lines.len() as u32 - next.face_lines.len() as u32;
        (self.group_events).extend(
            next.group_events
                .into_iter()
                .map(|(f, k, t)| (f + faces, k, t)),
        );
        (self.material_libraries).extend(next.material_libraries);
        self.smoothing += next.smoothing;
        Some(())
    }

    /// One logical line without its comment.
    fn statement(&mut self, data: &str, line: usize) -> Result<(), String> {
        let mut toks = data.split_ascii_whitespace();
        let Some(kw) = toks.next() else { return Ok(()) };
        match kw {
            "v" => self.vertex(toks),
            "vt" => self.texcoord(toks),
            "vn" => self.normal(toks),
            "f" | "fo" => self.face(toks, line),
            "t" => self.tag(toks, line),
            "o" | "g" | "usemtl" => {
                let kind = match kw {
                    "o" => GroupKind::Object,
                    "g" => GroupKind::Group,
                    _ => GroupKind::Material,
                };
                let faces = self.face_lines.len() as u32;
                (self.group_events).push((faces, kind, toks.collect::<Vec<_>>().join(" ")));
                Ok(())
            }
            "mtllib" => {
                (self.material_libraries).push(toks.collect::<Vec<_>>().join(" "));
                Ok(())
            }
            "s" => {
                let on = !matches!(toks.next(), None | Some("off" | "0"));
                self.smoothing += usize::from(on);
                Ok(())
            }
            // Everything else (l, p, vp, cstype, deg, curv, surf, parm, end, ... and unknown
            // statements) carries nothing we use; but a line that does not even start with
            // a keyword means this is not an OBJ file.
            _ if is_keyword(kw) => Ok(()),
            _ => {
                let shown: String = kw.chars().take(MAX_KEYWORD).collect();
                let more = if shown.len() < kw.len() { "..." } else { "" };
                Err(format!(
                    "'{shown}{more}' is not an OBJ statement (is this an OBJ file?)"
                ))
            }
        }
    }

    fn vertex(&mut self, toks: SplitAsciiWhitespace<'_>) -> Result<(), String> {
        let (p, n) = parse_numbers::<3>(toks, "v", "coordinate")?;
        if let Some(c) = p.iter().find(|c| c.abs() >= crate::mesh::MAX_COORDINATE) {
            return Err(format!(
                "v: the coordinate {c:e} is too large; coordinates must be below 1e75 in magnitude"
            ));
        }
        match n {
            // x y z, x y z w, x y z r g b, x y z r g b a
            3 | 4 | 6 | 7 => push_element(&mut self.positions, p, "vertices"),
            0..=2 => Err(format!("v: a vertex needs 3 coordinates (x y z), found {n}")),
            _ => Err(format!(
                "v: expected x y z, optionally followed by w or a colour r g b [a]; found {n} numbers"
            )),
        }
    }

    fn texcoord(&mut self, toks: SplitAsciiWhitespace<'_>) -> Result<(), String> {
        let (t, n) = parse_numbers::<3>(toks, "vt", "texture coordinate")?;
        match n {
            1..=3 => push_element(&mut self.texcoords, t, "texture coordinates"),
            0 => Err("vt: a texture coordinate needs at least 1 number (u [v [w]])".into()),
            _ => Err(format!("vt: expected u [v [w]], found {n} numbers")),
        }
    }

    fn normal(&mut self, toks: SplitAsciiWhitespace<'_>) -> Result<(), String> {
        let (v, n) = parse_numbers::<3>(toks, "vn", "normal component")?;
        match n {
            3 => push_element(&mut self.normals, v, "normals"),
            _ => Err(format!("vn: a normal needs 3 numbers (x y z), found {n}")),
        }
    }

    fn face(&mut self, toks: SplitAsciiWhitespace<'_>, line: usize) -> Result<(), String> {
        let start = self.face_verts.len();
        let [nv, nt, nn] = self.counts();
        for tok in toks {
            let malformed = || {
                format!(
                    "f: malformed vertex reference '{tok}' (expected v, v/vt, v//vn or v/vt/vn)"
                )
            };
            let mut parts = tok.split('/');
            let v = parts.next().unwrap_or("");
            let t = parts.next();
            let n = parts.next();
            if parts.next().is_some() {
                return Err(malformed());
            }
            let t = match (t, n) {
                (Some(""), Some(_)) | (None, _) => None, // v//vn, v
                (Some(t), _) => Some(t),
            };
            let vi = parse_index(v).ok_or_else(malformed)?;
            let vi = resolve(
                vi,
                v,
                nv,
                line,
                &mut self.forward_vertices,
                "vertex",
                "vertices",
            )?;
            self.face_verts.push(vi);
            let ti = match t {
                None => None,
                Some(t) => {
                    let raw = parse_index(t).ok_or_else(malformed)?;
                    let noun = "texture coordinate";
                    let plural = "texture coordinates";
                    Some(resolve(
                        raw,
                        t,
                        nt,
                        line,
                        &mut self.forward_texcoords,
                        noun,
                        plural,
                    )?)
                }
            };
            self.face_texcoords.push(ti, line);
            let ni = match n {
                None => None,
                Some(n) => {
                    let raw = parse_index(n).ok_or_else(malformed)?;
                    let fwd = &mut self.forward_normals;
                    Some(resolve(raw, n, nn, line, fwd, "normal", "normals")?)
                }
            };
            self.face_normals.push(ni, line);
        }
        let face = self.face_verts.get(start..).unwrap_or(&[]);
        if face.len() < 3 {
            return Err(format!(
                "f: face has {} vertices; a face needs at least 3",
                face.len()
            ));
        }
        if face.len() > usize::from(u16::MAX) {
            return Err(format!(
                "f: face has {} vertices; a face may have at most {}",
                face.len(),
                u16::MAX
            ));
        }
        // A face may repeat a vertex (a degenerate face); the mesh layer accepts it as
        // OpenSubdiv does and reports it as a warning.
        let end = u32::try_from(self.face_verts.len())
            .map_err(|_| "too many face corners for 32-bit indices".to_string())?;
        self.face_offsets.push(end);
        self.face_lines
            .push(u32::try_from(line).unwrap_or(u32::MAX));
        Ok(())
    }

    fn tag(&mut self, mut toks: SplitAsciiWhitespace<'_>, line: usize) -> Result<(), String> {
        let Some(name) = toks.next() else {
            return Err("t: missing tag name".into());
        };
        let name: &'static str = match name {
            "crease" => "crease",
            "corner" => "corner",
            "hole" => "hole",
            "interpolateboundary" => "interpolateboundary",
            "creasemethod" => "creasemethod",
            "smoothtriangles" => "smoothtriangles",
            "facevaryinginterpolateboundary" => "facevaryinginterpolateboundary",
            "facevaryingpropagatecorners" => "facevaryingpropagatecorners",
            "interval" => "interval",
            "sideinterval" => "sideinterval",
            "weight" => "weight",
            _ => {
                self.unsupported_tags.push(UnsupportedTag {
                    line,
                    name: name.to_owned(),
                });
                return Ok(());
            }
        };
        let counts = toks
            .next()
            .ok_or_else(|| format!("t {name}: missing counts ni/nf/ns"))?;
        let (ni, nf, ns) = parse_counts(counts).ok_or_else(|| {
            format!("t {name}: malformed counts '{counts}' (expected ni/nf/ns, three integers ≥ 0)")
        })?;
        let found = toks.clone().count();
        let needed = ni.checked_add(nf).and_then(|n| n.checked_add(ns));
        if needed != Some(found) {
            let needed = needed.map_or_else(|| "too many".to_string(), |n| n.to_string());
            return Err(format!(
                "t {name}: counts {counts} call for {needed} values, but the line has {found}"
            ));
        }
        let tag = Tag {
            name,
            counts,
            ni,
            nf,
            ns,
            line,
        };
        match name {
            "crease" => self.tag_crease(toks, &tag),
            "corner" => self.tag_corner(toks, &tag),
            "hole" => self.tag_hole(toks, &tag),
            "interval" | "sideinterval" => self.tag_interval(toks, &tag),
            "weight" => self.tag_weight(toks, &tag),
            _ => self.tag_option(toks, &tag),
        }
    }

    /// The scheme option tags (`interpolateboundary`, `facevaryinginterpolateboundary`,
    /// `facevaryingpropagatecorners`, `creasemethod`, `smoothtriangles`): one value each,
    /// stored in the file's options.
    fn tag_option(&mut self, toks: SplitAsciiWhitespace<'_>, tag: &Tag) -> Result<(), String> {
        let name = tag.name;
        match name {
            "interpolateboundary" => {
                let tok = Self::option_token(toks, tag, (1, 0, 0))?;
                let value: i64 = tok
                    .parse()
                    .map_err(|_| format!("t {name}: '{tok}' is not an integer"))?;
                let mode = BoundaryInterpolation::from_tag_value(value).ok_or_else(|| {
                    format!(
                        "t {name}: unknown value {value} (expected 0 none, 1 edge-and-corner \
                         or 2 edge-only)"
                    )
                })?;
                self.options.boundary = Some(mode);
                Ok(())
            }
            "facevaryinginterpolateboundary" => {
                let tok = Self::option_token(toks, tag, (1, 0, 0))?;
                let value: i64 = tok
                    .parse()
                    .map_err(|_| format!("t {name}: '{tok}' is not an integer"))?;
                let mode = FaceVaryingInterpolation::from_tag_value(value).ok_or_else(|| {
                    format!(
                        "t {name}: unknown value {value} (expected 0 none, 1 corners-only, \
                         2 corners-plus1, 3 corners-plus2, 4 boundaries or 5 all)"
                    )
                })?;
                self.options.face_varying = Some(mode);
                Ok(())
            }
            "facevaryingpropagatecorners" => {
                let tok = Self::option_token(toks, tag, (1, 0, 0))?;
                self.propagate_corners = match tok {
                    "0" => false,
                    "1" => true,
                    _ => return Err(format!("t {name}: '{tok}' is not 0 or 1")),
                };
                Ok(())
            }
            "creasemethod" => {
                let tok = Self::option_token(toks, tag, (0, 0, 1))?;
                let method: CreaseMethod = tok.parse().map_err(|e| format!("t {name}: {e}"))?;
                self.options.crease_method = Some(method);
                Ok(())
            }
            _ => {
                // smoothtriangles
                let tok = Self::option_token(toks, tag, (0, 0, 1))?;
                let rule: TriangleSubdivision =
                    tok.parse().map_err(|e| format!("t {name}: {e}"))?;
                self.options.triangles = Some(rule);
                Ok(())
            }
        }
    }

    /// The vertices of a crease or corner tag, and the sharpness of each: one for all
    /// (`nf` 1), one each (`nf` = `each`), or infinitely sharp (`nf` 0).
    fn sharp_vertices(
        &mut self,
        mut toks: SplitAsciiWhitespace<'_>,
        tag: &Tag,
        each: usize,
    ) -> Result<Vec<(u32, f32)>, String> {
        let nv = self.positions.len();
        let verts = (&mut toks)
            .take(tag.ni)
            .map(|t| tag_index(t, tag.name, nv, tag.line, &mut self.tag_vertices))
            .collect::<Result<Vec<u32>, String>>()?;
        let weights = (&mut toks)
            .take(tag.nf)
            .map(|t| sharpness(t, tag.name))
            .collect::<Result<Vec<f32>, String>>()?;
        let s = |i: usize| match tag.nf {
            0 => SHARPNESS_INFINITE,
            1 => weights.first().copied().unwrap_or(SHARPNESS_INFINITE),
            _ if tag.nf == each => weights.get(i).copied().unwrap_or(SHARPNESS_INFINITE),
            _ => SHARPNESS_INFINITE,
        };
        Ok(verts.iter().enumerate().map(|(i, &v)| (v, s(i))).collect())
    }

    /// `t crease N/nf/0 v…`: a chain of N vertices, sharpness for all or per edge.
    fn tag_crease(&mut self, toks: SplitAsciiWhitespace<'_>, tag: &Tag) -> Result<(), String> {
        let (ni, nf, ns) = (tag.ni, tag.nf, tag.ns);
        if ni < 2 || ns != 0 || !(nf == 0 || nf == 1 || nf == ni - 1) {
            return Err(tag.bad_counts(
                "2/1/0 for one edge, or N/1/0, N/(N-1)/0 or N/0/0 for a chain of N vertices",
            ));
        }
        let verts = self.sharp_vertices(toks, tag, ni - 1)?;
        for pair in verts.windows(2) {
            if let [(v0, sharpness), (v1, _)] = *pair {
                self.tags.creases.push(Crease { v0, v1, sharpness });
            }
        }
        Ok(())
    }

    /// `t corner N/nf/0 v…`: N vertices, sharpness for all or each.
    fn tag_corner(&mut self, toks: SplitAsciiWhitespace<'_>, tag: &Tag) -> Result<(), String> {
        let (ni, nf, ns) = (tag.ni, tag.nf, tag.ns);
        if ni < 1 || ns != 0 || !(nf == 0 || nf == 1 || nf == ni) {
            return Err(tag.bad_counts("1/1/0, or N/1/0, N/N/0 or N/0/0 for N vertices"));
        }
        for (vertex, sharpness) in self.sharp_vertices(toks, tag, ni)? {
            self.tags.corners.push(Corner { vertex, sharpness });
        }
        Ok(())
    }

    /// `t hole N/0/0 f…`: N faces.
    fn tag_hole(&mut self, toks: SplitAsciiWhitespace<'_>, tag: &Tag) -> Result<(), String> {
        if tag.nf != 0 || tag.ns != 0 {
            return Err(tag.bad_counts("N/0/0 for N faces"));
        }
        let nfaces = self.face_lines.len();
        for t in toks {
            let f = tag_index(t, tag.name, nfaces, tag.line, &mut self.tag_faces)?;
            self.tags.holes.push(f);
        }
        Ok(())
    }

    /// `t interval 2/1/0 v0 v1 d` and `t sideinterval 3/1/0 f v0 v1 d`: knot intervals.
    fn tag_interval(
        &mut self,
        mut toks: SplitAsciiWhitespace<'_>,
        tag: &Tag,
    ) -> Result<(), String> {
        let name = tag.name;
        let side = name == "sideinterval";
        let ni_expected = if side { 3 } else { 2 };
        if (tag.ni, tag.nf, tag.ns) != (ni_expected, 1, 0) {
            return Err(tag.bad_counts(if side {
                "3/1/0: face, two vertices, interval"
            } else {
                "2/1/0: two vertices, interval"
            }));
        }
        let face = if side {
            let nfaces = self.face_lines.len();
            let tok = toks.next().unwrap_or("");
            Some(tag_index(tok, name, nfaces, tag.line, &mut self.tag_faces)?)
        } else {
            None
        };
        let nv = self.positions.len();
        let mut vert = || {
            let tok = toks.next().unwrap_or("");
            tag_index(tok, name, nv, tag.line, &mut self.tag_vertices)
        };
        let (v0, v1) = (vert()?, vert()?);
        if v0 == v1 {
            return Err(format!(
                "t {name}: an edge needs two different vertices, found {v0} twice"
            ));
        }
        let interval = knot_interval(toks.next().unwrap_or(""), name)?;
        match face {
            Some(face) => {
                self.knots.side_intervals.push(SideInterval {
                    face,
                    v0,
                    v1,
                    interval,
                });
                self.knot_lines.side_intervals.push(tag.line);
            }
            None => {
                self.knots.intervals.push(EdgeInterval { v0, v1, interval });
                self.knot_lines.intervals.push(tag.line);
            }
        }
        Ok(())
    }

    /// `t weight 1/1/0 v w`: a rational weight.
    fn tag_weight(&mut self, mut toks: SplitAsciiWhitespace<'_>, tag: &Tag) -> Result<(), String> {
        if (tag.ni, tag.nf, tag.ns) != (1, 1, 0) {
            return Err(tag.bad_counts("1/1/0: vertex, weight"));
        }
        let nv = self.positions.len();
        let tok = toks.next().unwrap_or("");
        let vertex = tag_index(tok, tag.name, nv, tag.line, &mut self.tag_vertices)?;
        let tok = toks.next().unwrap_or("");
        let weight = match tok.parse::<f64>() {
            Ok(w) if w.is_finite() && w > 0.0 => w,
            _ => {
                return Err(format!(
                    "t weight: rational weight '{tok}' must be a finite number > 0"
                ))
            }
        };
        self.knots.weights.push(VertexWeight { vertex, weight });
        self.knot_lines.weights.push(tag.line);
        Ok(())
    }

    /// The one value of an option tag with counts `expected`.
    fn option_token<'a>(
        mut toks: SplitAsciiWhitespace<'a>,
        tag: &Tag,
        expected: (usize, usize, usize),
    ) -> Result<&'a str, String> {
        if (tag.ni, tag.nf, tag.ns) != expected {
            let (ni, nf, ns) = expected;
            return Err(tag.bad_counts(&format!("{ni}/{nf}/{ns}")));
        }
        Ok(toks.next().unwrap_or(""))
    }

    /// The problem on the earliest line among the indices that point past what the file
    /// has (faces' vertices, texture coordinates and normals; tags' vertices and faces) and
    /// faces that mix corners with and without texture coordinates: its line and message.
    fn first_index_problem(&self) -> Option<(usize, String)> {
        let (nv, nt, nn) = (
            self.positions.len(),
            self.texcoords.len(),
            self.normals.len(),
        );
        let nf = self.face_lines.len();
        let mut problems: Vec<(usize, String)> = Vec::new();
        if let Some((i, line, _)) = self.forward_vertices.first_out_of_range(nv, 1) {
            problems.push((
                line,
                format!("f: vertex index {i} is out of range: the file has {nv} vertices"),
            ));
        }
        if let Some((i, line, _)) = self.forward_texcoords.first_out_of_range(nt, 1) {
            problems.push((
                line,
                format!("f: texture coordinate index {i} is out of range: the file has {nt} texture coordinates (vt)"),
            ));
        }
        if let Some((i, line, _)) = self.forward_normals.first_out_of_range(nn, 1) {
            problems.push((
                line,
                format!("f: normal index {i} is out of range: the file has {nn} normals (vn)"),
            ));
        }
        if let Some((i, line, what)) = self.tag_vertices.first_out_of_range(nv, 0) {
            problems.push((
                line,
                format!("t {what}: vertex index {i} is out of range: the file has {nv} vertices (tag indices are 0-based)"),
            ));
        }
        if let Some((i, line, what)) = self.tag_faces.first_out_of_range(nf, 0) {
            problems.push((
                line,
                format!("t {what}: face index {i} is out of range: the file has {nf} faces (tag indices are 0-based)"),
            ));
        }
        if let Some(line) = self.face_texcoords.mixed() {
            problems.push((
                line,
                "f: some faces have texture coordinates (v/vt) and some have none; give every \
                 corner of every face a vt index, or none"
                    .into(),
            ));
        }
        problems.into_iter().min_by_key(|p| p.0)
    }

    /// The checks that need the whole file, then the mesh.
    fn finish(self, source_name: &str) -> Result<ObjFile, ObjError> {
        let err = |line: Option<usize>, message: String| ObjError {
            source_name: source_name.to_owned(),
            line,
            message,
        };
        if let Some((line, message)) = self.first_index_problem() {
            return Err(err(Some(line), message));
        }
        let mut options = self.options;
        if self.propagate_corners
            && options.face_varying == Some(FaceVaryingInterpolation::CornersPlus1)
        {
            options.face_varying = Some(FaceVaryingInterpolation::CornersPlus2);
        }

        let corners = self.face_verts.len();
        let face_lines = self.face_lines;
        let mut mesh =
            PolyMesh::new(self.positions, self.face_offsets, self.face_verts).map_err(|e| {
                let line = match e {
                    MeshError::FaceTooSmall { face, .. }
                    | MeshError::VertexOutOfRange { face, .. }
                    | MeshError::RepeatedVertex { face, .. } => {
                        face_lines.get(face).map(|&l| l as usize)
                    }
                    _ => None,
                };
                err(line, e.to_string())
            })?;
        mesh.tags = self.tags;
        mesh.knots = self.knots;
        mesh.groups = face_groups(
            &self.group_events,
            mesh.num_faces(),
            self.material_libraries,
        );
        let face_texcoords = self.face_texcoords.finish(corners);
        if let Some(indices) = &face_texcoords {
            let uv = uv_channel(&self.texcoords, indices.clone());
            mesh.face_varying
                .push(uv.map_err(|e| err(None, e.to_string()))?);
        }
        if let Err(e) = mesh.knots.validate(&mesh) {
            let (list, index) = e.entry();
            let lines = match list {
                "interval" => &self.knot_lines.intervals,
                "side interval" => &self.knot_lines.side_intervals,
                _ => &self.knot_lines.weights,
            };
            return Err(err(lines.get(index).copied(), knot_message(&e)));
        }
        Ok(ObjFile {
            mesh,
            texcoords: self.texcoords,
            normals: self.normals,
            face_texcoords,
            face_normals: self.face_normals.finish(corners),
            face_lines,
            options,
            unsupported_tags: self.unsupported_tags,
            smoothing_groups: self.smoothing,
        })
    }
}

/// The [`FaceGroups`] of `faces` faces from the `o`, `g` and `usemtl` statements `events`
/// (each applies to the faces from the count it holds on), with the `mtllib` texts
/// `libraries`; no face states when every face is in the state before any statement.
fn face_groups(
    events: &[(u32, GroupKind, String)],
    faces: usize,
    libraries: Vec<String>,
) -> FaceGroups {
    let mut groups = FaceGroups {
        material_libraries: libraries,
        ..FaceGroups::default()
    };
    if events.iter().all(|&(f, _, _)| f as usize >= faces) {
        return groups;
    }
    let mut ids: std::collections::HashMap<GroupState, u32> = std::collections::HashMap::new();
    let mut state = GroupState::default();
    let mut next = events.iter().peekable();
    let mut id = 0;
    groups.face_states.reserve_exact(faces);
    for f in 0..faces {
        let mut changed = f == 0;
        while let Some((_, kind, text)) = next.next_if(|e| e.0 as usize <= f) {
            let slot = match kind {
                GroupKind::Object => &mut state.object,
                GroupKind::Group => &mut state.group,
                GroupKind::Material => &mut state.material,
            };
            *slot = Some(text.clone());
            changed = true;
        }
        if changed {
            let n = groups.states.len() as u32;
            id = *ids.entry(state.clone()).or_insert(n);
            if id == n {
                groups.states.push(state.clone());
            }
        }
        groups.face_states.push(id);
    }
    groups
}

/// The face-varying channel `"uv"` of the `vt` records: `(u, v)`, or `(u, v, w)` when a
/// record has a `w` other than 0. The indices are in range (checked before).
fn uv_channel(texcoords: &[[f64; 3]], indices: Vec<u32>) -> Result<FaceVarying, MeshError> {
    let dim = if texcoords.iter().any(|t| t[2] != 0.0) {
        3
    } else {
        2
    };
    let values = texcoords.iter().flat_map(|t| t[..dim].to_vec()).collect();
    FaceVarying::new("uv", dim, values, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random OBJ text: vertices, texture coordinates and normals, faces (positive and
    /// relative indices, with and without `vt`/`vn`), comments, blank lines, groups,
    /// materials, smoothing groups and statements that carry nothing, CRLF ends; with `odd` set, now and then what makes a chunk
    /// stop: tags, continued lines, malformed lines, forward references beyond the file,
    /// and lines ended by a lone `\r` (which keep the file from being read in chunks).
    fn random_obj(seed: u64, odd: bool) -> Vec<u8> {
        let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut next = move |n: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % n
        };
        let mut text = String::new();
        if next(4) == 0 {
            text.push('\u{feff}');
        }
        let (mut nv, mut nt, mut nn) = (0u64, 0u64, 0u64);
        // Every face has texture coordinates or none does (a file that mixes them is
        // refused): with them, one is defined first.
        let with_t = next(2) == 0;
        if with_t {
            text += "vt 0.5 0.5\n";
            nt += 1;
        }
        for _ in 0..2000 {
            let end = if next(5) == 0 { "\r\n" } else { "\n" };
            match next(20) {
                0..=5 => {
                    let lead = ["", " ", "\t"][next(3) as usize];
                    let x = next(2001) as f64 / 7.0 - 100.0;
                    text += &format!("{lead}v {x} {} -{}e-3{end}", next(100), next(1000));
                    nv += 1;
                }
                6 => {
                    text += &format!("vt 0.{} 0.{}{end}", next(100), next(100));
                    nt += 1;
                }
                7 => {
                    text += &format!("vn 0 0.{} 1{end}", next(100));
                    nn += 1;
                }
                8..=14 if nv >= 4 => {
                    text.push('f');
                    let (t, n) = (with_t, nn > 0 && next(3) == 0);
                    for _ in 0..3 + next(3) {
                        let v = 1 + next(nv);
                        match next(4) {
                            0 => text += &format!(" -{}", nv + 1 - v),
                            _ => text += &format!(" {v}"),
                        }
                        match (t, n) {
                            (true, true) => text += &format!("/{}/{}", 1 + next(nt), 1 + next(nn)),
                            (true, false) => text += &format!("/{}", 1 + next(nt)),
                            (false, true) => text += &format!("//-{}", 1 + next(nn)),
                            _ => {}
                        }
                    }
                    text += end;
                }
                15 => text += &format!("# v 1 2 3 a comment{end}"),
                16 => {
                    let n = next(5);
                    text += &[
                        "\n".to_string(),
                        format!("g part{n}\n"),
                        format!("usemtl m{}\n", next(3)),
                        ["s off\n", "s 1\n", "o thing\n", "mtllib a.mtl\n"][next(4) as usize]
                            .to_string(),
                        "vp 1\n".to_string(),
                    ][n as usize]
                }
                _ if odd && next(40) == 0 => {
                    text += match next(7) {
                        0 => "t crease 2/1/0 0 1 2.5\n",
                        6 => "v 1 2 3\rv 4 5 6\n",
                        1 => "v 1 2 \\\n 3\n",
                        5 => "f 1 2 3 \\\ng x\n",
                        2 => "v 1 x 3\n",
                        3 => "f 1 2 999999\n",
                        _ => "t interpolateboundary 1/0/0 1\n",
                    }
                }
                _ => text += end,
            }
        }
        text.into_bytes()
    }

    /// Read in chunks on several threads, a file gives what one pass gives: the same
    /// file, or the same error at the same line; whether chunks stop (tags, continued
    /// lines, errors) or not, and with relative indices reaching into earlier chunks.
    #[test]
    fn chunks_read_as_one_pass_reads() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let (mut joined, mut read) = (0, 0);
        for seed in 0..60 {
            let text = random_obj(seed, seed % 3 != 0);
            let one = parse_obj_in(&text, "x.obj", usize::MAX, None);
            read += usize::from(one.as_ref().is_ok_and(|f| !f.mesh.groups.is_empty()));
            let shown = |r: &Result<ObjFile, Refusal>| format!("{r:?}");
            for chunk in [64, 500, 4096] {
                let parallel = pool.install(|| parse_obj_in(&text, "x.obj", chunk, None));
                assert_eq!(
                    shown(&parallel),
                    shown(&one),
                    "seed {seed}, chunks of {chunk}"
                );
                // How far the chunks got before one stopped.
                let chunks = pool.install(|| Chunks::new(&text, chunk));
                let prefix = pool.install(|| parallel_prefix(&text, &chunks));
                // Chunks are joined unless a line ends in a lone `\r`.
                let lone_cr = text.windows(2).any(|w| w[0] == b'\r' && w[1] != b'\n');
                assert_eq!(prefix.is_none(), lone_cr, "seed {seed}, chunks of {chunk}");
                if let Some((parser, rest)) = prefix {
                    joined += usize::from(rest.rest.is_empty() && !parser.face_lines.is_empty());
                }
            }
        }
        // Some files were read whole in chunks, the others in part.
        assert!(joined > 20 && joined < 180, "{joined}");
        // Some files are read (their meshes compared), the others refused.
        assert!(read > 10 && read < 60, "{read}");
    }
}
