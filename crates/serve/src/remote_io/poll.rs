//! One tokio task per link (a TCP device, or a serial line and the units
//! on it, RS-485 multi-drop), with tokio-modbus's client: every period of
//! each device it writes that device's outputs (those changed since its
//! last write, and all of them once per keep-alive while the scan thread
//! hands outputs over), reads every input range and hands the complete
//! poll to the scan thread; between polls, a scan that changed the outputs
//! has them written at once. A failed connection or request is tried again
//! at the device's next poll; after more than `retries` failures in a row
//! the device is lost (status relay OFF, inputs held or cleared) and tried
//! again after a backoff from `FIRST_BACKOFF` doubling up to
//! `LAST_BACKOFF`. A TCP connection is made anew after any failure; a
//! serial line is reopened only after an I/O error, and its input is
//! flushed before each request (a late answer is not taken for the next
//! one). When the server stops, every device's outputs are written OFF
//! once (`switch_off`).

use super::config::{
    split, Device, InputTable, Link, OutputTable, READ_BITS, READ_REGISTERS, WRITE_BITS, WRITE_REGISTERS,
};
use super::exchange::{Inputs, Outputs, Slot};
use std::future::Future;
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::watch;
use tokio::time::{sleep_until, timeout, Instant};
use tokio_modbus::client::{Context, Reader, Writer};
use tokio_modbus::slave::SlaveContext;
use tokio_modbus::Slave;

/// The first wait before trying a lost device again.
pub const FIRST_BACKOFF: Duration = Duration::from_millis(100);
/// The longest wait between two attempts.
pub const LAST_BACKOFF: Duration = Duration::from_secs(2);

/// Polls the devices of one link, device k the first time `phases[k]`
/// from now, until `stop` turns true (or its sender is gone); then writes
/// their outputs OFF.
pub async fn run(slots: Vec<Arc<Slot>>, phases: Vec<Duration>, mut stop: watch::Receiver<bool>) {
    let Some(first) = slots.first() else {
        return;
    };
    let changed = first.changed.waiter();
    let start = Instant::now();
    let mut units: Vec<Unit> = slots
        .into_iter()
        .zip(phases)
        .map(|(slot, phase)| Unit::new(slot, start + phase))
        .collect();
    let mut link: Option<Connection> = None;
    loop {
        let due = units.iter().map(|unit| unit.next).min().unwrap_or(start);
        tokio::select! {
            () = sleep_until(due) => {}
            () = changed.wait() => {}
            _ = stop.wait_for(|stopping| *stopping) => break,
        }
        for unit in &mut units {
            unit.step(&mut link).await;
        }
    }
    switch_off(&mut units, &mut link).await;
}

/// An open link: tokio-modbus's client, and for a serial line what
/// flushes its input.
struct Connection {
    context: Context,
    drain: Option<super::serial::Drain>,
}

impl Connection {
    /// Before a request: a serial line's unread input (a late answer to a
    /// request that timed out) discarded.
    fn ready(&mut self, unit: u8) -> &mut Context {
        if let Some(drain) = &self.drain {
            drain.flush_input();
        }
        self.context.set_slave(Slave(unit));
        &mut self.context
    }
}

/// A failed request or connection attempt.
struct Failure {
    text: String,
    /// Whether the link is to be made anew (TCP: always; a serial line:
    /// after an I/O error only, not after a timeout or an exception).
    reopen: bool,
}

/// One device's state between two polls.
struct Unit {
    slot: Arc<Slot>,
    /// When it is polled next (or tried again, lost).
    next: Instant,
    /// Failed requests and connection attempts in a row.
    failures: u32,
    backoff: Duration,
    /// This poll's inputs, handed over whole when complete.
    inputs: Inputs,
    /// The outputs the latest scan produced, as last taken.
    outputs: Outputs,
    /// What the module holds as far as this poller wrote it (None: unknown).
    written: Option<Outputs>,
    keepalive_due: Instant,
}

/// A new connection to the device (TCP within its timeout, or its serial
/// line opened).
async fn connect(device: &Device) -> Result<Connection, String> {
    let slave = Slave(device.unit);
    match &device.link {
        Link::Tcp(address) => match timeout(
            device.timeout,
            tokio_modbus::client::tcp::connect_slave(*address, slave),
        )
        .await
        {
            Ok(Ok(context)) => Ok(Connection { context, drain: None }),
            Ok(Err(error)) => Err(format!("cannot connect to {address}: {error}")),
            Err(_) => Err(format!(
                "cannot connect to {address}: no answer in {} ms",
                device.timeout.as_millis()
            )),
        },
        Link::Rtu { path, format } => super::serial::open(path, *format)
            .map(|line| {
                let drain = super::serial::drain_of(&line);
                Connection {
                    context: tokio_modbus::client::rtu::attach_slave(line, slave),
                    drain,
                }
            })
            .map_err(|error| error.to_string()),
    }
}

