//! `ladderc serve --melsec` with frames written by hand from the manuals,
//! on the real binary: what one frame kind writes the program sees and
//! every other protocol reads back; remote STOP and RUN; the access rules;
//! and frames that are malformed, cut short, or idle connections by the
//! hundred, none of which stops the server answering; every frame kind's
//! write read back at once (answered once applied); over UDP a write
//! waiting for a scan's end holds up no other peer, and one peer's
//! datagrams are answered in order.

use crate::common::server::{modbus_connect, modbus_request, slow_program, Server};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

/// A seal-in (X0 sets Y0, X1 resets it), D101 follows D100, Y7 follows M5,
/// D0 counts scans.
const PROGRAM: &str = "LD X0\nOR Y0\nANI X1\nOUT Y0\nLD M8000\nMOV D100 D101\nLD M5\nOUT Y7\nLD M8000\nINC D0\n";

fn start(extra: &[&str]) -> (Server, SocketAddr) {
    let mut args = vec!["--melsec", "127.0.0.1:0"];
    args.extend_from_slice(extra);
    let server = Server::start_program(PROGRAM, &args);
    let melsec = server.melsec.expect("a MELSEC address");
    (server, melsec)
}

fn connect(address: SocketAddr) -> TcpStream {
    let stream = TcpStream::connect(address).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    stream
}

fn hex(text: &str) -> Vec<u8> {
    let digits: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    digits
        .chunks(2)
        .map(|pair| u8::from_str_radix(std::str::from_utf8(pair).unwrap(), 16).unwrap())
        .collect()
}

/// A binary 3E request to this PLC with `body` (timer, command,
/// subcommand, data).
fn e3(body: &str) -> Vec<u8> {
    let body = hex(body);
    let mut frame = hex("5000 00 FF FF03 00");
    frame.extend((body.len() as u16).to_le_bytes());
    frame.extend(body);
    frame
}

/// Sends a binary 3E request; the end code and the data of its response.
fn ask_3e(stream: &mut TcpStream, body: &str) -> (u16, Vec<u8>) {
    stream.write_all(&e3(body)).unwrap();
    let mut header = [0u8; 9];
    stream.read_exact(&mut header).expect("a 3E response header");
    assert_eq!(&header[..7], &hex("D000 00 FF FF03 00")[..], "{header:02X?}");
    let mut rest = vec![0u8; usize::from(u16::from_le_bytes([header[7], header[8]]))];
    stream.read_exact(&mut rest).expect("the response data");
    (u16::from_le_bytes([rest[0], rest[1]]), rest[2..].to_vec())
}

/// Sends a 1E request and reads `answer_len` bytes of its response.
fn ask_1e(stream: &mut TcpStream, frame: &[u8], answer_len: usize) -> Vec<u8> {
    stream.write_all(frame).unwrap();
    let mut answer = vec![0u8; answer_len];
    stream.read_exact(&mut answer).expect("a 1E response");
    answer
}

/// D`n` read with a 3E batch read.
fn read_d(stream: &mut TcpStream, n: u32) -> i16 {
    let [a, b, c, _] = n.to_le_bytes();
    let (end, data) = ask_3e(stream, &format!("1000 0104 0000 {a:02X}{b:02X}{c:02X} A8 0100"));
    assert_eq!(end, 0);
    i16::from_le_bytes([data[0], data[1]])
}

/// Y0-Y7 read with a 1E batch read in bit units: one nibble a point.
fn read_y(stream: &mut TcpStream) -> [bool; 8] {
    let answer = ask_1e(stream, &hex("00 FF 0A00 00000000 2059 08 00"), 6);
    assert_eq!(&answer[..2], &[0x80, 0x00]);
    let nibbles: Vec<bool> = answer[2..].iter().flat_map(|b| [b >> 4 == 1, b & 0xF == 1]).collect();
    nibbles.try_into().unwrap()
}

