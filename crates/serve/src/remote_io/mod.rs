//! Remote I/O (`serve --io FILE`): Modbus TCP and RTU modules polled
//! asynchronously as the soft PLC's X inputs and Y outputs, as OpenPLC's
//! "slave devices" are. `config.rs` reads the file, `poll.rs` is one task
//! per link (a TCP device, or a serial line and its units; `serial.rs`
//! the line), `exchange.rs` the handoff to the scan thread (`wake.rs` its
//! lock-free wake-up of a poller). This file starts and stops the
//! pollers, holds the scan thread's two calls (inputs before a scan,
//! outputs after it), checks the file against the program and the other
//! serial server, and reports the devices' state to the JSON API.

mod config;
mod exchange;
mod poll;
mod serial;
mod wake;

pub use config::{load, parse, OnLoss, RemoteIo};
pub use exchange::Exchange;

use crate::shared::{HostWrite, Shared};
use config::{name_of, InputTable, Link};
use ladder_engine::Engine;
use ladder_runtime::{BitArea, Device as Place, Memory, Width, WordArea};
use serde_json::{json, Value};
use std::sync::Arc;

/// The running pollers, to stop when the server stops.
pub struct Pollers {
    stop: tokio::sync::watch::Sender<bool>,
    tasks: Vec<tokio::task::JoinHandle<()>>,
    /// How long their last writes may take: per link, a request under way
    /// and one write per device, each within its device's timeout.
    bound: std::time::Duration,
}

/// Starts one poller per link on `runtime` and hands the scan thread
/// their exchange (before the first scan); `scan_period` tells the
/// pollers when the scan thread is stalled.
pub fn start(
    runtime: &tokio::runtime::Runtime,
    io: &RemoteIo,
    shared: &Shared,
    scan_period: std::time::Duration,
) -> Pollers {
    let exchange = Arc::new(Exchange::new(&io.devices, scan_period));
    let (stop, stopped) = tokio::sync::watch::channel(false);
    // The devices' polls spread over their periods (the k-th of n starts
    // (2k+1)/2n of a period late), not all at the same instant.
    let count = u32::try_from(exchange.slots.len()).unwrap_or(u32::MAX).max(1);
    let mut k = 0u32;
    let mut tasks = Vec::new();
    let mut bound = std::time::Duration::ZERO;
    for link in exchange.links() {
        let phases = link
            .iter()
            .map(|slot| {
                let phase = slot.device.period * (2 * k + 1) / (2 * count);
                k += 1;
                phase
            })
            .collect();
        let timeouts: std::time::Duration = link.iter().map(|slot| slot.device.timeout).sum();
        let longest = link.iter().map(|slot| slot.device.timeout).max().unwrap_or_default();
        bound = bound.max(timeouts + longest);
        tasks.push(runtime.spawn(poll::run(link, phases, stopped.clone())));
    }
    shared.set_remote_io(exchange);
    let count = io.devices.len();
    crate::announce(&format!(
        "remote I/O: polling {count} device{}",
        if count == 1 { "" } else { "s" }
    ));
    Pollers { stop, tasks, bound }
}

impl Pollers {
    /// Stops the pollers once the scan thread has ended: each writes its
    /// devices' outputs OFF once (within their timeouts), then ends.
    pub fn stop(self, runtime: &tokio::runtime::Runtime) {
        let _ = self.stop.send(true);
        let tasks = self.tasks;
        let bound = self.bound + std::time::Duration::from_millis(100);
        runtime.block_on(async {
            // They end together (each bounded by its timeouts): awaited
            // one after the other, the wait is the longest of them.
            let all = async {
                for task in tasks {
                    let _ = task.await;
                }
            };
            let _ = tokio::time::timeout(bound, all).await;
        });
    }
}

/// `Err` when a device's serial line is the one `--modbus-rtu` serves on
/// (`rtu_server`): one program cannot be master and slave of one line.
pub fn check_serial_server(io: &RemoteIo, rtu_server: Option<&str>) -> Result<(), String> {
    let Some(server) = rtu_server else {
        return Ok(());
    };
    let same = |path: &str| {
        path == server
            || std::fs::canonicalize(path)
                .ok()
                .is_some_and(|a| std::fs::canonicalize(server).ok() == Some(a))
    };
    for device in &io.devices {
        match &device.link {
            Link::Rtu { path, .. } if same(path) => {
                return Err(format!(
                    "--io: device `{}` is on {path}, the serial line --modbus-rtu serves on",
                    device.name
                ))
            }
            Link::Rtu { .. } | Link::Tcp(_) => {}
        }
    }
    Ok(())
}