impl Unit {
    fn new(slot: Arc<Slot>, first: Instant) -> Unit {
        let device = &slot.device;
        Unit {
            next: first,
            failures: 0,
            backoff: FIRST_BACKOFF,
            inputs: Inputs::sized(device),
            outputs: Outputs::sized(device),
            written: None,
            keepalive_due: first,
            slot,
        }
    }

    /// A poll when one is due, else the changed outputs written when the
    /// device answers (a failing device waits for its next poll).
    async fn step(&mut self, link: &mut Option<Connection>) {
        let now = Instant::now();
        let poll = self.next <= now;
        if !poll && (link.is_none() || self.failures > 0) {
            return;
        }
        if poll {
            self.next += self.slot.device.period;
            if self.next < now {
                // Behind (a slow module): the next poll a period from now,
                // not a burst.
                self.next = now + self.slot.device.period;
            }
        }
        if link.is_none() {
            match connect(&self.slot.device).await {
                Ok(connection) => *link = Some(connection),
                Err(text) => {
                    self.failed(Failure { text, reopen: true }, now);
                    return;
                }
            }
        }
        let Some(connection) = link.as_mut() else {
            return;
        };
        let done = if poll {
            self.cycle(connection).await
        } else {
            self.write_changed(connection, false).await
        };
        match done {
            Ok(()) => {
                self.failures = 0;
                self.backoff = FIRST_BACKOFF;
            }
            Err(failure) => {
                if failure.reopen {
                    *link = None;
                }
                self.failed(failure, now);
            }
        }
    }

    /// One failure: counted, what the module holds unknown, and when they
    /// are more than `retries` in a row the device is lost and tried again
    /// after the backoff (else at its next poll).
    fn failed(&mut self, failure: Failure, now: Instant) {
        self.failures = self.failures.saturating_add(1);
        self.written = None;
        let lost = self.failures > self.slot.device.retries;
        self.slot.fail(failure.text, lost);
        if lost {
            self.next = self.next.max(now + self.backoff);
            self.backoff = (self.backoff * 2).min(LAST_BACKOFF);
        }
    }

    /// A poll: the outputs written, the inputs read and handed over.
    async fn cycle(&mut self, connection: &mut Connection) -> Result<(), Failure> {
        let now = Instant::now();
        // No keep-alive from a stalled scan thread: a module's watchdog
        // then turns its outputs off, as it would for a silent master.
        let keepalive = now >= self.keepalive_due && self.slot.beat.alive();
        self.write_changed(connection, keepalive).await?;
        if keepalive {
            self.keepalive_due = now + self.slot.device.keepalive;
        }
        self.read_inputs(connection).await?;
        let errors = self.slot.state().errors;
        self.slot.publish(&self.inputs.bits, &self.inputs.words, errors);
        Ok(())
    }

    /// Writes the outputs that differ from what the module holds (all of
    /// them with `all`).
    async fn write_changed(&mut self, connection: &mut Connection, all: bool) -> Result<(), Failure> {
        let since = if all { u64::MAX } else { self.outputs.generation };
        let taken = self.slot.outputs_since(since, &mut self.outputs);
        if self.outputs.generation == 0 || (!taken && !all && self.written.is_some()) {
            // No scan yet, or nothing new.
            return Ok(());
        }
        let held = if all { None } else { self.written.as_ref() };
        write(connection, &self.slot.device, &self.outputs, held).await?;
        self.written = Some(self.outputs.clone());
        Ok(())
    }

    /// Reads every input range into `inputs`.
    async fn read_inputs(&mut self, connection: &mut Connection) -> Result<(), Failure> {
        let device = &self.slot.device;
        let tcp = matches!(device.link, Link::Tcp(_));
        let (mut bit_at, mut word_at) = (0usize, 0usize);
        for input in &device.inputs {
            match input.table {
                InputTable::DiscreteInputs => {
                    for (address, count, offset) in split(input.address, input.count, READ_BITS) {
                        let context = connection.ready(device.unit);
                        let values = answer(device.timeout, tcp, context.read_discrete_inputs(address, count)).await?;
                        fill(&mut self.inputs.bits, bit_at + offset, &values, count)?;
                    }
                    bit_at += usize::from(input.count);
                }
                InputTable::InputRegisters => {
                    for (address, count, offset) in split(input.address, input.count, READ_REGISTERS) {
                        let context = connection.ready(device.unit);
                        let values = answer(device.timeout, tcp, context.read_input_registers(address, count)).await?;
                        fill(&mut self.inputs.words, word_at + offset, &values, count)?;
                    }
                    word_at += usize::from(input.count);
                }
            }
        }
        Ok(())
    }
}

