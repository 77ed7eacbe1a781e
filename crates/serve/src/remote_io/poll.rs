//! One tokio task per remote I/O device, with tokio-modbus's client (TCP,
//! or RTU on a serial line): every period it writes the outputs (those
//! changed since its last write, and all of them once per keep-alive),
//! reads every input range and hands the complete poll to the scan thread;
//! between polls, a scan that changed the outputs has them written at
//! once. A failed request is tried again on a new connection up to
//! `retries` times; then the device is lost (status relay OFF, inputs held
//! or cleared) and reconnected with a backoff from `FIRST_BACKOFF`
//! doubling up to `LAST_BACKOFF`.

use super::config::{
    split, Device, InputTable, Link, OutputTable, READ_BITS, READ_REGISTERS, WRITE_BITS, WRITE_REGISTERS,
};
use super::exchange::{Inputs, Outputs, Slot};
use std::future::Future;
use std::sync::Arc;
use std::time::Duration;
use tokio::time::{sleep, sleep_until, timeout, Instant};
use tokio_modbus::client::{Context, Reader, Writer};
use tokio_modbus::Slave;

/// The first wait before connecting to a lost device again.
pub const FIRST_BACKOFF: Duration = Duration::from_millis(100);
/// The longest wait between two attempts.
pub const LAST_BACKOFF: Duration = Duration::from_secs(2);

/// Polls the device, the first time `phase` from now, until the server
/// stops (the runtime drops the task).
pub async fn run(slot: Arc<Slot>, phase: Duration) {
    let device = &slot.device;
    let mut poller = Poller {
        slot: &slot,
        link: None,
        failures: 0,
        backoff: FIRST_BACKOFF,
        inputs: Inputs::sized(device),
        outputs: Outputs::sized(device),
        written: None,
        keepalive_due: Instant::now(),
    };
    let changed = slot.changed.waiter();
    let mut next_poll = Instant::now() + phase;
    loop {
        if poller.link.is_none() {
            match connect(device).await {
                Ok(context) => {
                    poller.link = Some(context);
                    // What the module holds after a reconnection is unknown.
                    poller.written = None;
                }
                Err(error) => {
                    poller.failed(error).await;
                    continue;
                }
            }
        }
        let poll = tokio::select! {
            () = sleep_until(next_poll) => true,
            () = changed.wait() => false,
        };
        let done = if poll {
            poller.cycle().await
        } else {
            poller.write_changed(false).await
        };
        match done {
            Ok(()) => {
                poller.failures = 0;
                poller.backoff = FIRST_BACKOFF;
            }
            Err(error) => {
                poller.link = None;
                poller.failed(error).await;
            }
        }
        if poll {
            next_poll += device.period;
            let now = Instant::now();
            if next_poll < now {
                // Behind (a slow module): the next poll a period from now,
                // not a burst.
                next_poll = now + device.period;
            }
        }
    }
}

/// A poller's state between two polls.
struct Poller<'a> {
    slot: &'a Slot,
    link: Option<Context>,
    /// Failed requests in a row.
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
async fn connect(device: &Device) -> Result<Context, String> {
    let slave = Slave(device.unit);
    match &device.link {
        Link::Tcp(address) => match timeout(
            device.timeout,
            tokio_modbus::client::tcp::connect_slave(*address, slave),
        )
        .await
        {
            Ok(Ok(context)) => Ok(context),
            Ok(Err(error)) => Err(format!("cannot connect to {address}: {error}")),
            Err(_) => Err(format!(
                "cannot connect to {address}: no answer in {} ms",
                device.timeout.as_millis()
            )),
        },
        Link::Rtu { path, format } => super::serial::open(path, *format)
            .map(|line| tokio_modbus::client::rtu::attach_slave(line, slave))
            .map_err(|error| error.to_string()),
    }
}

