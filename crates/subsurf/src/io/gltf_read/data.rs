//! The bytes behind a glTF document: the GLB container, the buffers (the GLB `BIN` chunk,
//! `data:` URIs in base64, files beside the document) and the accessors that read them,
//! every offset, length and stride checked before a byte is read.

use std::borrow::Cow;
use std::path::Path;

use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::Source;
use gltf::Accessor;

/// The JSON chunk and the `BIN` chunk (if any) of a GLB file (glTF 2.0 specification,
/// section 4.4 "Binary glTF Layout": a 12-byte header `glTF`, version 2, total length;
/// then chunks of a length, a type and the data, the first `JSON`, an optional `BIN`;
/// chunks of other types are skipped, as the specification asks).
pub(super) fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        let b = bytes.get(at..at.checked_add(4)?)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let short = || format!("the binary glTF file is cut short ({} bytes)", bytes.len());
    let version = word(4).ok_or_else(short)?;
    if version != 2 {
        return Err(format!(
            "binary glTF version {version} is not read (only version 2)"
        ));
    }
    let length = word(8).ok_or_else(short)? as usize;
    if length > bytes.len() || length < 12 {
        return Err(format!(
            "the binary glTF header gives a length of {length} bytes, but the file has {}",
            bytes.len()
        ));
    }
    let bytes = &bytes[..length];
    let mut at = 12usize;
    let (mut json, mut bin) = (None, None);
    while at < bytes.len() {
        let (Some(len), Some(kind)) = (word(at), word(at + 4)) else {
            return Err(format!("chunk header at byte {at} is cut short"));
        };
        let start = at + 8;
        let data = start
            .checked_add(len as usize)
            .and_then(|end| bytes.get(start..end))
            .ok_or_else(|| {
                format!("the chunk at byte {at} claims {len} bytes, beyond the end of the file")
            })?;
        match (kind, json.is_some()) {
            (super::super::gltf::CHUNK_JSON, false) => json = Some(data),
            (_, false) => {
                return Err("the first chunk of the binary glTF file is not its JSON".into())
            }
            (super::super::gltf::CHUNK_BIN, true) if bin.is_none() => bin = Some(data),
            _ => {}
        }
        // Chunks are padded to 4 bytes; a length that is not is tolerated.
        at = start + len as usize;
    }
    let json = json.ok_or("the binary glTF file has no JSON chunk")?;
    Ok((json, bin))
}

/// The data of every buffer, loaded when an accessor first needs it.
pub(super) struct Buffers<'a> {
    /// The GLB `BIN` chunk.
    bin: Option<&'a [u8]>,
    /// Where relative URIs are looked up.
    dir: Option<&'a Path>,
    loaded: Vec<Option<Cow<'a, [u8]>>>,
    /// Bytes read from files, counted against `limit`.
    pub(super) external: u64,
    /// What the caller allows for external files.
    limit: Option<u64>,
}

impl<'a> Buffers<'a> {
    pub(super) fn new(
        count: usize,
        bin: Option<&'a [u8]>,
        dir: Option<&'a Path>,
        limit: Option<u64>,
    ) -> Self {
        Self {
            bin,
            dir,
            loaded: (0..count).map(|_| None).collect(),
            external: 0,
            limit,
        }
    }

    /// Loads the data of `buffer` unless it is loaded: [`data`](Self::data) gives it then.
    ///
    /// # Errors
    /// [`BufferError::Bad`] naming the buffer: no data, a URI that is neither `data:` in
    /// base64 nor a relative file, a file that cannot be read, fewer bytes than
    /// `byteLength`; [`BufferError::TooLarge`] when the files read so far exceed the limit.
    pub(super) fn load(&mut self, buffer: &gltf::Buffer<'_>) -> Result<(), BufferError> {
        let i = buffer.index();
        if self.loaded.get(i).is_some_and(Option::is_none) {
            let data = self.fetch(buffer)?;
            if data.len() < buffer.length() {
                return Err(BufferError::Bad(format!(
                    "buffer {i}: its byteLength is {} bytes, but its data holds {}",
                    buffer.length(),
                    data.len()
                )));
            }
            self.loaded[i] = Some(data);
        }
        Ok(())
    }

    /// The data of buffer `buffer` (its first `byteLength` bytes), once loaded.
    fn data(&self, buffer: &gltf::Buffer<'_>) -> Option<&[u8]> {
        let data = self.loaded.get(buffer.index())?.as_deref()?;
        data.get(..buffer.length())
    }