/// Writes `values` to the device's output ranges, in requests within
/// Modbus's limits; with `held` (what the module holds), only the
/// requests whose values differ.
async fn write(
    connection: &mut Connection,
    device: &Device,
    values: &Outputs,
    held: Option<&Outputs>,
) -> Result<(), Failure> {
    let tcp = matches!(device.link, Link::Tcp(_));
    let (mut bit_at, mut word_at) = (0usize, 0usize);
    for output in &device.outputs {
        match output.table {
            OutputTable::Coils => {
                for (address, count, offset) in split(output.address, output.count, WRITE_BITS) {
                    let range = bit_at + offset..bit_at + offset + usize::from(count);
                    let new = values.bits.get(range.clone()).unwrap_or_default();
                    if held.and_then(|h| h.bits.get(range)) != Some(new) {
                        let context = connection.ready(device.unit);
                        let request = async {
                            if let [value] = new {
                                context.write_single_coil(address, *value).await
                            } else {
                                context.write_multiple_coils(address, new).await
                            }
                        };
                        answer(device.timeout, tcp, request).await?;
                    }
                }
                bit_at += usize::from(output.count);
            }
            OutputTable::HoldingRegisters => {
                for (address, count, offset) in split(output.address, output.count, WRITE_REGISTERS) {
                    let range = word_at + offset..word_at + offset + usize::from(count);
                    let new = values.words.get(range.clone()).unwrap_or_default();
                    if held.and_then(|h| h.words.get(range)) != Some(new) {
                        let context = connection.ready(device.unit);
                        let request = async {
                            if let [value] = new {
                                context.write_single_register(address, *value).await
                            } else {
                                context.write_multiple_registers(address, new).await
                            }
                        };
                        answer(device.timeout, tcp, request).await?;
                    }
                }
                word_at += usize::from(output.count);
            }
        }
    }
    Ok(())
}

/// The server stops: every device's outputs written OFF (coils OFF,
/// holding registers 0) once, each within its timeout (connecting first
/// when its link is down), so a module without a watchdog does not keep
/// driving the machine.
async fn switch_off(units: &mut [Unit], link: &mut Option<Connection>) {
    for unit in units.iter_mut() {
        let device = &unit.slot.device;
        if device.outputs.is_empty() {
            continue;
        }
        let off = Outputs {
            generation: 1,
            ..Outputs::sized(device)
        };
        let once = async {
            if link.is_none() {
                *link = connect(device).await.ok();
            }
            if let Some(connection) = link.as_mut() {
                if let Err(failure) = write(connection, device, &off, None).await {
                    if failure.reopen {
                        *link = None;
                    }
                }
            }
        };
        if timeout(device.timeout, once).await.is_err() {
            // Cut short within a request: the link is in an unknown state.
            *link = None;
        }
    }
}

/// A request's answer within `limit`, or what went wrong; `tcp` says a
/// timeout makes the connection anew (a serial line is kept: its input is
/// flushed before the next request).
async fn answer<T>(
    limit: Duration,
    tcp: bool,
    request: impl Future<Output = tokio_modbus::Result<T>>,
) -> Result<T, Failure> {
    match timeout(limit, request).await {
        Ok(Ok(Ok(value))) => Ok(value),
        Ok(Ok(Err(exception))) => Err(Failure {
            text: format!("exception: {exception}"),
            reopen: false,
        }),
        Ok(Err(error @ tokio_modbus::Error::Transport(_))) => Err(Failure {
            text: error.to_string(),
            reopen: true,
        }),
        // An answer that does not fit the request (a late one on a serial
        // line): the line itself works.
        Ok(Err(error @ tokio_modbus::Error::Protocol(_))) => Err(Failure {
            text: error.to_string(),
            reopen: tcp,
        }),
        Err(_) => Err(Failure {
            text: format!("no answer in {} ms", limit.as_millis()),
            reopen: tcp,
        }),
    }
}

