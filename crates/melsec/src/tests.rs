//! Frames from the manuals' examples and the corner cases, answered by a
//! device store in memory.

use crate::*;
use std::collections::HashMap;

/// An FX3U's device ranges over maps; C200-C255 are 32-bit.
#[derive(Default)]
struct Store {
    bits: HashMap<Device, bool>,
    words: HashMap<Device, u32>,
    writes: Vec<Write>,
    remote: Vec<Remote>,
    refuse: Option<Refusal>,
}

impl Plc for Store {
    fn points(&self, family: Family) -> u32 {
        match family {
            Family::X | Family::Y => 256,
            Family::M => 8512,
            Family::S => 4096,
            Family::D => 8512,
            Family::R => 32768,
            Family::TimerContact | Family::TimerCoil | Family::TimerValue => 512,
            Family::CounterContact | Family::CounterCoil | Family::CounterValue => 256,
            Family::Sm | Family::Sd | Family::LongCounterValue => 0,
        }
    }
    fn wide(&self, device: Device) -> bool {
        device.family == Family::CounterValue && device.number >= 200
    }
    fn bit(&self, device: Device) -> bool {
        self.bits.get(&device).copied().unwrap_or(false)
    }
    fn word(&self, device: Device) -> u16 {
        self.words.get(&device).copied().unwrap_or(0) as u16
    }
    fn dword(&self, device: Device) -> u32 {
        self.words.get(&device).copied().unwrap_or(0)
    }
    fn write(&mut self, writes: Vec<Write>) -> Result<(), Refusal> {
        if let Some(refusal) = self.refuse {
            return Err(refusal);
        }
        for &write in &writes {
            match write {
                Write::Bit(at, on) => {
                    self.bits.insert(at, on);
                }
                Write::Word(at, value) => {
                    self.words.insert(at, u32::from(value));
                }
                Write::Dword(at, value) => {
                    self.words.insert(at, value);
                }
            }
        }
        self.writes.extend(writes);
        Ok(())
    }
    fn remote(&mut self, operation: Remote) -> Result<(), Refusal> {
        self.remote.push(operation);
        Ok(())
    }
}

fn at(family: Family, number: u32) -> Device {
    Device { family, number }
}

fn hex(text: &str) -> Vec<u8> {
    let digits: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    digits
        .chunks(2)
        .map(|pair| u8::from_str_radix(std::str::from_utf8(pair).unwrap(), 16).unwrap())
        .collect()
}

/// A binary 3E request: the route to this PLC, the length counted.
fn e3b(body: &str) -> Vec<u8> {
    let body = hex(body);
    let mut frame = hex("5000 00 FF FF03 00");
    frame.extend((body.len() as u16).to_le_bytes());
    frame.extend(body);
    frame
}

/// A binary 3E response with `end` and `data`.
fn r3b(end: u16, data: &str) -> Vec<u8> {
    let data = hex(data);
    let mut frame = hex("D000 00 FF FF03 00");
    frame.extend((data.len() as u16 + 2).to_le_bytes());
    frame.extend(end.to_le_bytes());
    frame.extend(data);
    frame
}

/// An ASCII 3E request (spaces are for reading only).
fn e3a(body: &str) -> Vec<u8> {
    let body: String = body.split_whitespace().collect();
    format!("500000FF03FF00{:04X}{body}", body.len()).into_bytes()
}

fn r3a(end: u16, data: &str) -> Vec<u8> {
    let data: String = data.split_whitespace().collect();
    format!("D00000FF03FF00{:04X}{end:04X}{data}", data.len() + 4).into_bytes()
}

fn ask(store: &mut Store, frame: &[u8]) -> Vec<u8> {
    assert_eq!(frame_length(frame), Length::Frame(frame.len()), "{frame:02X?}");
    answer(frame, store).expect("answered")
}

fn m100_pattern() -> Store {
    let mut store = Store::default();
    for n in [100, 102, 105, 106] {
        store.bits.insert(at(Family::M, n), true);
    }
    store
}

