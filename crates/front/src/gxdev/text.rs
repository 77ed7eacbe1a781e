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
        // The files hold no byte-order marks: FF FE at the start of a
        // Windows-1252 comment is two letters, not UTF-16.
        let (text, _) = self.codec().decode_without_bom_handling(bytes);
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

    /// The code page that reads `texts` best. Of the East Asian code pages
    /// that read every text without an error: the one chardetng (Firefox's
    /// detector, from the frequencies of characters in real text) names;
    /// else Shift-JIS when no double-byte code page reads them and every
    /// non-ASCII byte could be a half-width katakana (old FX comments are
    /// written so); else the one that makes the fewest characters (a
    /// double-byte text read in the wrong code page falls apart into
    /// single-byte characters). Windows-1252 when none reads them all;
    /// Shift-JIS, GX Developer's own, for ASCII.
    pub fn guess<'a>(texts: impl IntoIterator<Item = &'a [u8]> + Clone) -> Encoding {
        let non_ascii = || texts.clone().into_iter().flatten().copied().filter(|b| !b.is_ascii());
        let kana = non_ascii().all(|b| (0xA1..=0xDF).contains(&b));
        if non_ascii().next().is_none() {
            return Encoding::ShiftJis;
        }
        let candidates = [Encoding::ShiftJis, Encoding::Big5, Encoding::Gbk, Encoding::EucKr];
        let readable: Vec<(usize, Encoding)> = candidates
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
            .collect();
        let mut detector = chardetng::EncodingDetector::new(chardetng::Iso2022JpDetection::Deny);
        for text in texts {
            detector.feed(text, false);
            // Texts apart: no character across two of them.
            detector.feed(b"\n", false);
        }
        detector.feed(&[], true);
        let detected = detector.guess(None, chardetng::Utf8Detection::Deny);
        if let Some(&(_, encoding)) = readable.iter().find(|(_, e)| e.codec() == detected) {
            return encoding;
        }
        let double_byte = readable.iter().any(|(_, e)| *e != Encoding::ShiftJis);
        if kana && !double_byte && readable.iter().any(|(_, e)| *e == Encoding::ShiftJis) {
            return Encoding::ShiftJis;
        }
        readable
            .into_iter()
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

    #[test]
    fn korean_and_chinese_in_the_kana_range_are_not_katakana() {
        // Every byte of these is in A1-DF, as half-width katakana are.
        let korean: &[u8] = b"\xc7\xd1\xb1\xb9";
        let chinese: &[u8] = b"\xd6\xd0\xce\xc4";
        assert_eq!(Encoding::guess([korean]), Encoding::EucKr);
        assert_eq!(Encoding::EucKr.decode(korean), "\u{d55c}\u{ad6d}");
        assert_eq!(Encoding::guess([chinese]), Encoding::Gbk);
        assert_eq!(Encoding::Gbk.decode(chinese), "\u{4e2d}\u{6587}");
    }

    #[test]
    fn a_comment_starting_ff_fe_is_not_utf16() {
        assert_eq!(Encoding::Windows1252.decode(b"\xff\xfeA"), "\u{ff}\u{fe}A");
        assert_eq!(Encoding::Windows1252.decode(b"\xef\xbb\xbfA"), "\u{ef}\u{bb}\u{bf}A");
    }
}