/// Puts the `count` values a read asked for at `at`; fewer is an error
/// (a module that answered short).
fn fill<T: Copy>(target: &mut [T], at: usize, values: &[T], count: u16) -> Result<(), Failure> {
    let count = usize::from(count);
    let (Some(source), Some(place)) = (values.get(..count), target.get_mut(at..at + count)) else {
        return Err(Failure {
            text: format!("{} values in an answer to a read of {count}", values.len()),
            reopen: false,
        });
    };
    place.copy_from_slice(source);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::config::parse;
    use super::super::exchange::Exchange;
    use super::*;
    use std::io::{Read, Write};
    use std::sync::atomic::{AtomicU32, Ordering};

    /// A Modbus TCP module that answers function 05 (write single coil,
    /// whose answer echoes the request) and counts the requests.
    fn coil_module(requests: Arc<AtomicU32>) -> std::net::SocketAddr {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap();
        std::thread::spawn(move || {
            for mut stream in listener.incoming().map_while(Result::ok) {
                let requests = Arc::clone(&requests);
                std::thread::spawn(move || {
                    // MBAP header: transaction, protocol, length, unit.
                    let mut header = [0u8; 7];
                    while stream.read_exact(&mut header).is_ok() {
                        let length = usize::from(u16::from_be_bytes([header[4], header[5]]));
                        let mut pdu = vec![0u8; length.saturating_sub(1)];
                        if stream.read_exact(&mut pdu).is_err() {
                            return;
                        }
                        requests.fetch_add(1, Ordering::SeqCst);
                        let _ = stream.write_all(&header).and_then(|()| stream.write_all(&pdu));
                    }
                });
            }
        });
        address
    }

    #[test]
    fn keep_alives_stop_while_the_scan_thread_hands_no_outputs_over() {
        let requests = Arc::new(AtomicU32::new(0));
        let address = coil_module(Arc::clone(&requests));
        let io = parse(&format!(
            "[[device]]\ntcp = \"{address}\"\nperiod_ms = 20\n\
             [[device.output]]\ncoils = 0\ncount = 1\nfrom = \"Y0\"\n"
        ))
        .unwrap();
        // Scans every 10 ms: stalled after 30 ms without a hand-off.
        let exchange = Exchange::new(&io.devices, Duration::from_millis(10));
        let memory = ladder_runtime::Memory::new_boxed();
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let (stop, stopped) = watch::channel(false);
        let task = runtime.spawn(run(exchange.links().remove(0), vec![Duration::ZERO], stopped));
        // One scan, then none: the first write and at most a keep-alive.
        exchange.from_image(&memory);
        runtime.block_on(async { tokio::time::sleep(Duration::from_millis(60)).await });
        let first = requests.load(Ordering::SeqCst);
        runtime.block_on(async { tokio::time::sleep(Duration::from_millis(300)).await });
        let stalled = requests.load(Ordering::SeqCst) - first;
        // Scans every 10 ms again: a keep-alive every 20 ms poll.
        runtime.block_on(async {
            for _ in 0..30 {
                exchange.from_image(&memory);
                tokio::time::sleep(Duration::from_millis(10)).await;
            }
        });
        let beating = requests.load(Ordering::SeqCst) - first - stalled;
        assert!(first >= 1, "the first outputs written");
        assert_eq!(stalled, 0, "no keep-alive in 300 ms without a scan");
        assert!(beating >= 5, "{beating} keep-alives in 300 ms of scans");
        stop.send(true).unwrap();
        let ended = runtime.block_on(async { tokio::time::timeout(Duration::from_secs(2), task).await });
        assert!(ended.is_ok(), "the poller ends when told to stop");
        // Once (a keep-alive may have been under way when counted).
        let at_stop = requests.load(Ordering::SeqCst) - first - stalled - beating;
        assert!((1..=2).contains(&at_stop), "{at_stop}: the outputs written OFF at stop");
    }

    #[test]
    fn a_refused_connection_is_tried_again_at_the_next_poll_not_at_once() {
        // A port nobody listens on: every connection is refused at once.
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let io = parse(&format!(
            "[[device]]\ntcp = \"127.0.0.1:{port}\"\nperiod_ms = 50\nretries = 100\n\
             [[device.output]]\ncoils = 0\ncount = 1\nfrom = \"Y0\"\n"
        ))
        .unwrap();
        let exchange = Exchange::new(&io.devices, Duration::from_millis(10));
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let (stop, stopped) = watch::channel(false);
        let slots = exchange.links().remove(0);
        let task = runtime.spawn(run(slots, vec![Duration::ZERO], stopped));
        runtime.block_on(async { tokio::time::sleep(Duration::from_millis(320)).await });
        let errors = exchange.slots[0].state().errors;
        // Attempts at 0, 50, ... 300 ms: 7 (before, up to 101 at once).
        assert!((4..=9).contains(&errors), "{errors} errors in 320 ms");
        stop.send(true).unwrap();
        let ended = runtime.block_on(async { tokio::time::timeout(Duration::from_secs(2), task).await });
        assert!(ended.is_ok(), "the poller ends when told to stop");
    }
}