#[test]
fn a_1e_batch_read_of_bits_answers_as_the_manual_shows() {
    // FX3U-ENET-ADP manual 7.3: M100-M107, 2500 ms timer.
    let mut store = m100_pattern();
    assert_eq!(
        ask(&mut store, &hex("00 FF 0A00 64000000 204D 08 00")),
        hex("80 00 10 10 01 10")
    );
    assert_eq!(
        ask(&mut store, b"00FF000A4D2000000064080000"[..24].as_ref()),
        b"800010100110"
    );
}

#[test]
fn a_1e_frame_is_measured_before_it_is_whole() {
    let frame = hex("02 FF 0A00 32000000 204D 05 00 11 01 10");
    for cut in 1..frame.len() {
        let length = frame_length(&frame[..cut]);
        assert!(
            matches!(length, Length::Need(n) if n > cut) || length == Length::Frame(frame.len()),
            "{cut}: {length:?}"
        );
    }
    assert_eq!(frame_length(&frame), Length::Frame(frame.len()));
    let mut store = Store::default();
    assert_eq!(ask(&mut store, &frame), hex("82 00"));
    let on: Vec<u32> = (50..55).filter(|&n| store.bit(at(Family::M, n))).collect();
    assert_eq!(on, [50, 51, 53, 54]);
}

#[test]
fn a_1e_word_read_of_32_bit_counters_counts_words() {
    let mut store = Store::default();
    store.words.insert(at(Family::CounterValue, 220), 12345678);
    store.words.insert(at(Family::CounterValue, 221), 45678912);
    let answer = ask(&mut store, b"01FF000A434E000000DC0400");
    assert_eq!(answer, b"810000BC614E02B90140");
    // An odd word count is refused with 57H.
    assert_eq!(ask(&mut store, b"01FF000A434E000000DC0300"), b"8157");
    let binary = ask(&mut store, &hex("01 FF 0A00 DC000000 4E43 02 00"));
    assert_eq!(binary, hex("81 00 4E61BC00"));
}

#[test]
fn a_1e_random_word_write_sets_each_device() {
    // Manual 7.5: Y20-Y37 = 7B29H, R26 = 1234H, CN18 = 0050H (ASCII).
    let mut store = Store::default();
    let frame = b"05FF000A0300592000000010 7B29 522000000001A 1234 434E00000012 0050";
    let frame: Vec<u8> = frame.iter().copied().filter(|b| *b != b' ').collect();
    // (R's number field is 8 digits.)
    let frame: Vec<u8> = String::from_utf8(frame)
        .unwrap()
        .replace("522000000001A", "52200000001A")
        .into_bytes();
    assert_eq!(ask(&mut store, &frame), b"8500");
    let y: Vec<u32> = (16..32)
        .filter(|&n| store.bit(at(Family::Y, n)))
        .map(|n| n - 16)
        .collect();
    assert_eq!(y, [0, 3, 5, 8, 9, 11, 12, 13, 14], "7B29H from Y20 up");
    assert_eq!(store.word(at(Family::R, 26)), 0x1234);
    assert_eq!(store.word(at(Family::CounterValue, 18)), 0x50);
}

#[test]
fn a_1e_frame_gets_the_end_code_of_what_is_wrong() {
    let mut store = Store::default();
    // Unknown device name, too many points, a head beyond the last device,
    // a word device in a bit command, a bit head not at a multiple of 16,
    // another PC number, ASCII that is not hex, a run past the last device,
    // a run from C190 into the 32-bit counters, a timer that is not hex.
    let cases: [(&[u8], &[u8]); 10] = [
        (b"00FF000A5A2000000000080000", b"8056"),
        (b"02FF000A4D200000000000A100", b"8257"),
        (b"00FF000A4D2000002140100000", b"8058"),
        (b"00FF000A442000000000010000", b"8058"),
        (b"01FF000A4D2000000001010000", b"8158"),
        (b"0001000A4D2000000000010000", b"805B1000"),
        (b"00FF000A4D20000000G0010000", b"8054"),
        (b"00FF000A4D2000002140080000", b"8058"),
        (b"00FF000A4D200000213C080000", b"8057"),
        (b"01FF000A434E000000BE140000", b"8158"),
    ];
    for (frame, end) in cases {
        let frame = &frame[..frame.len().min(24)];
        let got = answer(frame, &mut store).unwrap();
        assert_eq!(
            String::from_utf8_lossy(&got),
            String::from_utf8_lossy(end),
            "{}",
            String::from_utf8_lossy(frame)
        );
    }
    assert_eq!(answer(&hex("17 FF 0A00"), &mut store).unwrap(), hex("97 50"));
    // A header whose timer is not hex still names its command.
    assert_eq!(answer(b"00FF00ZZ", &mut store).unwrap(), b"8054");
}

