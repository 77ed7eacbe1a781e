//! Source text and byte spans into it.

/// A half-open byte range `start..end` into one source file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Span {
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(start: usize, end: usize) -> Span {
        Span {
            start: start as u32,
            end: end as u32,
        }
    }

    /// The span covering both `self` and `other`.
    pub fn to(self, other: Span) -> Span {
        Span {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// A named source text (a file, or the inline program of a scenario).
#[derive(Clone, Debug)]
pub struct SourceFile {
    pub name: String,
    pub text: String,
    line_starts: Vec<usize>,
    /// Where in `text` the first bytes that could not be decoded are (now
    /// U+FFFD), if any: the front end reports the encoding there.
    pub undecodable_at: Option<usize>,
    /// For a GX Developer project read as its IL listing: the program
    /// file's name (diagnostics name its steps).
    pub listing_of: Option<String>,
    /// A binary file that could not be decoded: the one error to report
    /// (the text is empty).
    pub decode_error: Option<String>,
}

/// How a program file's bytes are text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// UTF-8 without a byte-order mark.
    Utf8,
    /// UTF-8 with the byte-order mark EF BB BF.
    Utf8WithMark,
    /// UTF-16 little-endian, byte-order mark FF FE (GX Works2 exports).
    Utf16Le,
    /// UTF-16 big-endian, byte-order mark FE FF.
    Utf16Be,
}

/// The text of a program file's bytes, its encoding (told by the byte-order
/// mark, UTF-8 without one), and the offset in the text of the first bytes
/// that are not valid in that encoding (decoded as U+FFFD).
pub fn decode(bytes: &[u8]) -> (String, Encoding, Option<usize>) {
    let utf16 = |rest: &[u8], big_endian: bool| {
        let units = rest.chunks(2).map(|pair| match (pair, big_endian) {
            ([high, low], true) | ([low, high], false) => u16::from_le_bytes([*low, *high]),
            // An odd byte at the end: never a valid unit.
            _ => 0xDC00,
        });
        let mut text = String::with_capacity(rest.len() / 2);
        let mut undecodable = None;
        for unit in char::decode_utf16(units) {
            match unit {
                Ok(c) => text.push(c),
                Err(_) => {
                    undecodable.get_or_insert(text.len());
                    text.push(char::REPLACEMENT_CHARACTER);
                }
            }
        }
        (text, undecodable)
    };
    let utf8 = |rest: &[u8]| match std::str::from_utf8(rest) {
        Ok(text) => (text.to_string(), None),
        Err(error) => (String::from_utf8_lossy(rest).into_owned(), Some(error.valid_up_to())),
    };
    match bytes {
        [0xEF, 0xBB, 0xBF, rest @ ..] => {
            let (text, bad) = utf8(rest);
            (text, Encoding::Utf8WithMark, bad)
        }
        [0xFF, 0xFE, rest @ ..] => {
            let (text, bad) = utf16(rest, false);
            (text, Encoding::Utf16Le, bad)
        }
        [0xFE, 0xFF, rest @ ..] => {
            let (text, bad) = utf16(rest, true);
            (text, Encoding::Utf16Be, bad)
        }
        _ => {
            let (text, bad) = utf8(bytes);
            (text, Encoding::Utf8, bad)
        }
    }
}

impl SourceFile {
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        let text = text.into();
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        SourceFile {
            name: name.into(),
            text,
            line_starts,
            undecodable_at: None,
            listing_of: None,
            decode_error: None,
        }
    }

    /// Reads a program file of at most `MAX_SOURCE_BYTES`, decoded as its
    /// byte-order mark says (UTF-8 without one); bytes that are not valid
    /// become U+FFFD and the front end reports where the first one is.
    /// Reading stops at the first NUL byte of a file that is not UTF-16 (it
    /// is not a text file; the front end reports it), so `/dev/zero` ends at
    /// once.
    ///
    /// A GX Developer project (its folder, its `.gps`/`.gpw` file, or its
    /// `MAIN.wpg`) is read as its IL listing, with the comments and
    /// parameters beside the program (`gxdev`).
    pub fn read(path: &std::path::Path) -> Result<SourceFile, ReadError> {
        if let Some(project) = crate::gxdev::locate(path) {
            let name = project.program.display().to_string();
            return match crate::gxdev::read(&project) {
                Ok(listing) => Ok(SourceFile::decoded(&name, Ok(listing))),
                Err(crate::gxdev::ReadFailure::Decode(undecodable)) => Ok(SourceFile::decoded(&name, Err(undecodable))),
                Err(crate::gxdev::ReadFailure::Read(error)) => Err(error),
            };
        }
        let bytes = read_bounded(path)?;
        let mut file = SourceFile::from_bytes(path.display().to_string(), &bytes);
        // `//@ comments FILE`: the comments of a GX Works2 device-comment
        // export beside the program, added after it (spans stay).
        if let Some(name) = crate::gxdev::listing::directives(&file.text).comment_file {
            let csv = path.parent().unwrap_or(std::path::Path::new("")).join(&name);
            let (text, _, _) = decode(&read_bounded(&csv)?);
            let mut all = file.text.clone();
            if !all.is_empty() && !all.ends_with('\n') {
                all.push('\n');
            }
            all.push_str(&crate::gxdev::listing::comments_from_csv(&text));
            file = SourceFile {
                undecodable_at: file.undecodable_at,
                ..SourceFile::new(file.name, all)
            };
        }
        Ok(file)
    }

    /// The listing of a binary program, or the error that it cannot be
    /// decoded (named after the file that cannot be, so that the error
    /// points at it).
    fn decoded(name: &str, listing: Result<String, crate::gxdev::Undecodable>) -> SourceFile {
        let file_name = std::path::Path::new(name)
            .file_name()
            .map_or(name.to_string(), |n| n.to_string_lossy().into_owned());
        match listing {
            Ok(text) => SourceFile {
                listing_of: Some(file_name),
                ..SourceFile::new(name, text)
            },
            Err(undecodable) => SourceFile {
                decode_error: Some(undecodable.to_string()),
                ..SourceFile::new(undecodable.file, "")
            },
        }
    }

    /// A program file's bytes as the front end sees them (a GX Developer
    /// program file, recognised by its header, as its listing).
    pub fn from_bytes(name: impl Into<String>, bytes: &[u8]) -> SourceFile {
        let name = name.into();
        if crate::gxdev::is_gx_file(bytes) {
            return SourceFile::decoded(&name, crate::gxdev::listing_of((&name, bytes), None, None));
        }
        let (mut text, _, undecodable_at) = decode(bytes);
        // A byte-order mark saved twice (an editor re-saving a file that
        // had one) is not text either.
        let marks = text.len() - text.trim_start_matches('\u{feff}').len();
        if marks > 0 {
            text.drain(..marks);
        }
        let undecodable_at = undecodable_at.map(|at| at.saturating_sub(marks));
        SourceFile {
            undecodable_at,
            ..SourceFile::new(name, text)
        }
    }

    /// 1-based line number of a byte offset.
    pub fn line_of(&self, offset: u32) -> u32 {
        match self.line_starts.binary_search(&(offset as usize)) {
            Ok(line) => line as u32 + 1,
            Err(next) => next as u32,
        }
    }

    /// 1-based (line, column) of a byte offset; columns count characters.
    pub fn line_col(&self, offset: u32) -> (u32, u32) {
        let line = self.line_of(offset);
        let start = self.line_starts[line as usize - 1];
        let end = (offset as usize).min(self.text.len());
        let column = self.text.get(start..end).map_or(0, |s| s.chars().count());
        (line, column as u32 + 1)
    }

    /// Byte offsets where each line starts (the first is 0).
    pub fn line_starts(&self) -> &[usize] {
        &self.line_starts
    }

    pub fn slice(&self, span: Span) -> &str {
        self.text.get(span.range()).unwrap_or("")
    }
}

