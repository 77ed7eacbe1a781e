//! Retained (latched) devices: what an FX keeps through a power cycle on its
//! battery, `serve --retain FILE` keeps in a file. The latched ranges are
//! FX3U's defaults unless `--latch` names others (as the FX parameters set
//! the latched ranges of M, S, D and C); T and C ranges keep each timer's or
//! counter's contact and current value.
//!
//! The file is written whole to a temporary file beside it, flushed to the
//! disk and renamed over the old one, so a crash (or `kill -9`) at any time
//! leaves either the previous or the new version, never a mixture. It
//! starts with a magic line and carries a CRC-32 of its contents: a file
//! that is cut short, damaged, or not ours is refused with a message rather
//! than read as zeros, and it is never overwritten by a server that could
//! not read it.

use ladder_runtime::device::{FIRST_WIDE_COUNTER, STATE_COUNT, TIMER_COUNT};
use ladder_runtime::Memory;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The first bytes of every retain file.
const MAGIC: &[u8; 16] = b"LADDERC-RETAIN\n\0";
/// The version of the layout below.
const VERSION: u32 = 1;
/// Magic, version, payload length, CRC-32 of the payload.
const HEADER_LEN: usize = 16 + 4 + 4 + 4;
const CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// A kind of latched device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Latched {
    M,
    S,
    /// Timer contact and current value.
    T,
    /// Counter contact and current value (16-bit below C200, 32-bit from C200).
    C,
    D,
    R,
}

impl Latched {
    fn code(self) -> u8 {
        match self {
            Latched::M => 1,
            Latched::S => 2,
            Latched::T => 3,
            Latched::C => 4,
            Latched::D => 5,
            Latched::R => 6,
        }
    }

    fn from_code(code: u8) -> Option<Latched> {
        [Latched::M, Latched::S, Latched::T, Latched::C, Latched::D, Latched::R]
            .into_iter()
            .find(|kind| kind.code() == code)
    }

    fn prefix(self) -> &'static str {
        match self {
            Latched::M => "M",
            Latched::S => "S",
            Latched::T => "T",
            Latched::C => "C",
            Latched::D => "D",
            Latched::R => "R",
        }
    }

    /// Devices of the kind that may be latched: M8000 and up, D8000 and up
    /// are the machine's special devices, which the scan itself maintains.
    fn count(self) -> u32 {
        match self {
            Latched::M => 8000,
            Latched::S => STATE_COUNT,
            Latched::T => TIMER_COUNT,
            Latched::C => ladder_runtime::device::COUNTER_COUNT,
            Latched::D => 8000,
            Latched::R => ladder_runtime::WordArea::R.count(),
        }
    }

    /// The bytes of each value a device has in the file: a bit is one
    /// byte, a word two, a counter's value four (C200 and up are 32-bit).
    fn value_widths(self) -> &'static [usize] {
        match self {
            Latched::M | Latched::S => &[1],
            Latched::D | Latched::R => &[2],
            Latched::T => &[1, 2],
            Latched::C => &[1, 4],
        }
    }

    fn values_per_device(self) -> usize {
        self.value_widths().len()
    }

    fn bytes_per_device(self) -> usize {
        self.value_widths().iter().sum()
    }
}

/// A run of latched devices: `first..end` of one kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LatchRange {
    pub kind: Latched,
    pub first: u32,
    pub end: u32,
}

impl std::fmt::Display for LatchRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = self.kind.prefix();
        write!(f, "{p}{}-{p}{}", self.first, self.end - 1)
    }
}

/// FX3U's latched ranges as they leave the factory: M500-M7679, S500-S4095,
/// T246-T255, C100-C199, C220-C255, D200-D7999 and all of R.
pub fn fx3u_defaults() -> Vec<LatchRange> {
    let range = |kind, first, last: u32| LatchRange {
        kind,
        first,
        end: last + 1,
    };
    vec![
        range(Latched::M, 500, 7679),
        range(Latched::S, 500, STATE_COUNT - 1),
        range(Latched::T, 246, 255),
        range(Latched::C, 100, 199),
        range(Latched::C, 220, 255),
        range(Latched::D, 200, 7999),
        range(Latched::R, 0, Latched::R.count() - 1),
    ]
}