#[test]
fn refused_writes_change_nothing() {
    let mut store = Store {
        refuse: Some(Refusal::NotAllowed),
        ..Store::default()
    };
    assert_eq!(
        ask(&mut store, &hex("03 FF 0A00 00000000 2044 01 00 3412")),
        hex("83 55")
    );
    store.refuse = Some(Refusal::Busy);
    assert_eq!(
        ask(&mut store, &hex("03 FF 0A00 00000000 2044 01 00 3412")),
        hex("83 5B 18 00")
    );
    assert!(store.writes.is_empty());
    let frame = hex("500000FFFF0300 0E00 0A00 0114 0000 000000 A8 0100 3412");
    let got = ask(&mut store, &frame);
    assert_eq!(got, hex("D00000FFFF0300 0B00 E0CE 00FFFF0300 0114 0000"));
}

#[test]
fn remote_control_model_and_loopback_in_1e() {
    let mut store = Store::default();
    assert_eq!(ask(&mut store, &hex("14 FF 0A00")), hex("94 00"));
    assert_eq!(ask(&mut store, &hex("13 FF 0A00")), hex("93 00"));
    assert_eq!(store.remote, [Remote::Stop, Remote::Run]);
    assert_eq!(ask(&mut store, &hex("15 FF 0A00")), hex("95 00 F3"));
    assert_eq!(ask(&mut store, b"16FF000A05ABCDE"), b"960005ABCDE");
}

#[test]
fn a_3e_batch_read_of_words_in_binary_and_ascii() {
    let mut store = Store::default();
    for (n, value) in [(100, 0x1995), (101, 0x1202), (102, 0x1130)] {
        store.words.insert(at(Family::D, n), value);
    }
    let binary = e3b("1000 0104 0000 640000 A8 0300");
    assert_eq!(ask(&mut store, &binary), r3b(0, "9519 0212 3011"));
    let ascii = e3a("0010 0401 0000 D* 000100 0003");
    assert_eq!(ask(&mut store, &ascii), r3a(0, "1995 1202 1130"));
}

#[test]
fn a_3e_frame_names_x_and_y_in_octal_and_packs_bits() {
    let mut store = Store::default();
    store.bits.insert(at(Family::X, 0o17), true);
    store.bits.insert(at(Family::X, 0o20), true);
    let ascii = e3a("0010 0401 0001 X* 000017 0003");
    assert_eq!(ask(&mut store, &ascii), r3a(0, "110"));
    let binary = e3b("1000 0104 0100 0F0000 9C 0300");
    assert_eq!(ask(&mut store, &binary), r3b(0, "11 00"));
    // iQ-R form: 4-byte number, 2-byte code; ASCII 4 characters, 8 digits.
    let long = e3b("1000 0104 0300 0F000000 9C00 0200");
    assert_eq!(ask(&mut store, &long), r3b(0, "11"));
    let long = e3a("0010 0401 0003 X*** 00000017 0002");
    assert_eq!(ask(&mut store, &long), r3a(0, "11"));
}

#[test]
fn a_4e_frame_echoes_its_serial_and_writes_bits() {
    let mut store = Store::default();
    let frame = hex("5400 3412 0000 00 FF FF03 00 0E00 1000 0114 0100 050000 90 0300 1010");
    assert_eq!(ask(&mut store, &frame), hex("D400 3412 0000 00 FF FF03 00 0200 0000"));
    let on: Vec<u32> = (5..8).filter(|&n| store.bit(at(Family::M, n))).collect();
    assert_eq!(on, [5, 7]);
    let body = "0010 0401 0001 M* 000005 0003".replace(' ', "");
    let ascii = format!("5400ABCD000000FF03FF00{:04X}{body}", body.len());
    assert_eq!(ask(&mut store, ascii.as_bytes()), b"D400ABCD000000FF03FF0000070000101");
}