    fn fetch(&mut self, buffer: &gltf::Buffer<'_>) -> Result<Cow<'a, [u8]>, BufferError> {
        let i = buffer.index();
        let bad = |m: String| BufferError::Bad(format!("buffer {i}: {m}"));
        let uri =
            match buffer.source() {
                Source::Bin => return match (i, self.bin) {
                    (0, Some(bin)) => Ok(Cow::Borrowed(bin)),
                    _ => Err(bad(
                        "it has no uri, and only the first buffer of a binary glTF file (.glb) \
                         may be its BIN chunk"
                            .into(),
                    )),
                },
                Source::Uri(uri) => uri,
            };
        if let Some(rest) = uri.strip_prefix("data:") {
            let Some((_, data)) = rest.split_once(";base64,") else {
                return Err(bad("a data URI must be base64 (';base64,')".into()));
            };
            return decode_base64(data).map(Cow::Owned).map_err(bad);
        }
        let scheme = uri.split_once(':').map(|(s, _)| s);
        if scheme.is_some_and(|s| s.len() > 1 && s.bytes().all(|b| b.is_ascii_alphabetic())) {
            return Err(bad(format!(
                "its uri '{}' is not a relative file name or a data: URI; buffers are read from \
                 files beside the .gltf file only",
                shorten(uri)
            )));
        }
        let relative = percent_decode(uri).map_err(bad)?;
        let path = match self.dir {
            Some(dir) => dir.join(&relative),
            None => relative.clone().into(),
        };
        let size = std::fs::metadata(&path)
            .map_err(|e| bad(format!("cannot read {}: {e}", path.display())))?
            .len();
        self.external = self.external.saturating_add(size);
        if self.limit.is_some_and(|l| self.external > l) {
            return Err(BufferError::TooLarge {
                needed: self.external,
            });
        }
        std::fs::read(&path)
            .map(Cow::Owned)
            .map_err(|e| bad(format!("cannot read {}: {e}", path.display())))
    }
}

/// Why a buffer gave no data.
pub(super) enum BufferError {
    /// What is wrong, naming the buffer.
    Bad(String),
    /// External files beyond the memory limit.
    TooLarge { needed: u64 },
}

/// At most 60 characters of `s`, for a message.
fn shorten(s: &str) -> String {
    match s.char_indices().nth(60) {
        Some((at, _)) => format!("{}...", &s[..at]),
        None => s.to_owned(),
    }
}

/// Standard base64 (RFC 4648, section 4), padding optional.
fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let text = text.trim_end_matches('=');
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 3);
    let (mut acc, mut bits) = (0u32, 0u32);
    for (i, c) in text.bytes().enumerate() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => {
                return Err(format!(
                    "its data URI has the character {:?} at {i}, which is not base64",
                    c as char
                ))
            }
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    if bits >= 6 {
        return Err("its base64 data has a length that no bytes have (4n + 1)".into());
    }
    Ok(out)
}

/// A URI path with `%XX` escapes decoded (RFC 3986, section 2.1).
fn percent_decode(uri: &str) -> Result<String, String> {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = b
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("its uri '{}' has a bad % escape", shorten(uri)))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("its uri '{}' is not UTF-8", shorten(uri)))
}

/// An accessor's elements as raw bytes: where each starts, checked to lie in its buffer
/// view and the view in its buffer.
pub(super) struct Elements<'b> {
    data: &'b [u8],
    stride: usize,
    /// Number of elements.
    pub(super) count: usize,
    kind: DataType,
    normalized: bool,
}

/// Components per element of `d` (matrices: all their entries).
fn components(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

fn type_name(kind: DataType, normalized: bool, dims: Dimensions) -> String {
    let k = match kind {
        DataType::I8 => "i8",
        DataType::U8 => "u8",
        DataType::I16 => "i16",
        DataType::U16 => "u16",
        DataType::U32 => "u32",
        DataType::F32 => "f32",
    };
    let d = match dims {
        Dimensions::Scalar => "SCALAR",
        Dimensions::Vec2 => "VEC2",
        Dimensions::Vec3 => "VEC3",
        Dimensions::Vec4 => "VEC4",
        Dimensions::Mat2 => "MAT2",
        Dimensions::Mat3 => "MAT3",
        Dimensions::Mat4 => "MAT4",
    };
    format!("{d} of {}{k}", if normalized { "normalized " } else { "" })
}

/// The elements of `accessor`, whose type must be `dims` of one of the component types
/// `allowed` (with whether normalized); `what` names it in messages (`"POSITION"`). Its
/// buffer must have been loaded ([`Buffers::load`]).
///
/// # Errors
/// A message naming the accessor: another type, a sparse accessor (not read), a view or
/// element beyond its buffer, a stride smaller than an element.
pub(super) fn elements<'b>(
    accessor: &Accessor<'_>,
    buffers: &'b Buffers<'_>,
    what: &str,
    dims: Dimensions,
    allowed: &[(DataType, bool)],
) -> Result<Elements<'b>, String> {
    let a = accessor.index();
    let bad = |m: String| format!("{what} accessor {a}: {m}");
    let (kind, normalized) = (accessor.data_type(), accessor.normalized());
    if accessor.dimensions() != dims || !allowed.contains(&(kind, normalized)) {
        let wanted: Vec<String> = (allowed.iter())
            .map(|&(k, n)| type_name(k, n, dims))
            .collect();
        return Err(bad(format!(
            "its type is {}, but {what} must be {}",
            type_name(kind, normalized, accessor.dimensions()),
            wanted.join(" or ")
        )));
    }
    if accessor.sparse().is_some() {
        return Err(bad("sparse accessors are not read".into()));
    }
    let n = components(dims);
    let size = n * kind.size();
    let count = accessor.count();
    let Some(view) = accessor.view() else {
        // No buffer view: every element is zero (glTF 2.0, section 3.6.2.1).
        return Ok(Elements {
            data: &[],
            stride: 0,
            count,
            kind,
            normalized,
        });
    };
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(bad(format!(
            "its buffer view {} has a byteStride of {stride}, less than an element ({size} bytes)",
            view.index()
        )));
    }
    let buffer = buffers.data(&view.buffer()).ok_or_else(|| {
        bad(format!(
            "the data of its buffer {} is not loaded",
            view.buffer().index()
        ))
    })?;
    let view_end = view.offset().checked_add(view.length());
    let view_data = view_end
        .and_then(|end| buffer.get(view.offset()..end))
        .ok_or_else(|| {
            bad(format!(
                "its buffer view {} (bytes {} to {}) lies beyond its buffer {} of {} bytes",
                view.index(),
                view.offset(),
                view.offset().saturating_add(view.length()),
                view.buffer().index(),
                buffer.len()
            ))
        })?;
    let end = match count {
        0 => Some(accessor.offset()),
        _ => (count - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(size))
            .and_then(|x| x.checked_add(accessor.offset())),
    };
    let data = end
        .and_then(|end| view_data.get(accessor.offset()..end))
        .ok_or_else(|| {
            bad(format!(
                "its {count} elements from byte {} lie beyond its buffer view {} of {} bytes",
                accessor.offset(),
                view.index(),
                view_data.len()
            ))
        })?;
    Ok(Elements {
        data,
        stride,
        count,
        kind,
        normalized,
    })
}