/// `--latch M500-M1023,D200-D511,C100-C199`, or `none`.
pub fn parse_latch_list(text: &str) -> Result<Vec<LatchRange>, String> {
    if text.trim().eq_ignore_ascii_case("none") {
        return Ok(Vec::new());
    }
    text.split(',')
        .map(str::trim)
        .filter(|item| !item.is_empty())
        .map(parse_latch_range)
        .collect()
}

fn parse_latch_range(item: &str) -> Result<LatchRange, String> {
    let device = |text: &str| -> Result<(Latched, u32), String> {
        let text = text.trim();
        let split = text.find(|c: char| c.is_ascii_digit()).unwrap_or(text.len());
        let (prefix, number) = text.split_at(split);
        let kind = [Latched::M, Latched::S, Latched::T, Latched::C, Latched::D, Latched::R]
            .into_iter()
            .find(|kind| kind.prefix().eq_ignore_ascii_case(prefix))
            .ok_or_else(|| format!("`{text}`: only M, S, T, C, D and R devices can be latched"))?;
        let number: u32 = number
            .parse()
            .map_err(|_| format!("`{text}` is not a device like M500"))?;
        if number >= kind.count() {
            return Err(format!(
                "`{text}` cannot be latched (the latched {} devices end at {}{})",
                kind.prefix(),
                kind.prefix(),
                kind.count() - 1
            ));
        }
        Ok((kind, number))
    };
    let (first_text, last_text) = item.split_once('-').unwrap_or((item, item));
    let (kind, first) = device(first_text)?;
    let (last_kind, last) = device(last_text)?;
    if kind != last_kind || last < first {
        return Err(format!("`{item}` is not a range like M500-M1023"));
    }
    Ok(LatchRange {
        kind,
        first,
        end: last + 1,
    })
}

/// The latched values of `image`, as the file holds them.
fn collect(image: &Memory, range: LatchRange) -> Vec<i32> {
    let (first, end) = (range.first as usize, range.end as usize);
    let mut values = Vec::with_capacity((end - first) * range.kind.values_per_device());
    for n in first..end {
        match range.kind {
            Latched::M => values.push(i32::from(image.m[n])),
            Latched::S => values.push(i32::from(image.s[n])),
            Latched::D => values.push(i32::from(image.d[n])),
            Latched::R => values.push(i32::from(image.r[n])),
            Latched::T => values.extend([i32::from(image.timer_contact[n]), i32::from(image.timer_value[n])]),
            Latched::C => values.extend([i32::from(image.counter_contact[n]), counter_value(image, n)]),
        }
    }
    values
}

fn counter_value(image: &Memory, n: usize) -> i32 {
    let wide = FIRST_WIDE_COUNTER as usize;
    if n < wide {
        i32::from(image.counter_value[n])
    } else {
        image.wide_counter_value[n - wide]
    }
}

/// Writes retained values back into `image`.
fn restore(image: &mut Memory, range: LatchRange, values: &[i32]) {
    let per = range.kind.values_per_device();
    let wide = FIRST_WIDE_COUNTER as usize;
    for (n, value) in (range.first as usize..range.end as usize).zip(values.chunks_exact(per)) {
        let bit = |v: i32| u8::from(v != 0);
        match range.kind {
            Latched::M => image.m[n] = bit(value[0]),
            Latched::S => image.s[n] = bit(value[0]),
            Latched::D => image.d[n] = value[0] as i16,
            Latched::R => image.r[n] = value[0] as i16,
            Latched::T => {
                image.timer_contact[n] = bit(value[0]);
                image.timer_value[n] = value[1] as i16;
            }
            Latched::C => {
                image.counter_contact[n] = bit(value[0]);
                if n < wide {
                    image.counter_value[n] = value[1] as i16;
                } else {
                    image.wide_counter_value[n - wide] = value[1];
                }
            }
        }
    }
}

/// The file's contents for `image`.
pub fn encode(image: &Memory, ranges: &[LatchRange]) -> Vec<u8> {
    let mut payload = Vec::new();
    for &range in ranges {
        payload.push(range.kind.code());
        payload.extend(range.first.to_le_bytes());
        payload.extend(range.end.to_le_bytes());
        let widths = range.kind.value_widths().iter().cycle();
        for (value, &width) in collect(image, range).into_iter().zip(widths) {
            payload.extend(&value.to_le_bytes()[..width]);
        }
    }
    let mut file = Vec::with_capacity(HEADER_LEN + payload.len());
    file.extend(MAGIC);
    file.extend(VERSION.to_le_bytes());
    file.extend((payload.len() as u32).to_le_bytes());
    file.extend(CRC.checksum(&payload).to_le_bytes());
    file.extend(payload);
    file
}