impl Poller<'_> {
    /// One failure: counted, and when they are more than `retries` in a
    /// row the device is lost and the next attempt waits the backoff.
    async fn failed(&mut self, error: String) {
        self.failures = self.failures.saturating_add(1);
        let lost = self.failures > self.slot.device.retries;
        self.slot.fail(error, lost);
        if lost {
            sleep(self.backoff).await;
            self.backoff = (self.backoff * 2).min(LAST_BACKOFF);
        }
    }

    /// A poll: the outputs written, the inputs read and handed over.
    async fn cycle(&mut self) -> Result<(), String> {
        let keepalive = Instant::now() >= self.keepalive_due;
        self.write_changed(keepalive).await?;
        if keepalive {
            self.keepalive_due = Instant::now() + self.slot.device.keepalive;
        }
        self.read_inputs().await?;
        let errors = self.slot.state().errors;
        self.slot.publish(&self.inputs.bits, &self.inputs.words, errors);
        Ok(())
    }

    /// Writes the outputs that differ from what the module holds (all of
    /// them with `all`), in requests within Modbus's limits.
    async fn write_changed(&mut self, all: bool) -> Result<(), String> {
        let since = if all { u64::MAX } else { self.outputs.generation };
        let taken = self.slot.outputs_since(since, &mut self.outputs);
        if self.outputs.generation == 0 || (!taken && !all && self.written.is_some()) {
            // No scan yet, or nothing new.
            return Ok(());
        }
        let device = &self.slot.device;
        let timeout_of = device.timeout;
        let Some(context) = self.link.as_mut() else {
            return Ok(());
        };
        let (mut bit_at, mut word_at) = (0usize, 0usize);
        for output in &device.outputs {
            match output.table {
                OutputTable::Coils => {
                    for (address, count, offset) in split(output.address, output.count, WRITE_BITS) {
                        let range = bit_at + offset..bit_at + offset + usize::from(count);
                        let values = self.outputs.bits.get(range.clone()).unwrap_or_default();
                        let held = self.written.as_ref().and_then(|w| w.bits.get(range));
                        if all || held != Some(values) {
                            let request = async {
                                if let [value] = values {
                                    context.write_single_coil(address, *value).await
                                } else {
                                    context.write_multiple_coils(address, values).await
                                }
                            };
                            answer(timeout_of, request).await?;
                        }
                    }
                    bit_at += usize::from(output.count);
                }
                OutputTable::HoldingRegisters => {
                    for (address, count, offset) in split(output.address, output.count, WRITE_REGISTERS) {
                        let range = word_at + offset..word_at + offset + usize::from(count);
                        let values = self.outputs.words.get(range.clone()).unwrap_or_default();
                        let held = self.written.as_ref().and_then(|w| w.words.get(range));
                        if all || held != Some(values) {
                            let request = async {
                                if let [value] = values {
                                    context.write_single_register(address, *value).await
                                } else {
                                    context.write_multiple_registers(address, values).await
                                }
                            };
                            answer(timeout_of, request).await?;
                        }
                    }
                    word_at += usize::from(output.count);
                }
            }
        }
        self.written = Some(self.outputs.clone());
        Ok(())
    }

    /// Reads every input range into `inputs`.
    async fn read_inputs(&mut self) -> Result<(), String> {
        let device = &self.slot.device;
        let Some(context) = self.link.as_mut() else {
            return Err("not connected".to_string());
        };
        let (mut bit_at, mut word_at) = (0usize, 0usize);
        for input in &device.inputs {
            match input.table {
                InputTable::DiscreteInputs => {
                    for (address, count, offset) in split(input.address, input.count, READ_BITS) {
                        let values = answer(device.timeout, context.read_discrete_inputs(address, count)).await?;
                        fill(&mut self.inputs.bits, bit_at + offset, &values, count)?;
                    }
                    bit_at += usize::from(input.count);
                }
                InputTable::InputRegisters => {
                    for (address, count, offset) in split(input.address, input.count, READ_REGISTERS) {
                        let values = answer(device.timeout, context.read_input_registers(address, count)).await?;
                        fill(&mut self.inputs.words, word_at + offset, &values, count)?;
                    }
                    word_at += usize::from(input.count);
                }
            }
        }
        Ok(())
    }
}

/// A request's answer within `limit`, or what went wrong as text.
async fn answer<T>(limit: Duration, request: impl Future<Output = tokio_modbus::Result<T>>) -> Result<T, String> {
    match timeout(limit, request).await {
        Ok(Ok(Ok(value))) => Ok(value),
        Ok(Ok(Err(exception))) => Err(format!("exception: {exception}")),
        Ok(Err(error)) => Err(error.to_string()),
        Err(_) => Err(format!("no answer in {} ms", limit.as_millis())),
    }
}

/// Puts the `count` values a read asked for at `at`; fewer is an error
/// (a module that answered short).
fn fill<T: Copy>(target: &mut [T], at: usize, values: &[T], count: u16) -> Result<(), String> {
    let count = usize::from(count);
    let (Some(source), Some(place)) = (values.get(..count), target.get_mut(at..at + count)) else {
        return Err(format!("{} values in an answer to a read of {count}", values.len()));
    };
    place.copy_from_slice(source);
    Ok(())
}