#[test]
fn random_reads_and_writes_of_words_and_double_words() {
    let mut store = Store::default();
    // Write D0 = 1, D10:32 = 0x12345678, then read D0 and D10 as a dword.
    let write = e3b("1000 0214 0000 01 01 000000 A8 0100 0A0000 A8 78563412");
    assert_eq!(ask(&mut store, &write), r3b(0, ""));
    assert_eq!(store.word(at(Family::D, 11)), 0x1234);
    let read = e3b("1000 0304 0000 01 01 000000 A8 0A0000 A8");
    assert_eq!(ask(&mut store, &read), r3b(0, "0100 78563412"));
    // In ASCII a double word is 8 digits, high first.
    let read = e3a("0010 0403 0000 01 01 D* 000000 D* 000010");
    assert_eq!(ask(&mut store, &read), r3a(0, "0001 12345678"));
}

#[test]
fn random_access_never_cuts_a_32_bit_counter() {
    let mut store = Store::default();
    let end = |store: &mut Store, frame: &[u8]| {
        let got = ask(store, frame);
        u16::from_le_bytes([got[9], got[10]])
    };
    // A double word from CN199 would take C200's low word; LCN200 as a word
    // would cut it; D8511 as a double word runs past the last D.
    assert_eq!(end(&mut store, &e3b("1000 0304 0000 00 01 C70000 C5")), 0xC056);
    assert_eq!(end(&mut store, &e3b("1000 0304 0000 01 00 C80000 56")), 0xC056);
    assert_eq!(end(&mut store, &e3b("1000 0304 0000 00 01 3F2100 A8")), 0xC056);
    assert_eq!(end(&mut store, &e3b("1000 0214 0000 00 01 C70000 C5 01000100")), 0xC056);
    assert_eq!(end(&mut store, &e3b("1000 0214 0000 01 00 C80000 56 0100")), 0xC056);
    assert!(store.writes.is_empty());
    // LCN200 as a double word is the counter whole.
    assert_eq!(end(&mut store, &e3b("1000 0214 0000 00 01 C80000 56 78563412")), 0);
    assert_eq!(store.dword(at(Family::CounterValue, 200)), 0x1234_5678);
}

#[test]
fn the_32_bit_counters_are_lcn_in_3e_frames() {
    let mut store = Store::default();
    store.words.insert(at(Family::CounterValue, 200), 0x0001_0002);
    let lcn = hex("5000 00 FF FF03 00 0C00 1000 0104 0000 C80000 56 0100");
    assert_eq!(ask(&mut store, &lcn), hex("D000 00 FF FF03 00 0600 0000 0200 0100"));
    let cn = hex("5000 00 FF FF03 00 0C00 1000 0104 0000 C70000 C5 0200");
    assert_eq!(&ask(&mut store, &cn)[9..11], &hex("56C0")[..]);
}

#[test]
fn a_3e_frame_gets_the_end_code_of_what_is_wrong() {
    let mut store = Store::default();
    let end = |store: &mut Store, frame: &[u8]| {
        let got = ask(store, frame);
        u16::from_le_bytes([got[9], got[10]])
    };
    // Unknown command, unknown subcommand, unknown device code, beyond the
    // last, too many points, bits of a word device, a length that does not
    // match, a coil write.
    assert_eq!(end(&mut store, &hex("5000 00 FF FF03 00 0600 1000 9999 0000")), 0xC059);
    assert_eq!(
        end(
            &mut store,
            &hex("5000 00 FF FF03 00 0C00 1000 0104 0800 000000 A8 0100")
        ),
        0xC059
    );
    assert_eq!(
        end(
            &mut store,
            &hex("5000 00 FF FF03 00 0C00 1000 0104 0000 000000 CC 0100")
        ),
        0xC05B
    );
    assert_eq!(
        end(
            &mut store,
            &hex("5000 00 FF FF03 00 0C00 1000 0104 0000 3F2100 A8 0200")
        ),
        0xC056
    );
    assert_eq!(
        end(
            &mut store,
            &hex("5000 00 FF FF03 00 0C00 1000 0104 0000 000000 A8 C103")
        ),
        0xC051
    );
    assert_eq!(
        end(
            &mut store,
            &hex("5000 00 FF FF03 00 0C00 1000 0104 0100 000000 A8 0100")
        ),
        0xC05C
    );
    assert_eq!(
        end(
            &mut store,
            &hex("5000 00 FF FF03 00 0D00 1000 0104 0000 000000 A8 0100 00")
        ),
        0xC061
    );
    assert_eq!(
        end(
            &mut store,
            &hex("5000 00 FF FF03 00 0D00 1000 0114 0100 000000 C0 0100 10")
        ),
        0xC05B
    );
    assert!(store.writes.is_empty());
}