/// Why a retain file cannot be used.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
pub enum RetainError {
    #[error("is not a ladderc retain file (it does not start with the retain file's mark)")]
    Foreign,
    #[error("was written by a newer ladderc (retain file version {0}; this one reads version {VERSION})")]
    Version(u32),
    #[error("is cut short ({found} bytes of {expected})")]
    Truncated { found: usize, expected: usize },
    #[error("is damaged (its checksum does not match its contents)")]
    Checksum,
    #[error("is damaged ({0})")]
    Malformed(String),
}

/// The ranges and values a file holds, checked whole before anything is
/// restored.
pub fn decode(bytes: &[u8]) -> Result<Vec<(LatchRange, Vec<i32>)>, RetainError> {
    if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
        return Err(RetainError::Foreign);
    }
    if bytes.len() < HEADER_LEN {
        return Err(RetainError::Truncated {
            found: bytes.len(),
            expected: HEADER_LEN,
        });
    }
    let word = |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let version = word(16);
    if version != VERSION {
        return Err(RetainError::Version(version));
    }
    let expected = HEADER_LEN + word(20) as usize;
    if bytes.len() != expected {
        return Err(if bytes.len() < expected {
            RetainError::Truncated {
                found: bytes.len(),
                expected,
            }
        } else {
            RetainError::Malformed(format!("{} bytes where the header says {expected}", bytes.len()))
        });
    }
    let payload = &bytes[HEADER_LEN..];
    if CRC.checksum(payload) != word(24) {
        return Err(RetainError::Checksum);
    }
    let mut records = Vec::new();
    let mut at = 0;
    while at < payload.len() {
        let malformed = |what: &str| RetainError::Malformed(format!("{what} at byte {}", HEADER_LEN + at));
        if payload.len() - at < 9 {
            return Err(malformed("a range header cut short"));
        }
        let kind = Latched::from_code(payload[at]).ok_or_else(|| malformed("an unknown device kind"))?;
        let field = |offset: usize| {
            let b = &payload[at + offset..at + offset + 4];
            u32::from_le_bytes([b[0], b[1], b[2], b[3]])
        };
        let (first, end) = (field(1), field(5));
        if first >= end || end > kind.count() {
            return Err(malformed("a range outside the device area"));
        }
        let length = (end - first) as usize * kind.bytes_per_device();
        let values_at = at + 9;
        if payload.len() - values_at < length {
            return Err(malformed("a range's values cut short"));
        }
        let mut values = Vec::with_capacity((end - first) as usize * kind.values_per_device());
        let mut rest = &payload[values_at..values_at + length];
        for &width in kind.value_widths().iter().cycle() {
            if rest.is_empty() {
                break;
            }
            let (bytes, after) = rest.split_at(width);
            values.push(match *bytes {
                [a] => i32::from(a),
                [a, b] => i32::from(i16::from_le_bytes([a, b])),
                [a, b, c, d] => i32::from_le_bytes([a, b, c, d]),
                _ => return Err(malformed("a value of an unknown width")),
            });
            rest = after;
        }
        records.push((LatchRange { kind, first, end }, values));
        at = values_at + length;
    }
    Ok(records)
}

/// The retain file of a server: where it is and which ranges it keeps.
#[derive(Clone, Debug)]
pub struct RetainFile {
    pub path: PathBuf,
    pub ranges: Vec<LatchRange>,
}

/// What was found at start.
pub enum Restored {
    /// No file yet: it will be created.
    Fresh,
    /// The file's values, to be written into the first image.
    Values(Vec<(LatchRange, Vec<i32>)>),
}