/// Before a scan (scan thread): the freshest complete poll of every device
/// into the input image. Never waits on the network.
pub fn before_scan(shared: &Shared, engine: &mut dyn Engine) {
    if let Some(exchange) = shared.remote_io() {
        exchange.to_engine(engine);
    }
}

/// After a scan (scan thread): the mapped outputs to the pollers.
pub fn after_scan(shared: &Shared, image: &Memory) {
    if let Some(exchange) = shared.remote_io() {
        exchange.from_image(image);
    }
}

/// Warnings for the file against the program: inputs, status relays and
/// error counts that `written` says the program writes too (the remote I/O
/// writes them before every scan, so the program's value lasts to the end
/// of that scan only).
pub fn warnings(io: &RemoteIo, written: &dyn Fn(Place) -> bool) -> Vec<String> {
    let mut out = Vec::new();
    for device in &io.devices {
        let mut places = vec![
            Place::Bit(BitArea::M, device.status),
            Place::Word(WordArea::D, device.errors),
        ];
        for input in &device.inputs {
            for n in input.to..input.to + u32::from(input.count) {
                places.push(match input.table {
                    InputTable::DiscreteInputs => Place::Bit(BitArea::X, n),
                    InputTable::InputRegisters => Place::Word(WordArea::D, n),
                });
            }
        }
        for place in places.into_iter().filter(|&p| written(p)) {
            out.push(format!(
                "--io: the program writes {}, which remote I/O device `{}` writes before every scan",
                name_of(place),
                device.name
            ));
        }
    }
    out
}

/// Why a client's `writes` are refused: one writes an X, D or M that the
/// remote I/O writes before every scan (a device's inputs, status relay or
/// error count), which would be answered as applied and then overwritten.
/// Forces are let through: a forced X wins over its input.
pub fn refused(shared: &Shared, writes: &[HostWrite]) -> Option<String> {
    let exchange = shared.remote_io()?;
    writes.iter().find_map(|write| {
        let (first, count) = written(*write)?;
        exchange.slots.iter().find_map(|slot| {
            let device = &slot.device;
            let mut fed = vec![
                (Place::Bit(BitArea::M, device.status), 1),
                (Place::Word(WordArea::D, device.errors), 1),
            ];
            fed.extend(device.inputs.iter().map(|input| match input.table {
                InputTable::DiscreteInputs => (Place::Bit(BitArea::X, input.to), u32::from(input.count)),
                InputTable::InputRegisters => (Place::Word(WordArea::D, input.to), u32::from(input.count)),
            }));
            fed.into_iter()
                .find(|&fed| config::overlap(fed, (first, count)))
                .map(|_| {
                    format!(
                        "{} is written by remote I/O device `{}` before every scan",
                        name_of(first),
                        device.name
                    )
                })
        })
    })
}

/// The X, D or M a write writes, as its first device and how many; None
/// for other devices and for forces.
fn written(write: HostWrite) -> Option<(Place, u32)> {
    match write {
        HostWrite::Input(n, _) => Some((Place::Bit(BitArea::X, n), 1)),
        HostWrite::Relay(n, _) => Some((Place::Bit(BitArea::M, n), 1)),
        HostWrite::Data(n, _) => Some((Place::Word(WordArea::D, n), 1)),
        HostWrite::Set(device, _) => match device.device {
            Place::Bit(area, n) => Some((Place::Bit(area, n), 1)),
            Place::Word(area, n) => Some((Place::Word(area, n), if device.width == Width::Double { 2 } else { 1 })),
            Place::WordBit(area, n, _) => Some((Place::Word(area, n), 1)),
            Place::Digits(area, n, digits) => Some((Place::Bit(area, n), 4 * u32::from(digits))),
            Place::WideCounter(_) => None,
        },
        HostWrite::Output(..) | HostWrite::Force(..) | HostWrite::Unforce(..) => None,
    }
}

