//! The MELSEC communication protocol (MC protocol) as a PLC answers it:
//! the A-compatible 1E frames of an FX3U-ENET-ADP / FX3U-ENET(-L), and the
//! 3E and 4E frames (SLMP) of an iQ-F / Q / L CPU, in binary and in ASCII.
//!
//! The crate knows frames and commands, not the PLC: what a request reads
//! and writes goes through the [`Plc`] trait, which the soft PLC
//! implements over its device image (reads) and its queue of host writes
//! (writes, applied before the next scan). So it has no dependencies and
//! is fuzzed and tested on its own.
//!
//! - [`frame_length`] splits a byte stream into frames, telling the kinds
//!   apart by their first bytes: a 1E command byte (up to 1FH, so that an
//!   unknown command gets its end code) or its two hex digits, the 3E
//!   subheader 5000H, the 4E subheader 5400H, in binary or as ASCII text.
//! - [`answer`] answers one frame: the response, or the frame kind's end
//!   code for what is refused (unknown command, device out of range, too
//!   many points, a write refused by the server's access rules).
//!
//! Decisions where the manuals leave a choice (docs/serve.md lists them for
//! users): X and Y are octal in every frame kind, as on an FX and an iQ-F
//! (binary frames send the number's value, X17 = 15; ASCII 3E/4E frames
//! send octal digits); the FX3's 32-bit counters C200-C255 are read and
//! written as two words a point in 1E frames (as an FX3U-ENET-ADP does)
//! and as LCN200-LCN255 in 3E/4E frames, where CN200 and up are refused.

mod device;
mod e1;
mod e3;
mod exec;
mod wire;

pub use device::{Device, Family, FAMILIES};
pub use exec::{Refusal, Remote, Write};
pub use wire::Code;

/// The largest frame accepted (the longest request the point limits
/// allow, in ASCII, is under 8 KiB).
pub const MAX_FRAME: usize = 16 * 1024;

/// What the soft PLC offers a frame. Reads see one image (the latest
/// scan's); writes are applied all together before the next scan, or not
/// at all.
pub trait Plc {
    /// Points in a family (0: none); device numbers run from 0.
    fn points(&self, family: Family) -> u32;
    /// Whether a device holds 32 bits (an FX3's C200-C255 current values).
    fn wide(&self, device: Device) -> bool;
    fn bit(&self, device: Device) -> bool;
    /// A 16-bit device's value.
    fn word(&self, device: Device) -> u16;
    /// A 32-bit device's value.
    fn dword(&self, device: Device) -> u32;
    /// Applies `writes` before the next scan, in order, or refuses them all.
    fn write(&mut self, writes: Vec<Write>) -> Result<(), Refusal>;
    /// RUN, STOP or PAUSE, as the RUN/STOP switch and the debugger do.
    fn remote(&mut self, operation: Remote) -> Result<(), Refusal>;
}

/// The kind of a frame, as its first bytes tell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A-compatible 1E (FX3U-ENET-ADP).
    E1(Code),
    /// 3E (QnA-compatible; SLMP).
    E3(Code),
    /// 4E (3E with a serial number).
    E4(Code),
}

/// How much of a stream the next frame takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Length {
    /// At least this many bytes are needed to know.
    Need(usize),
    /// The frame is this many bytes.
    Frame(usize),
    /// The bytes cannot start a frame, or say a length that cannot be
    /// right: a stream cannot find the next frame after them.
    Invalid,
}

/// The kind of frame `bytes` start (at least 4 bytes are needed to tell
/// ASCII 3E/4E from 1E).
pub fn kind(bytes: &[u8]) -> Option<Kind> {
    let first = *bytes.first()?;
    if e1::is_command(first) {
        return Some(Kind::E1(Code::Binary));
    }
    match bytes.get(..2)? {
        [0x50, 0x00] => return Some(Kind::E3(Code::Binary)),
        [0x54, 0x00] => return Some(Kind::E4(Code::Binary)),
        _ => {}
    }
    match bytes.get(..4)? {
        b"5000" => Some(Kind::E3(Code::Ascii)),
        b"5400" => Some(Kind::E4(Code::Ascii)),
        [a, b, ..] if a.is_ascii_hexdigit() && b.is_ascii_hexdigit() => Some(Kind::E1(Code::Ascii)),
        _ => None,
    }
}

/// The length of the frame at the start of `bytes`.
pub fn frame_length(bytes: &[u8]) -> Length {
    let needed = match bytes.first() {
        None => return Length::Need(1),
        Some(&first) if e1::is_command(first) => 1,
        Some(_) => 4,
    };
    if bytes.len() < needed {
        return Length::Need(needed);
    }
    match kind(bytes) {
        None => Length::Invalid,
        Some(Kind::E1(code)) => e1::frame_length(bytes, code),
        Some(Kind::E3(code)) => e3::frame_length(bytes, code, false),
        Some(Kind::E4(code)) => e3::frame_length(bytes, code, true),
    }
}

/// The response to one whole frame (as [`frame_length`] delimits it).
/// Frames that cannot be answered (no frame kind) get no response.
pub fn answer(frame: &[u8], plc: &mut dyn Plc) -> Option<Vec<u8>> {
    match kind(frame)? {
        Kind::E1(code) => Some(e1::answer(frame, code, plc)),
        Kind::E3(code) => e3::answer(frame, code, false, plc),
        Kind::E4(code) => e3::answer(frame, code, true, plc),
    }
}

#[cfg(test)]
mod tests;
