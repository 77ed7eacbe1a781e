//! The network side of start-up: every listener the options name is bound
//! (and announced) and the serial line opened before a scan runs, so that a
//! port in use or a wrong device is an error before anything starts; once
//! the scan thread runs, each server is started on them and runs until the
//! server stops.

use super::shared::Shared;
use super::stop::{wait_for_stop, StopSignals};
use super::{access, announce, connections, guard, http, melsec, modbus, modbus_rtu, modbus_tcp, opcua, tls};
use super::{Limits, ServeOptions};
use ladder_engine::EngineKind;
use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::Arc;
use tokio::net::{TcpListener, UdpSocket};
use tokio::runtime::Runtime;

/// The OPC UA server, built and waiting to be spawned.
type Server = Pin<Box<dyn Future<Output = ()> + Send + 'static>>;

/// What the servers will serve on.
pub struct Listeners {
    modbus: Option<TcpListener>,
    web: Option<TcpListener>,
    /// HTTPS on `web`, when `--tls-cert` is given.
    tls: Option<axum_server::tls_rustls::RustlsConfig>,
    opcua: Option<Server>,
    /// MELSEC on TCP, and on the UDP port of the same number.
    melsec: Option<(TcpListener, Option<UdpSocket>)>,
    serial: Option<modbus_rtu::Serial>,
}

impl Listeners {
    /// Binds Modbus, HTTP(S), OPC UA and MELSEC in this order (each says
    /// where it listens) and opens the serial line.
    pub fn open(runtime: &Runtime, options: &ServeOptions, shared: &Arc<Shared>) -> Result<Listeners, String> {
        let modbus = listen(runtime, options.modbus, "Modbus", "modbus")?;
        let tls = options
            .tls
            .as_ref()
            .map(|(cert, key)| tls::config(cert, key))
            .transpose()?;
        let web = listen(
            runtime,
            options.http,
            "HTTP",
            if tls.is_some() { "https" } else { "http" },
        )?;
        let opcua = match listen(runtime, options.opcua, "OPC UA", "opcua")? {
            Some(listener) => Some(Box::pin(runtime.block_on(async {
                opcua::start(
                    opcua::Setup {
                        listener,
                        devices: options.opcua_devices.clone(),
                        read_only: options.read_only,
                        token: options.access.token.clone(),
                        period: options.period,
                    },
                    Arc::clone(shared),
                )
            })?) as Server),
            None => None,
        };
        let melsec = match bind(runtime, options.melsec, "MELSEC")? {
            Some(listener) => {
                // UDP on the port TCP has (the same number when it was 0),
                // bound before either is announced: a client may send a
                // datagram as soon as it reads the address.
                let udp = if options.melsec_udp {
                    let address = listener.local_addr().map_err(|e| e.to_string())?;
                    let udp = runtime
                        .block_on(UdpSocket::bind(address))
                        .map_err(|e| format!("cannot listen for MELSEC on UDP {address}: {e}"))?;
                    Some(udp)
                } else {
                    None
                };
                say_listening(&listener, "melsec")?;
                Some((listener, udp))
            }
            None => None,
        };
        // The serial line opens before a scan, so a wrong device stops here.
        let serial = options.modbus_rtu.as_ref().map(modbus_rtu::open).transpose()?;
        Ok(Listeners {
            modbus,
            web,
            tls,
            opcua,
            melsec,
            serial,
        })
    }

    /// Starts every server (the serial line on a thread of its own, the
    /// rest on the runtime) and returns when a signal stops the server or
    /// the scan thread stops on its own.
    pub fn serve(self, runtime: &Runtime, options: &ServeOptions, shared: &Arc<Shared>, signals: StopSignals) {
        let mut access = options.access.clone();
        // Listening on port 0 (any free port): the host names carry the port
        // the system chose.
        if let Some(bound) = self.web.as_ref().and_then(|web| web.local_addr().ok()) {
            if access.hosts.port == 0 {
                access.hosts.port = bound.port();
            }
        }
        let limits = options.limits;
        // Who may write over Modbus and MELSEC.
        let permission = connections::Permission {
            read_only: options.read_only,
            write_from: options.modbus_write_from.clone(),
        };
        if let Some(serial) = self.serial {
            let service = modbus::Service {
                shared: Arc::clone(shared),
                may_write: !options.read_only,
            };
            std::thread::spawn(move || serial.serve(&service));
        }
        let native = options.engine == EngineKind::Jit;
        let served = Arc::clone(shared);
        runtime.block_on(async move {
            if let Some(listener) = self.modbus {
                let shared = Arc::clone(&served);
                let permission = permission.clone();
                tokio::spawn(modbus_tcp::serve(listener, limits.modbus, move |peer| {
                    modbus::Service {
                        shared: Arc::clone(&shared),
                        may_write: permission.may_write(peer),
                    }
                }));
            }
            if let Some((listener, udp)) = self.melsec {
                tokio::spawn(melsec::serve(
                    listener,
                    udp,
                    limits.melsec,
                    permission,
                    Arc::clone(&served),
                ));
            }
            if let Some(web) = self.web {
                let app = http::router(Arc::clone(&served), native)
                    .layer(axum::middleware::from_fn_with_state(Arc::new(access), access::check));
                spawn_web(web, self.tls, app, &limits);
            }
            if let Some(opcua) = self.opcua {
                tokio::spawn(opcua);
            }
            wait_for_stop(&served, signals).await;
        });
    }
}

/// Binds `address` (when given) and says where it listens: `{what}
/// listening on ADDRESS`, the line tests read the port from.
fn listen(
    runtime: &Runtime,
    address: Option<SocketAddr>,
    protocol: &str,
    what: &str,
) -> Result<Option<TcpListener>, String> {
    let listener = bind(runtime, address, protocol)?;
    if let Some(listener) = &listener {
        say_listening(listener, what)?;
    }
    Ok(listener)
}

/// Binds `address` (when given), saying nothing yet.
fn bind(runtime: &Runtime, address: Option<SocketAddr>, protocol: &str) -> Result<Option<TcpListener>, String> {
    let Some(address) = address else {
        return Ok(None);
    };
    runtime
        .block_on(TcpListener::bind(address))
        .map(Some)
        .map_err(|e| format!("cannot listen for {protocol} on {address}: {e}"))
}

/// `{what} listening on ADDRESS`: from then on, clients may come.
fn say_listening(listener: &TcpListener, what: &str) -> Result<(), String> {
    let bound = listener.local_addr().map_err(|e| e.to_string())?;
    announce(&format!("{what} listening on {bound}"));
    Ok(())
}

/// Serves the monitor and the JSON API on `web` (HTTPS with `tls`), each
/// connection within the HTTP bounds (inside the runtime).
fn spawn_web(web: TcpListener, tls: Option<axum_server::tls_rustls::RustlsConfig>, app: axum::Router, limits: &Limits) {
    match tls {
        Some(tls) => match web.into_std() {
            Ok(web) => {
                let app = app.into_make_service_with_connect_info::<SocketAddr>();
                let guard = guard::GuardAcceptor::new(limits.http);
                let server = axum_server::from_tcp_rustls(web, tls).map(|rustls| rustls.acceptor(guard));
                tokio::spawn(async move {
                    let _ = server.serve(app).await;
                });
            }
            Err(error) => {
                use std::io::Write as _;
                let _ = writeln!(std::io::stderr(), "https: {error}");
            }
        },
        None => {
            let app = app.into_make_service_with_connect_info::<guard::Peer>();
            let web = guard::GuardedListener::new(web, limits.http);
            tokio::spawn(async move {
                let _ = axum::serve(web, app).await;
            });
        }
    }
}