/// Waits until `check` holds (for a scan or two to run), up to 5 s.
fn eventually(what: &str, mut check: impl FnMut() -> bool) {
    let deadline = Instant::now() + Duration::from_secs(5);
    while !check() {
        assert!(Instant::now() < deadline, "{what}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn what_one_frame_kind_writes_the_program_sees_and_every_protocol_reads_back() {
    let (_server, melsec) = start(&["--melsec-udp"]);
    let mut stream = connect(melsec);
    // 3E binary: D100 = 1234.
    assert_eq!(ask_3e(&mut stream, "1000 0114 0000 640000 A8 0100 D204").0, 0);
    // The program copies it to D101; 1E ASCII reads D101.
    eventually("D101 = 1234 over 1E ASCII", || {
        let answer = ask_1e(&mut stream, b"01FF000A4420000000650100", 8);
        answer == b"810004D2"
    });
    // Modbus holding register 101 is D101.
    let mut modbus = modbus_connect(_server.address);
    assert_eq!(
        modbus_request(&mut modbus, &[0x03, 0, 101, 0, 1]),
        [0x03, 2, 0x04, 0xD2]
    );
    // 4E ASCII: M5 ON (bit units); Y7 follows through the program, read
    // over 1E binary, 3E ASCII and Modbus coil 7.
    let body = "001014010001M*00000500011";
    let frame = format!("54001234000000FF03FF00{:04X}{body}", body.len());
    stream.write_all(frame.as_bytes()).unwrap();
    let mut answer = [0u8; 30];
    stream.read_exact(&mut answer).unwrap();
    assert_eq!(&answer, b"D4001234000000FF03FF0000040000");
    eventually("Y7 ON", || read_y(&mut stream)[7]);
    let body = "001004010001Y*0000000008";
    stream
        .write_all(format!("500000FF03FF00{:04X}{body}", body.len()).as_bytes())
        .unwrap();
    let mut answer = [0u8; 22 + 8];
    stream.read_exact(&mut answer).unwrap();
    assert_eq!(&answer[..], b"D00000FF03FF00000C000000000001");
    assert_eq!(modbus_request(&mut modbus, &[0x01, 0, 7, 0, 1]), [0x01, 1, 1]);
    // And a Modbus write is read over MELSEC.
    assert_eq!(modbus_request(&mut modbus, &[0x06, 0, 100, 0xFF, 0xFE])[0], 0x06);
    eventually("D101 = -2", || read_d(&mut stream, 101) == -2);
    // UDP on the same port (--melsec-udp): one frame a datagram.
    let udp = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    udp.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    udp.send_to(&e3("1000 0104 0000 650000 A8 0100"), melsec).unwrap();
    let mut datagram = [0u8; 64];
    let n = udp.recv(&mut datagram).expect("a UDP answer");
    assert_eq!(&datagram[..n], &hex("D000 00 FF FF03 00 0400 0000 FEFF")[..]);
}

#[test]
fn udp_is_answered_only_when_asked_for() {
    let (_server, melsec) = start(&[]);
    let udp = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    udp.set_read_timeout(Some(Duration::from_millis(500))).unwrap();
    udp.send_to(&e3("1000 0104 0000 000000 A8 0100"), melsec).unwrap();
    let mut datagram = [0u8; 64];
    assert!(udp.recv(&mut datagram).is_err(), "no UDP without --melsec-udp");
    // TCP answers all the same.
    let mut stream = connect(melsec);
    eventually("scanning", || read_d(&mut stream, 0) > 0);
}

#[test]
fn a_frame_that_trickles_in_is_closed_after_the_frame_time() {
    let (_server, melsec) = start(&[]);
    let mut slow = connect(melsec);
    let frame = e3("1000 0104 0000 000000 A8 0100");
    // A byte every 2 s: each read comes well within 5 s, the frame never.
    let started = Instant::now();
    for byte in &frame[..5] {
        if slow.write_all(std::slice::from_ref(byte)).is_err() {
            break;
        }
        if closed_within(&mut slow, Duration::from_secs(2)) {
            break;
        }
    }
    assert!(closed_within(&mut slow, Duration::from_secs(3)), "closed");
    assert!(
        started.elapsed() < Duration::from_secs(9),
        "within the frame time: {:?}",
        started.elapsed()
    );
}

#[test]
fn remote_stop_turns_the_outputs_off_and_remote_run_resumes() {
    let (_server, melsec) = start(&[]);
    let mut stream = connect(melsec);
    // X0 ON in the input image (1E random write, bit units): Y0 seals in.
    assert_eq!(
        ask_1e(&mut stream, &hex("04 FF 0A00 01 00 00000000 2058 01"), 2),
        [0x84, 0]
    );
    eventually("Y0 ON", || read_y(&mut stream)[0]);
    // 3E remote STOP: outputs OFF, no more scans.
    assert_eq!(ask_3e(&mut stream, "1000 0210 0000 0100").0, 0);
    eventually("Y0 OFF in STOP", || !read_y(&mut stream)[0]);
    let stopped = read_d(&mut stream, 0);
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(read_d(&mut stream, 0), stopped, "no scans in STOP");
    // 1E remote RUN: scans again, X0 still ON seals Y0 in again.
    assert_eq!(ask_1e(&mut stream, &hex("13 FF 0A00"), 2), [0x93, 0]);
    eventually("Y0 ON after RUN", || read_y(&mut stream)[0]);
    // PAUSE (3E 1003) stops the scans too; RUN ends it.
    assert_eq!(ask_3e(&mut stream, "1000 0310 0000 0100").0, 0);
    let paused = read_d(&mut stream, 0);
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(read_d(&mut stream, 0), paused, "no scans while paused");
    assert_eq!(ask_3e(&mut stream, "1000 0110 0000 0100 0000").0, 0);
    eventually("scans after RUN", || read_d(&mut stream, 0) != paused);
}

#[test]
fn read_only_and_remote_peers_get_the_refusal_end_codes() {
    let (_server, melsec) = start(&["--read-only"]);
    let mut stream = connect(melsec);
    assert_eq!(ask_3e(&mut stream, "1000 0114 0000 640000 A8 0100 D204").0, 0xC05F);
    assert_eq!(ask_3e(&mut stream, "1000 0210 0000 0100").0, 0xC05F, "remote STOP");
    assert_eq!(
        ask_1e(&mut stream, &hex("03 FF 0A00 64000000 2044 01 00 D204"), 2),
        [0x83, 0x55]
    );
    assert_eq!(ask_1e(&mut stream, &hex("14 FF 0A00"), 2), [0x94, 0x55]);
    // Reads still answer, and nothing was written.
    assert_eq!(read_d(&mut stream, 100), 0);
    eventually("scanning", || read_d(&mut stream, 0) > 0);
}

/// Whether the server closed `stream` within `within`.
fn closed_within(stream: &mut TcpStream, within: Duration) -> bool {
    stream.set_read_timeout(Some(within)).unwrap();
    let mut buffer = [0u8; 64];
    loop {
        match stream.read(&mut buffer) {
            Ok(0) => return true,
            Ok(_) => continue,
            Err(e) => return !matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut),
        }
    }
}

#[test]
fn malformed_frames_cost_only_their_connection() {
    let (_server, melsec) = start(&[]);
    // Errors the frame can carry are answered and the connection stays:
    // an unknown 3E command, an unknown 1E command, a device beyond the last.
    let mut stream = connect(melsec);
    assert_eq!(ask_3e(&mut stream, "1000 9999 0000").0, 0xC059);
    assert_eq!(ask_1e(&mut stream, &hex("17 FF 0A00"), 2), [0x97, 0x50]);
    assert_eq!(ask_3e(&mut stream, "1000 0104 0000 3F2100 A8 0200").0, 0xC056);
    eventually("scanning", || read_d(&mut stream, 0) > 0);
    // What cannot be a frame closes its connection at once: text, a 3E
    // header whose length cannot be right.
    for garbage in [&b"GET / HTTP/1.1\r\n\r\n"[..], &hex("5000 00 FF FF03 00 FFFF")[..]] {
        let mut bad = connect(melsec);
        bad.write_all(garbage).unwrap();
        assert!(closed_within(&mut bad, Duration::from_secs(3)), "{garbage:02X?}");
    }
    // A frame cut short is closed when it has not come whole in 5 s.
    let mut cut = connect(melsec);
    cut.write_all(&e3("1000 0104 0000 000000 A8 0100")[..12]).unwrap();
    assert!(
        !closed_within(&mut cut, Duration::from_millis(500)),
        "waits for the rest"
    );
    assert!(
        closed_within(&mut cut, Duration::from_secs(8)),
        "closed after the frame timeout"
    );
    // Through all of it, the first connection is served.
    assert!(read_d(&mut stream, 0) > 0);
}

#[test]
fn a_hundred_idle_connections_leave_the_server_answering() {
    let (_server, melsec) = start(&["--max-melsec-connections", "64"]);
    let idle: Vec<TcpStream> = (0..100).filter_map(|_| TcpStream::connect(melsec).ok()).collect();
    assert_eq!(idle.len(), 100, "every connection is accepted or closed, none refused");
    // The longest idle yields its place after a second.
    std::thread::sleep(Duration::from_millis(1200));
    let mut stream = connect(melsec);
    eventually("scanning", || read_d(&mut stream, 0) > 0);
    drop(idle);
}

/// Each frame kind and transport, at `--scan-ms 100`: a write of D300 is
/// answered once applied, so the read right after it sees it, 1,000 times
/// each (3E binary over TCP and UDP, 1E binary, 4E ASCII) in well under
/// the 400 s that waiting a period for every write would take.
#[test]
fn every_frame_kind_reads_back_its_write_at_once() {
    let (_server, melsec) = start(&["--melsec-udp", "--scan-ms", "100"]);
    let mut stream = connect(melsec);
    let udp = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    udp.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let over_udp = |frame: &[u8]| -> Vec<u8> {
        udp.send_to(frame, melsec).unwrap();
        let mut datagram = [0u8; 64];
        let n = udp.recv(&mut datagram).expect("a UDP answer");
        datagram[..n].to_vec()
    };
    let began = Instant::now();
    let mut misses = Vec::new();
    for i in 0..1000u16 {
        let value = (i.wrapping_mul(7919) % 30_000) as i16;
        let [low, high] = value.to_le_bytes();
        // 3E binary over TCP.
        let (end, _) = ask_3e(
            &mut stream,
            &format!("1000 0114 0000 2C0100 A8 0100 {low:02X}{high:02X}"),
        );
        assert_eq!(end, 0);
        if read_d(&mut stream, 300) != value {
            misses.push(("3E", i));
        }
        // 3E binary over UDP.
        let value = value.wrapping_add(1);
        let [low, high] = value.to_le_bytes();
        let answer = over_udp(&e3(&format!("1000 0114 0000 2C0100 A8 0100 {low:02X}{high:02X}")));
        assert_eq!(answer, hex("D000 00 FF FF03 00 0200 0000"));
        let answer = over_udp(&e3("1000 0104 0000 2C0100 A8 0100"));
        if answer[answer.len() - 2..] != [low, high] {
            misses.push(("3E UDP", i));
        }
        // 1E binary.
        let value = value.wrapping_add(1);
        let [low, high] = value.to_le_bytes();
        let mut write = hex("03 FF 0A00 2C010000 2044 01 00");
        write.extend([low, high]);
        assert_eq!(ask_1e(&mut stream, &write, 2), [0x83, 0x00]);
        let answer = ask_1e(&mut stream, &hex("01 FF 0A00 2C010000 2044 01 00"), 4);
        if answer != [0x81, 0x00, low, high] {
            misses.push(("1E", i));
        }
        // 4E ASCII.
        let value = value.wrapping_add(1);
        let body = format!("001014010000D*0003000001{:04X}", value as u16);
        let frame = format!("54001234000000FF03FF00{:04X}{body}", body.len());
        stream.write_all(frame.as_bytes()).unwrap();
        let mut answer = [0u8; 30];
        stream.read_exact(&mut answer).unwrap();
        assert_eq!(&answer, b"D4001234000000FF03FF0000040000");
        let body = "001004010000D*0003000001";
        stream
            .write_all(format!("54001234000000FF03FF00{:04X}{body}", body.len()).as_bytes())
            .unwrap();
        let mut answer = [0u8; 34];
        stream.read_exact(&mut answer).unwrap();
        if answer[30..] != *format!("{:04X}", value as u16).as_bytes() {
            misses.push(("4E", i));
        }
    }
    let took = began.elapsed();
    println!("4,000 MELSEC write-then-read pairs in {took:?}");
    assert_eq!(misses, [], "reads that missed their write");
    assert!(took < Duration::from_secs(40), "{took:?}");
}

/// Over UDP, a write waits for the end of the scan in progress, and holds
/// up no other peer: with scans back to back of some 50 ms, a write from
/// one peer and then a read from another, 20 times, the read is answered
/// first (at once) most times. (The datagrams were once answered in turn,
/// the read only after the write.) A peer's own datagrams keep their
/// order: a read sent right after its write, without waiting, sees it.
#[test]
fn a_udp_write_waiting_for_a_scan_holds_up_no_other_peer() {
    let program = slow_program(Duration::from_millis(50));
    let server = Server::start_program(
        &program,
        &[
            "--melsec",
            "127.0.0.1:0",
            "--melsec-udp",
            "--scan-ms",
            "10",
            "--engine",
            "interp",
        ],
    );
    let melsec = server.melsec.expect("a MELSEC address");
    let socket = || {
        let udp = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
        udp.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        udp
    };
    let (writer, reader) = (socket(), socket());
    let write_d100 = |value: i16| {
        let [low, high] = value.to_le_bytes();
        e3(&format!("1000 0114 0000 640000 A8 0100 {low:02X}{high:02X}"))
    };
    let read_d100 = e3("1000 0104 0000 640000 A8 0100");
    let mut datagram = [0u8; 64];
    let mut reads_first = 0;
    for round in 1..=20i16 {
        writer.send_to(&write_d100(round), melsec).unwrap();
        reader.send_to(&read_d100, melsec).unwrap();
        let n = reader
            .recv(&mut datagram)
            .unwrap_or_else(|e| panic!("round {round}: the read is answered: {e}"));
        assert_eq!(datagram[9..11], [0, 0], "{:02X?}", &datagram[..n]);
        // Not answered yet, the write waits for the scan's end.
        writer.set_nonblocking(true).unwrap();
        let answered = writer.recv(&mut datagram);
        writer.set_nonblocking(false).unwrap();
        let n = answered.or_else(|_| {
            reads_first += 1;
            writer.recv(&mut datagram)
        });
        let n = n.expect("the write is answered");
        assert_eq!(&datagram[..n], &hex("D000 00 FF FF03 00 0200 0000")[..]);
        // The same peer: its write, then its read, sent at once.
        writer.send_to(&write_d100(-round), melsec).unwrap();
        writer.send_to(&read_d100, melsec).unwrap();
        let n = writer.recv(&mut datagram).expect("the write is answered");
        assert_eq!(
            &datagram[..n],
            &hex("D000 00 FF FF03 00 0200 0000")[..],
            "the write first"
        );
        let n = writer.recv(&mut datagram).expect("the read is answered");
        let [low, high] = (-round).to_le_bytes();
        assert_eq!(&datagram[n - 2..n], &[low, high], "the read after it sees it");
    }
    println!("{reads_first} of 20 reads answered while another peer's write waited");
    assert!(reads_first >= 10, "{reads_first} of 20");
}
