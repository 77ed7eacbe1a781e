//! The text of comments and statements in GX Developer files: bytes in the
//! Windows code page of the PC that saved the project, which the files do
//! not name. The code page is guessed from all the texts of a project at
//! once and kept (`//@ encoding NAME` in the listing) so that writing the
//! project back gives the same bytes.

/// A code page of project texts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    ShiftJis,
    Big5,
    Gbk,
    EucKr,
    Windows1252,
}

impl Encoding {
    pub const ALL: [Encoding; 5] = [
        Encoding::ShiftJis,
        Encoding::Big5,
        Encoding::Gbk,
        Encoding::EucKr,
        Encoding::Windows1252,
    ];

    fn codec(self) -> &'static encoding_rs::Encoding {
        match self {
            Encoding::ShiftJis => encoding_rs::SHIFT_JIS,
            Encoding::Big5 => encoding_rs::BIG5,
            Encoding::Gbk => encoding_rs::GBK,
            Encoding::EucKr => encoding_rs::EUC_KR,
            Encoding::Windows1252 => encoding_rs::WINDOWS_1252,
        }
    }

    /// The name the listing's `//@ encoding` line uses.
    pub fn name(self) -> &'static str {
        self.codec().name()
    }

    pub fn from_name(name: &str) -> Option<Encoding> {
        Encoding::ALL
            .into_iter()
            .find(|e| e.name().eq_ignore_ascii_case(name.trim()))
    }

    /// The text of `bytes` (trailing blanks and NULs removed; a byte that
    /// is not text becomes U+FFFD).
    pub fn decode(self, bytes: &[u8]) -> String {
        let (text, _, _) = self.codec().decode(bytes);
        text.trim_end_matches([' ', '\0']).replace(['\r', '\n'], " ")
    }

    /// The bytes of `text`, or why it cannot be written in this code page.
    pub fn encode(self, text: &str) -> Result<Vec<u8>, String> {
        let (bytes, _, unmappable) = self.codec().encode(text);
        if unmappable {
            return Err(format!(
                "the comment `{text}` has characters that the project's code page {} cannot hold",
                self.name()
            ));
        }
        Ok(bytes.into_owned())
    }

    /// The code page that reads `texts` best: Shift-JIS when every
    /// non-ASCII byte could be a half-width katakana (old FX comments are
    /// written so); otherwise, of the East Asian code pages that read every
    /// text without an error, the one that makes the fewest characters of
    /// them (a double-byte text read in the wrong code page falls apart
    /// into single-byte characters); Windows-1252 when none does.
    pub fn guess<'a>(texts: impl IntoIterator<Item = &'a [u8]> + Clone) -> Encoding {
        let non_ascii = || texts.clone().into_iter().flatten().copied().filter(|b| !b.is_ascii());
        if non_ascii().all(|b| (0xA1..=0xDF).contains(&b)) {
            return Encoding::ShiftJis;
        }
        let candidates = [Encoding::ShiftJis, Encoding::Big5, Encoding::Gbk, Encoding::EucKr];
        candidates
            .into_iter()
            .filter_map(|encoding| {
                let mut characters = 0usize;
                for text in texts.clone() {
                    let (decoded, had_errors) = encoding.codec().decode_without_bom_handling(text);
                    if had_errors {
                        return None;
                    }
                    characters += decoded.chars().count();
                }
                Some((characters, encoding))
            })
            .min_by_key(|&(characters, _)| characters)
            .map_or(Encoding::Windows1252, |(_, encoding)| encoding)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_pages_are_told_apart() {
        let big5: &[u8] = b"\xa4\x40\xa6\xb8\xc4\xb2\xb5\x6f\x33\xac\xed";
        let sjis: &[u8] = b"\x8e\x9e\x8c\x76";
        let kana: &[u8] = b"\xba\xdd\xcd\xde\xb1";
        assert_eq!(Encoding::guess([big5]), Encoding::Big5);
        assert_eq!(Encoding::guess([sjis]), Encoding::ShiftJis);
        assert_eq!(Encoding::guess([kana]), Encoding::ShiftJis);
        assert_eq!(Encoding::guess([b"UP".as_slice()]), Encoding::ShiftJis);
        assert_eq!(Encoding::Big5.decode(b"\xa4\x40  "), "\u{4e00}");
        assert_eq!(Encoding::Big5.encode("\u{4e00}").unwrap(), b"\xa4\x40");
        assert!(Encoding::ShiftJis.encode("\u{0416}\u{1F600}").is_err());
        assert_eq!(Encoding::from_name("big5"), Some(Encoding::Big5));
    }
}