#[test]
fn headers_that_cannot_be_right_are_invalid() {
    assert_eq!(frame_length(&hex("5000 00 FF FF03 00 0200")), Length::Invalid);
    assert_eq!(frame_length(&hex("5000 00 FF FF03 00 FFFF")), Length::Invalid);
    assert_eq!(frame_length(b"5000 0FF03FF00zz00"), Length::Invalid);
    assert_eq!(frame_length(b"GET / HTTP/1.1"), Length::Invalid);
    assert_eq!(frame_length(&hex("5000 00 FF")), Length::Need(9));
}

#[test]
fn model_and_loopback_in_3e() {
    let mut store = Store::default();
    let got = ask(&mut store, &hex("5000 00 FF FF03 00 0600 1000 0101 0000"));
    assert_eq!(&got[11..27], b"FX3U-LADDERC    ");
    assert_eq!(&got[27..], &[0xF3, 0x00]);
    assert_eq!(ask(&mut store, &e3a("0010 0619 0000 0005 ABCDE")), r3a(0, "0005ABCDE"));
    assert_eq!(
        ask(&mut store, &e3b("1000 1906 0000 0300 414243")),
        r3b(0, "0300 414243")
    );
    assert_eq!(ask(&mut store, &e3b("1000 0210 0000 0100")), r3b(0, ""));
    assert_eq!(ask(&mut store, &e3b("1000 0110 0000 0100 0000")), r3b(0, ""));
    assert_eq!(ask(&mut store, &e3b("1000 0310 0000 0100")), r3b(0, ""));
    assert_eq!(store.remote, [Remote::Stop, Remote::Run, Remote::Pause]);
}

/// A generator seeded from a fixed number (printed on failure), so a
/// failing frame repeats.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

#[test]
fn mutated_frames_of_every_kind_are_answered_or_refused_without_panicking() {
    let valid: Vec<Vec<u8>> = vec![
        hex("00 FF 0A00 64000000 204D 08 00"),
        hex("03 FF 0A00 C8000000 4E43 04 00 01000000 02000000"),
        hex("05 FF 0A00 02 00 10000000 2059 7B29 1A000000 2052 3412"),
        b"01FF000A434E000000DC0400".to_vec(),
        b"16FF000A05ABCDE".to_vec(),
        e3b("1000 0104 0000 640000 A8 0300"),
        e3b("1000 0214 0000 01 01 000000 A8 0100 0A0000 A8 78563412"),
        e3b("1000 0104 0300 0F000000 9C00 0200"),
        e3a("0010 0403 0000 01 01 D* 000000 D* 000010"),
        e3a("0010 1401 0001 M* 000005 0003 101"),
        hex("5400 3412 0000 00 FF FF03 00 0E00 1000 0114 0100 050000 90 0300 1010"),
    ];
    let seed = 0x4D45_4C53_4543;
    let mut random = Random(seed);
    let mut store = Store::default();
    for round in 0..20_000 {
        let mut frame = valid[random.below(valid.len())].clone();
        for _ in 0..=random.below(4) {
            match random.below(4) {
                0 if !frame.is_empty() => {
                    let at = random.below(frame.len());
                    frame[at] = random.next() as u8;
                }
                1 if !frame.is_empty() => frame.truncate(random.below(frame.len())),
                2 => frame.push(random.next() as u8),
                _ => {
                    // A digit or a field edge where ASCII frames have them.
                    let at = random.below(frame.len() + 1);
                    frame.insert(at, b"0F9*"[random.below(4)]);
                }
            }
        }
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            if let Length::Frame(length) = frame_length(&frame) {
                if length <= frame.len() {
                    let _ = answer(&frame[..length], &mut store);
                }
            }
        }));
        assert!(outcome.is_ok(), "seed {seed:#x}, round {round}: {frame:02X?}");
    }
}