impl RetainFile {
    /// Reads the file at start; a missing file is a fresh start, any other
    /// problem a message naming the file (and the server does not start).
    pub fn load(&self) -> Result<Restored, String> {
        let bytes = match std::fs::read(&self.path) {
            Ok(bytes) => bytes,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Restored::Fresh),
            Err(e) => return Err(format!("cannot read the retain file {}: {e}", self.path.display())),
        };
        decode(&bytes).map(Restored::Values).map_err(|error| {
            format!(
                "the retain file {} {error}; it was left as it is and nothing was restored \
                 (move it away to start with the latched devices cleared)",
                self.path.display()
            )
        })
    }

    /// The temporary file a save writes before it renames it over the real
    /// one: `FILE.tmp`, beside it.
    pub fn temporary(&self) -> PathBuf {
        let mut name = self.path.file_name().unwrap_or_default().to_os_string();
        name.push(".tmp");
        self.path.with_file_name(name)
    }

    /// A temporary file a save cut short (the server killed while writing)
    /// left behind: removed; whether there was one.
    pub fn remove_leftover(&self) -> bool {
        let leftover = self.temporary();
        leftover.is_file() && std::fs::remove_file(&leftover).is_ok()
    }

    /// Writes `bytes` (the encoding of an image) as the file's contents: a
    /// temporary file beside the real one, flushed, then renamed over it
    /// (and the directory flushed).
    pub fn write(&self, bytes: &[u8]) -> std::io::Result<()> {
        let directory = match self.path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let temporary = self.temporary();
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temporary, &self.path)?;
        sync_directory(&directory);
        Ok(())
    }
}

/// The rename is only durable once the directory is on the disk.
fn sync_directory(directory: &Path) {
    #[cfg(unix)]
    if let Ok(handle) = std::fs::File::open(directory) {
        let _ = handle.sync_all();
    }
    #[cfg(not(unix))]
    let _ = directory;
}

/// Writes retained values into `image`.
pub fn apply(image: &mut Memory, records: &[(LatchRange, Vec<i32>)]) {
    for (range, values) in records {
        restore(image, *range, values);
    }
}

/// The parts of a file's `records` that lie in the configured `ranges`
/// (a file written with wider ranges gives back only what is latched now),
/// and the parts left out (to be said).
#[allow(clippy::type_complexity)]
pub fn within(
    records: Vec<(LatchRange, Vec<i32>)>,
    ranges: &[LatchRange],
) -> (Vec<(LatchRange, Vec<i32>)>, Vec<LatchRange>) {
    let mut kept = Vec::new();
    let mut dropped = Vec::new();
    for (record, values) in records {
        let per = record.kind.values_per_device();
        let mut covered: Vec<(u32, u32)> = Vec::new();
        for range in ranges.iter().filter(|r| r.kind == record.kind) {
            let (first, end) = (record.first.max(range.first), record.end.min(range.end));
            if first < end {
                let from = (first - record.first) as usize * per;
                let to = (end - record.first) as usize * per;
                if let Some(part) = values.get(from..to) {
                    kept.push((
                        LatchRange {
                            kind: record.kind,
                            first,
                            end,
                        },
                        part.to_vec(),
                    ));
                    covered.push((first, end));
                }
            }
        }
        // What of the record no configured range covers.
        covered.sort_unstable();
        let mut at = record.first;
        for (first, end) in covered {
            if first > at {
                dropped.push(LatchRange {
                    kind: record.kind,
                    first: at,
                    end: first,
                });
            }
            at = at.max(end);
        }
        if at < record.end {
            dropped.push(LatchRange {
                kind: record.kind,
                first: at,
                end: record.end,
            });
        }
    }
    (kept, dropped)
}

