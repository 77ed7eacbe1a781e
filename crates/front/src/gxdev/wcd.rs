//! GX Developer's device comments, `Others/COMMENT.wcd`: decoded to a list
//! of (device, comment) and encoded from one.
//!
//! After the header: the size of the range table (two bytes, ten more than
//! the table), four zero bytes, 20 08, the number of ranges (two bytes);
//! then the ranges, ten bytes each (device code in two bytes, first device
//! and count in four each); then one 40-byte entry per device of the
//! ranges in order: eight bytes GX Developer leaves blank, the comment in
//! 32 bytes padded with blanks.

use super::records::{self, code};
use super::text::Encoding;
use super::DecodeError;

const TABLE_AT: usize = records::HEADER_LEN;
const TABLE_HEAD: usize = 10;
const RANGE_LEN: usize = 10;
const ENTRY_LEN: usize = 40;
/// The blank part before the comment in an entry.
const ENTRY_GAP: usize = 8;
/// How many bytes of a comment an entry holds.
pub const COMMENT_BYTES: usize = ENTRY_LEN - ENTRY_GAP;

/// Bit devices are numbered as written (X/Y octal); word devices decimal.
const DEVICES: [(u8, &str); 9] = [
    (code::X, "X"),
    (code::Y, "Y"),
    (code::M, "M"),
    (code::S, "S"),
    (code::T, "T"),
    (code::C, "C"),
    (code::D, "D"),
    (code::R, "R"),
    (code::P, "P"),
];

/// The name of device `number` of code `device`, as GX Developer shows it.
pub fn device_name(device: u8, number: u32) -> Option<String> {
    let (_, letter) = DEVICES.iter().find(|(c, _)| *c == device)?;
    Some(if device == code::X || device == code::Y {
        format!("{letter}{number:03o}")
    } else {
        format!("{letter}{number}")
    })
}

/// Decoded comments: each device's name and comment (entries left blank
/// are not listed), and the raw comment bytes (for the code-page guess).
pub struct Comments {
    pub cpu: u8,
    pub entries: Vec<(u8, u32, Vec<u8>)>,
}

/// Decodes a comment file.
pub fn decode(bytes: &[u8]) -> Result<Comments, DecodeError> {
    let cpu = records::check_header(bytes)?;
    let head = bytes
        .get(TABLE_AT..TABLE_AT + TABLE_HEAD)
        .ok_or_else(|| DecodeError::new(bytes.len(), "the ten bytes that start the comment table"))?;
    let u16_at = |i: usize| usize::from(u16::from_le_bytes([head[i], head[i + 1]]));
    let ranges = u16_at(8);
    if u16_at(0) != TABLE_HEAD + ranges * RANGE_LEN {
        return Err(DecodeError::new(
            TABLE_AT,
            format!(
                "the table size {} (ten bytes and ten per range, for {ranges} ranges)",
                TABLE_HEAD + ranges * RANGE_LEN
            ),
        ));
    }
    let mut entries = Vec::new();
    let mut entry_at = TABLE_AT + TABLE_HEAD + ranges * RANGE_LEN;
    for range in 0..ranges {
        let at = TABLE_AT + TABLE_HEAD + range * RANGE_LEN;
        let row = bytes
            .get(at..at + RANGE_LEN)
            .ok_or_else(|| DecodeError::new(bytes.len(), format!("range {} of {ranges}", range + 1)))?;
        let word = |i: usize| u32::from_le_bytes([row[i], row[i + 1], row[i + 2], row[i + 3]]);
        let (device, first, count) = (row[0], word(2), word(6));
        if row[1] != 0 || device_name(device, 0).is_none() {
            return Err(DecodeError::new(
                at,
                format!(
                    "the code of a device with comments (found {:02X} {:02X})",
                    row[0], row[1]
                ),
            ));
        }
        for number in first..first.saturating_add(count) {
            let entry = bytes.get(entry_at..entry_at + ENTRY_LEN).ok_or_else(|| {
                DecodeError::new(
                    bytes.len(),
                    format!(
                        "the 40-byte comment of {}",
                        device_name(device, number).unwrap_or_default()
                    ),
                )
            })?;
            let comment = &entry[ENTRY_GAP..];
            let blank = comment.iter().all(|&b| b == b' ' || b == 0);
            if !blank {
                let end = comment.iter().rposition(|&b| b != b' ' && b != 0).map_or(0, |i| i + 1);
                entries.push((device, number, comment[..end].to_vec()));
            }
            entry_at += ENTRY_LEN;
        }
    }
    if entry_at != bytes.len() {
        return Err(DecodeError::new(
            entry_at,
            format!(
                "the end of the file after the last comment ({} more bytes)",
                bytes.len() - entry_at
            ),
        ));
    }
    Ok(Comments { cpu, entries })
}

/// Encodes comments (device code, number, comment text) for CPU type `cpu`:
/// devices in the order of their codes (M, S, X, Y, D, ...) and by number, a range for each run of
/// consecutive devices.
pub fn encode(cpu: u8, comments: &[(u8, u32, String)], encoding: Encoding) -> Result<Vec<u8>, String> {
    let mut sorted: Vec<&(u8, u32, String)> = comments.iter().collect();
    sorted.sort_by_key(|(device, number, _)| (*device, *number));
    let mut ranges: Vec<(u8, u32, u32)> = Vec::new();
    let mut names = Vec::new();
    for (device, number, comment) in sorted {
        match ranges.last_mut() {
            Some((d, first, count)) if d == device && *first + *count == *number => *count += 1,
            Some((d, first, count)) if d == device && *first + *count > *number => {
                return Err(format!(
                    "{} has two comments",
                    device_name(*device, *number).unwrap_or_default()
                ))
            }
            _ => ranges.push((*device, *number, 1)),
        }
        let bytes = encoding.encode(comment)?;
        if bytes.len() > COMMENT_BYTES {
            return Err(format!(
                "the comment of {} is {} bytes long; GX Developer holds {COMMENT_BYTES}",
                device_name(*device, *number).unwrap_or_default(),
                bytes.len()
            ));
        }
        let mut entry = vec![b' '; ENTRY_LEN];
        entry[ENTRY_GAP..ENTRY_GAP + bytes.len()].copy_from_slice(&bytes);
        names.push(entry);
    }
    // The table's size is two bytes: it holds at most 6552 ranges.
    let table = TABLE_HEAD + ranges.len() * RANGE_LEN;
    let (Ok(table), Ok(count)) = (u16::try_from(table), u16::try_from(ranges.len())) else {
        return Err(format!(
            "the comments make {} runs of consecutive devices; COMMENT.wcd holds at most {} \
             (its table size is two bytes): comment fewer devices or number them consecutively",
            ranges.len(),
            (usize::from(u16::MAX) - TABLE_HEAD) / RANGE_LEN
        ));
    };
    let mut out = records::header(cpu, &[]);
    out.extend(table.to_le_bytes());
    out.extend([0, 0, 0, 0, 0x20, 0x08]);
    out.extend(count.to_le_bytes());
    for (device, first, count) in ranges {
        out.extend([device, 0]);
        out.extend(first.to_le_bytes());
        out.extend(count.to_le_bytes());
    }
    out.extend(names.concat());
    Ok(out)
}