impl Elements<'_> {
    /// Component `k` of element `i` as a number: floats as they are, normalized integers
    /// mapped to `[0, 1]` or `[-1, 1]` as the glTF 2.0 specification converts them
    /// (`f = c / (2ⁿ − 1)` unsigned, `max(c / (2ⁿ⁻¹ − 1), −1)` signed, for `n`-bit `c`),
    /// other integers as they are. `i < count`, `k < dims`.
    pub(super) fn component(&self, i: usize, k: usize) -> f64 {
        if self.data.is_empty() {
            return 0.0;
        }
        let at = i * self.stride + k * self.kind.size();
        let b = &self.data[at..at + self.kind.size()];
        let norm = self.normalized;
        match self.kind {
            DataType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            DataType::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            DataType::U16 => {
                let c = f64::from(u16::from_le_bytes([b[0], b[1]]));
                if norm {
                    c / 65535.0
                } else {
                    c
                }
            }
            DataType::I16 => {
                let c = f64::from(i16::from_le_bytes([b[0], b[1]]));
                if norm {
                    (c / 32767.0).max(-1.0)
                } else {
                    c
                }
            }
            DataType::U8 => {
                let c = f64::from(b[0]);
                if norm {
                    c / 255.0
                } else {
                    c
                }
            }
            DataType::I8 => {
                let c = f64::from(b[0] as i8);
                if norm {
                    (c / 127.0).max(-1.0)
                } else {
                    c
                }
            }
        }
    }

    /// Element `i` as an index (an unsigned integer scalar).
    pub(super) fn index(&self, i: usize) -> u32 {
        if self.data.is_empty() {
            return 0;
        }
        let at = i * self.stride;
        let b = &self.data[at..];
        match self.kind {
            DataType::U8 => u32::from(b[0]),
            DataType::U16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_rfc_4648_vectors() {
        for (text, bytes) in [
            ("", ""),
            ("Zg==", "f"),
            ("Zm8=", "fo"),
            ("Zm9v", "foo"),
            ("Zm9vYg==", "foob"),
            ("Zm9vYmE=", "fooba"),
            ("Zm9vYmFy", "foobar"),
            ("Zm9vYmFy", "foobar"),
        ] {
            assert_eq!(decode_base64(text).unwrap(), bytes.as_bytes(), "{text}");
        }
        assert!(decode_base64("Zm9v!").is_err());
        assert!(decode_base64("Z").is_err());
    }

    #[test]
    fn percent_escapes_decode() {
        assert_eq!(percent_decode("a%20b.bin").unwrap(), "a b.bin");
        assert!(percent_decode("a%2").is_err());
        assert!(percent_decode("a%zz").is_err());
    }

    #[test]
    fn glb_container_errors_never_panic() {
        let mut glb = b"glTF".to_vec();
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&24u32.to_le_bytes());
        glb.extend_from_slice(&4u32.to_le_bytes());
        glb.extend_from_slice(&super::super::super::gltf::CHUNK_JSON.to_le_bytes());
        glb.extend_from_slice(b"{}  ");
        assert_eq!(split_glb(&glb).unwrap().0, b"{}  ");
        for cut in 0..glb.len() {
            let mut g = glb[..cut].to_vec();
            if g.len() >= 12 {
                g[8..12].copy_from_slice(&(cut as u32).to_le_bytes());
            }
            let _ = split_glb(&g);
        }
    }
}