/// The largest program or scenario file ladderc reads (64 MiB): generous
/// for real programs (a million instructions are about 12 MiB), and a bound
/// for everything else.
pub const MAX_SOURCE_BYTES: u64 = 64 * 1024 * 1024;

/// Why a file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("cannot read {path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("{path} is larger than 64 MiB, the most ladderc reads from a program or scenario file")]
    TooLarge { path: String },
}

/// The bytes of a file, at most `MAX_SOURCE_BYTES`; stops after the first
/// NUL byte unless the file starts with a UTF-16 byte-order mark or is a
/// GX Developer file.
pub fn read_bounded(path: &std::path::Path) -> Result<Vec<u8>, ReadError> {
    use std::io::Read;
    let io = |source| ReadError::Io {
        path: path.display().to_string(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut reader = file.take(MAX_SOURCE_BYTES + 1);
    let mut bytes = Vec::new();
    let mut chunk = [0u8; 64 * 1024];
    loop {
        let read = reader.read(&mut chunk).map_err(io)?;
        if read == 0 {
            break;
        }
        let utf16 = matches!(bytes.get(..2).or(chunk.get(..2)), Some([0xFF, 0xFE] | [0xFE, 0xFF]));
        let binary = crate::gxdev::is_gx_file(if bytes.is_empty() { &chunk[..read] } else { &bytes });
        match chunk[..read].iter().position(|&b| b == 0) {
            Some(nul) if !utf16 && !binary => {
                bytes.extend_from_slice(&chunk[..=nul]);
                return Ok(bytes);
            }
            _ => bytes.extend_from_slice(&chunk[..read]),
        }
    }
    if bytes.len() as u64 > MAX_SOURCE_BYTES {
        return Err(ReadError::TooLarge {
            path: path.display().to_string(),
        });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reading_stops_at_binary_data() {
        let bytes = read_bounded(std::path::Path::new("/dev/zero")).unwrap();
        assert_eq!(bytes, [0]);
    }

    #[test]
    fn byte_order_marks_decide_the_encoding() {
        let utf16le: Vec<u8> = [0xFF, 0xFE]
            .into_iter()
            .chain("LD X0\r\n".encode_utf16().flat_map(u16::to_le_bytes))
            .collect();
        let utf16be: Vec<u8> = [0xFE, 0xFF]
            .into_iter()
            .chain("LD X0".encode_utf16().flat_map(u16::to_be_bytes))
            .collect();
        assert_eq!(decode(&utf16le), ("LD X0\r\n".to_string(), Encoding::Utf16Le, None));
        assert_eq!(decode(&utf16be), ("LD X0".to_string(), Encoding::Utf16Be, None));
        assert_eq!(
            decode(b"\xEF\xBB\xBFLD X0"),
            ("LD X0".to_string(), Encoding::Utf8WithMark, None)
        );
        assert_eq!(decode(b"LD X0"), ("LD X0".to_string(), Encoding::Utf8, None));
        // Latin-1 without a mark, an unpaired surrogate, an odd last byte.
        assert_eq!(decode(b"LD X0 ; caf\xE9").2, Some(11));
        assert_eq!(decode(&[0xFF, 0xFE, b'L', 0, 0x00, 0xD8, b'D', 0]).2, Some(1));
        assert_eq!(decode(&[0xFF, 0xFE, b'L', 0, b'D']).2, Some(1));
    }

    #[test]
    fn lines_and_columns_are_one_based() {
        let file = SourceFile::new("t.il", "LD X0\nOUT Y0\n");
        assert_eq!(file.line_col(0), (1, 1));
        assert_eq!(file.line_col(6), (2, 1));
        assert_eq!(file.line_col(10), (2, 5));
        assert_eq!(file.line_of(13), 3);
    }
}