/// The devices an FX keeps at STOP→RUN: the latched ranges. Everything
/// else of the program's devices is cleared, as an FX clears its
/// non-latched devices when it switches to RUN; what belongs to the
/// machine around the program stays (the inputs as the host set them,
/// forces, the clock, the modules' buffer memory), and the first scan is
/// the first again (M8002 ON, D8011/D8012 since RUN).
pub fn restart(image: &Memory, ranges: &[LatchRange]) -> Box<Memory> {
    let mut fresh = Memory::new_boxed();
    let kept: Vec<(LatchRange, Vec<i32>)> = ranges.iter().map(|&range| (range, collect(image, range))).collect();
    apply(&mut fresh, &kept);
    fresh.input_image = image.input_image;
    fresh.x = image.x;
    fresh.forced_count = image.forced_count;
    fresh.force_x = image.force_x;
    fresh.force_y = image.force_y;
    fresh.force_m = image.force_m;
    fresh.force_timer = image.force_timer;
    fresh.force_counter = image.force_counter;
    // A forced device keeps its forced value.
    for (n, &force) in image.force_m.iter().enumerate() {
        if force != ladder_runtime::memory::FORCE_NONE {
            fresh.m[n] = image.m[n];
        }
    }
    for (n, &force) in image.force_y.iter().enumerate() {
        if force != ladder_runtime::memory::FORCE_NONE {
            fresh.y[n] = image.y[n];
        }
    }
    for (n, &force) in image.force_timer.iter().enumerate() {
        if force != ladder_runtime::memory::FORCE_NONE {
            fresh.timer_contact[n] = image.timer_contact[n];
        }
    }
    for (n, &force) in image.force_counter.iter().enumerate() {
        if force != ladder_runtime::memory::FORCE_NONE {
            fresh.counter_contact[n] = image.counter_contact[n];
        }
    }
    fresh.calendar_seconds = image.calendar_seconds;
    fresh.calendar_ms = image.calendar_ms;
    fresh.calendar_flags = image.calendar_flags;
    fresh.clock_ms = image.clock_ms;
    fresh.d[8013..8020].copy_from_slice(&image.d[8013..8020]);
    bytemuck::cast_slice_mut::<i16, u8>(&mut fresh.buffer[..])
        .copy_from_slice(bytemuck::cast_slice::<i16, u8>(&image.buffer[..]));
    fresh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_image() -> Box<Memory> {
        let mut image = Memory::new_boxed();
        image.m[500] = 1;
        image.m[499] = 1;
        image.s[900] = 1;
        image.d[200] = -1234;
        image.d[199] = 77;
        image.r[32767] = 5;
        image.timer_contact[250] = 1;
        image.timer_value[250] = 300;
        image.counter_value[150] = 9;
        image.counter_contact[150] = 1;
        image.wide_counter_value[(230 - FIRST_WIDE_COUNTER) as usize] = -100_000;
        image
    }

    #[test]
    fn latched_devices_come_back_and_others_do_not() {
        let ranges = fx3u_defaults();
        let bytes = encode(&sample_image(), &ranges);
        let records = decode(&bytes).expect("a file just written reads back");
        let mut fresh = Memory::new_boxed();
        apply(&mut fresh, &records);
        assert_eq!((fresh.m[500], fresh.m[499]), (1, 0));
        assert_eq!(fresh.s[900], 1);
        assert_eq!((fresh.d[200], fresh.d[199]), (-1234, 0));
        assert_eq!(fresh.r[32767], 5);
        assert_eq!((fresh.timer_contact[250], fresh.timer_value[250]), (1, 300));
        assert_eq!((fresh.counter_contact[150], fresh.counter_value[150]), (1, 9));
        assert_eq!(fresh.wide_counter_value[30], -100_000);
    }

    #[test]
    fn every_cut_and_every_flipped_byte_is_refused() {
        let ranges = parse_latch_list("M500-M520,D200-D203,C199-C201").unwrap();
        let bytes = encode(&sample_image(), &ranges);
        for cut in 0..bytes.len() {
            assert!(decode(&bytes[..cut]).is_err(), "cut at {cut} accepted");
        }
        for at in 0..bytes.len() {
            let mut damaged = bytes.clone();
            damaged[at] ^= 0x10;
            assert!(decode(&damaged).is_err(), "flip at {at} accepted");
        }
        assert_eq!(decode(b"hello, world"), Err(RetainError::Foreign));
    }

    #[test]
    fn latch_lists_parse_as_fx_parameters_name_them() {
        let ranges = parse_latch_list("m500-M1023, D200-D511,T250").unwrap();
        assert_eq!(ranges.len(), 3);
        assert_eq!(ranges[0].to_string(), "M500-M1023");
        assert_eq!(ranges[2].to_string(), "T250-T250");
        assert_eq!(parse_latch_list("none").unwrap(), Vec::new());
        for bad in ["X0-X7", "M10-M5", "M500-D600", "M8000", "D9000", "Mx"] {
            assert!(parse_latch_list(bad).is_err(), "{bad} accepted");
        }
    }
}