/// The devices' state for the JSON API (`GET /api/io`).
pub fn report(shared: &Shared) -> Value {
    let Some(exchange) = shared.remote_io() else {
        return json!({ "devices": [] });
    };
    let devices: Vec<Value> = exchange
        .slots
        .iter()
        .map(|slot| {
            let device = &slot.device;
            let state = slot.state().clone();
            let link = match &device.link {
                Link::Tcp(address) => format!("tcp {address}"),
                Link::Rtu { path, format } => format!("rtu {path} {format}"),
            };
            json!({
                "name": device.name,
                "link": link,
                "unit": device.unit,
                "period_ms": device.period.as_millis() as u64,
                "connected": state.connected,
                "errors": state.errors,
                "losses": state.losses,
                "polls": state.polls,
                "last_error": state.last_error,
                "last_poll_ms_ago": state.last_poll.map(|at| at.elapsed().as_millis() as u64),
                "on_loss": match device.on_loss {
                    OnLoss::Hold => "hold",
                    OnLoss::Clear => "clear",
                },
                "status": name_of(Place::Bit(BitArea::M, device.status)),
                "error_count": name_of(Place::Word(WordArea::D, device.errors)),
            })
        })
        .collect();
    json!({ "devices": devices })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn client_writes_of_what_the_remote_io_writes_are_refused() {
        let io = parse(
            "[[device]]\ntcp = \"127.0.0.1:502\"\nstatus = \"M100\"\nerrors = \"D100\"\n\
             [[device.input]]\ndiscrete_inputs = 0\ncount = 8\nto = \"X0\"\n\
             [[device.input]]\ninput_registers = 0\ncount = 2\nto = \"D10\"\n",
        )
        .unwrap();
        let shared = Shared::default();
        let set = |device: Place, width| HostWrite::Set(ladder_front::host_device::HostDevice { device, width }, 1);
        assert_eq!(refused(&shared, &[HostWrite::Input(0, true)]), None, "no remote I/O");
        shared.set_remote_io(Arc::new(Exchange::new(
            &io.devices,
            std::time::Duration::from_millis(10),
        )));
        for write in [
            HostWrite::Input(7, true),
            HostWrite::Relay(100, true),
            HostWrite::Data(11, 5),
            set(Place::Word(WordArea::D, 9), Width::Double),
            set(Place::Digits(BitArea::X, 4, 1), Width::Single),
            set(Place::WordBit(WordArea::D, 100, 3), Width::Single),
        ] {
            assert!(refused(&shared, &[write]).is_some(), "{write:?}");
        }
        for write in [
            HostWrite::Input(8, true),
            HostWrite::Data(12, 5),
            HostWrite::Output(0, true),
            HostWrite::Force(BitArea::X, 0, true),
            set(Place::Word(WordArea::D, 8), Width::Double),
        ] {
            assert_eq!(refused(&shared, &[write]), None, "{write:?}");
        }
        let message = refused(&shared, &[HostWrite::Data(0, 1), HostWrite::Input(3, true)]).unwrap();
        assert_eq!(
            message,
            "X3 is written by remote I/O device `device1` before every scan"
        );
    }

    #[test]
    fn a_serial_line_that_modbus_rtu_serves_on_is_refused() {
        let io = parse("[[device]]\nrtu = \"/dev/ttyS9:9600,8N1\"\n").unwrap();
        assert_eq!(check_serial_server(&io, None), Ok(()));
        assert_eq!(check_serial_server(&io, Some("/dev/ttyS8")), Ok(()));
        let error = check_serial_server(&io, Some("/dev/ttyS9")).unwrap_err();
        assert!(error.contains("`device1` is on /dev/ttyS9"), "{error}");
    }

    #[test]
    fn what_the_program_writes_too_is_warned_about() {
        let io = parse(
            "[[device]]\ntcp = \"127.0.0.1:502\"\n[[device.input]]\ndiscrete_inputs = 0\ncount = 2\nto = \"X0\"\n",
        )
        .unwrap();
        let written = |place| place == Place::Bit(BitArea::X, 1) || place == Place::Bit(BitArea::M, 7600);
        let warnings = warnings(&io, &written);
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(warnings[0].contains("writes M7600"), "{warnings:?}");
        assert!(warnings[1].contains("writes X1"), "{warnings:?}");
    }
}
