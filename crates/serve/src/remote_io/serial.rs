//! A serial line as tokio-modbus's RTU client needs it (`AsyncRead` and
//! `AsyncWrite`): the line opened and set up by the `serialport` crate (as
//! `--modbus-rtu` opens its own), its descriptor made non-blocking and
//! watched by tokio's reactor, so a poller waiting for an answer holds no
//! thread; its unread input can be discarded before a request (`Drain`).
//! Unix only (a terminal device); elsewhere opening fails with a message.

use ladder_modbus::rtu::{Format, Parity};

/// Opens `path` as `format` says, ready for the RTU client.
#[cfg(unix)]
pub fn open(path: &str, format: Format) -> std::io::Result<unix::Line> {
    unix::Line::open(path, format)
}

#[cfg(not(unix))]
pub fn open(path: &str, _format: Format) -> std::io::Result<tokio::io::DuplexStream> {
    Err(std::io::Error::other(format!(
        "{path}: remote I/O over a serial line needs a Unix system"
    )))
}

/// What discards a serial line's unread input before a request.
#[cfg(unix)]
pub use unix::Drain;

/// The drain of an open line (it lives as long as the line does: both are
/// kept by the poller's connection).
#[cfg(unix)]
pub fn drain_of(line: &unix::Line) -> Option<Drain> {
    Some(line.drain())
}

#[cfg(not(unix))]
pub struct Drain;

#[cfg(not(unix))]
impl Drain {
    pub fn flush_input(&self) {}
}

#[cfg(not(unix))]
pub fn drain_of(_line: &tokio::io::DuplexStream) -> Option<Drain> {
    None
}

/// The line's settings for `serialport`.
fn builder(path: &str, format: Format) -> serialport::SerialPortBuilder {
    let data_bits = match format.data_bits {
        7 => serialport::DataBits::Seven,
        _ => serialport::DataBits::Eight,
    };
    let parity = match format.parity {
        Parity::None => serialport::Parity::None,
        Parity::Even => serialport::Parity::Even,
        Parity::Odd => serialport::Parity::Odd,
    };
    let stop_bits = match format.stop_bits {
        2 => serialport::StopBits::Two,
        _ => serialport::StopBits::One,
    };
    serialport::new(path, format.baud)
        .data_bits(data_bits)
        .parity(parity)
        .stop_bits(stop_bits)
        .flow_control(serialport::FlowControl::None)
}

#[cfg(unix)]
mod unix {
    use super::Format;
    use std::io;
    use std::os::fd::AsRawFd;
    use std::pin::Pin;
    use std::task::{ready, Context, Poll};
    use tokio::io::unix::AsyncFd;
    use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};

    /// An open serial line, non-blocking, registered with the reactor.
    #[derive(Debug)]
    pub struct Line {
        fd: AsyncFd<serialport::TTYPort>,
    }

    impl Line {
        pub fn open(path: &str, format: Format) -> io::Result<Line> {
            let port = super::builder(path, format)
                .open_native()
                .map_err(|e| io::Error::other(format!("cannot open the serial line {path}: {e}")))?;
            let fd = port.as_raw_fd();
            // SAFETY: `fd` is the open descriptor `port` owns; F_GETFL and
            // F_SETFL only read and set its flags.
            let set = unsafe {
                let flags = libc::fcntl(fd, libc::F_GETFL);
                flags >= 0 && libc::fcntl(fd, libc::F_SETFL, flags | libc::O_NONBLOCK) >= 0
            };
            if !set {
                return Err(io::Error::last_os_error());
            }
            // SAFETY: `port` owns the open descriptor and keeps it, the
            // same one, until it is dropped with the `AsyncFd`. Called from
            // the poller's task, inside the runtime (its reactor).
            let fd = unsafe { AsyncFd::register(port) }.map_err(|e| io::Error::other(e.to_string()))?;
            Ok(Line { fd })
        }
    }

    /// The line's descriptor, to discard its unread input.
    pub struct Drain {
        fd: std::os::fd::RawFd,
    }

    impl Line {
        pub fn drain(&self) -> Drain {
            Drain {
                fd: self.fd.get_ref().as_raw_fd(),
            }
        }
    }

    impl Drain {
        /// Discards what the line received and nobody read (tcflush).
        pub fn flush_input(&self) {
            // SAFETY: the descriptor belongs to the `Line` the poller's
            // connection keeps open as long as this drain (they are
            // dropped together); tcflush takes no pointers.
            let _ = unsafe { libc::tcflush(self.fd, libc::TCIFLUSH) };
        }
    }

    /// `read(2)` or `write(2)`'s answer as a result.
    fn result(done: isize) -> io::Result<usize> {
        usize::try_from(done).map_err(|_| io::Error::last_os_error())
    }

    impl AsyncRead for Line {
        fn poll_read(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
            loop {
                let mut guard = ready!(self.fd.poll_read_ready(cx))?;
                let unfilled = buf.initialize_unfilled();
                let read = guard.try_io(|fd| {
                    // SAFETY: the descriptor is open while `fd` lives; the
                    // kernel writes at most `unfilled.len()` bytes into it.
                    result(unsafe {
                        libc::read(fd.get_ref().as_raw_fd(), unfilled.as_mut_ptr().cast(), unfilled.len())
                    })
                });
                match read {
                    Ok(Ok(n)) => {
                        buf.advance(n);
                        return Poll::Ready(Ok(()));
                    }
                    Ok(Err(error)) => return Poll::Ready(Err(error)),
                    Err(_would_block) => continue,
                }
            }
        }
    }

    impl AsyncWrite for Line {
        fn poll_write(self: Pin<&mut Self>, cx: &mut Context<'_>, bytes: &[u8]) -> Poll<io::Result<usize>> {
            loop {
                let mut guard = ready!(self.fd.poll_write_ready(cx))?;
                let written = guard.try_io(|fd| {
                    // SAFETY: the descriptor is open while `fd` lives; the
                    // kernel reads at most `bytes.len()` bytes from it.
                    result(unsafe { libc::write(fd.get_ref().as_raw_fd(), bytes.as_ptr().cast(), bytes.len()) })
                });
                match written {
                    Ok(done) => return Poll::Ready(done),
                    Err(_would_block) => continue,
                }
            }
        }

        fn poll_flush(self: Pin<&mut Self>, _cx: &mut Context<'_>) -> Poll<io::Result<()>> {
            Poll::Ready(Ok(()))
        }

        fn poll_shutdown(self: Pin<&mut Self>, _cx: &mut Context<'_>) -> Poll<io::Result<()>> {
            Poll::Ready(Ok(()))
        }
    }
}
