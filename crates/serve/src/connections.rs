//! Who may write over the plant protocols (Modbus TCP, MELSEC), and the
//! connection places of their TCP servers: at most `connections` at once; one that sends no
//! request for the idle time is closed; a new client that finds every
//! place taken gets the place of the connection idle longest (when that
//! one has been idle for a second at least), so idle or abandoned
//! connections never lock a working client out.

use std::future::Future;
use std::sync::Arc;
use std::time::Duration;

/// Connections served at once by default.
pub const MOST_CONNECTIONS: usize = 64;
/// How long a connection may send nothing, by default.
pub const IDLE_TIMEOUT: Duration = Duration::from_secs(60);
/// A connection idle this long gives its place to a new client when every
/// place is taken.
const YIELDS_AFTER: Duration = Duration::from_secs(1);

/// How many connections are served, and how long one may be idle.
#[derive(Clone, Copy, Debug)]
pub struct ConnectionLimits {
    pub connections: usize,
    pub idle: Duration,
}

impl Default for ConnectionLimits {
    fn default() -> Self {
        ConnectionLimits {
            connections: MOST_CONNECTIONS,
            idle: IDLE_TIMEOUT,
        }
    }
}

/// A served connection, as the acceptor sees it.
pub struct Open {
    /// When it last sent a whole request (or connected).
    active: std::sync::Mutex<tokio::time::Instant>,
    /// Told to close (its place goes to a new client).
    pub close: tokio::sync::Notify,
}

impl Open {
    fn idle(&self) -> Duration {
        self.active.lock().map_or(Duration::ZERO, |at| at.elapsed())
    }

    /// The connection sent a whole request.
    pub fn touch(&self) {
        if let Ok(mut at) = self.active.lock() {
            *at = tokio::time::Instant::now();
        }
    }
}

/// Accepts connections until the process ends and serves each on its own
/// task with `serve(stream, peer, open)`, within `limits`. `serve` ends
/// the connection when `open.close` is notified.
pub async fn accept<F>(
    listener: tokio::net::TcpListener,
    limits: ConnectionLimits,
    serve: impl Fn(tokio::net::TcpStream, std::net::SocketAddr, Arc<Open>) -> F + Send + 'static,
) where
    F: Future<Output = ()> + Send + 'static,
{
    let places = Arc::new(tokio::sync::Semaphore::new(limits.connections.max(1)));
    let served: Arc<std::sync::Mutex<Vec<std::sync::Weak<Open>>>> = Arc::default();
    loop {
        let Ok((stream, peer)) = listener.accept().await else {
            // Out of file descriptors or similar: try again shortly.
            tokio::time::sleep(Duration::from_millis(50)).await;
            continue;
        };
        let permit = match Arc::clone(&places).try_acquire_owned() {
            Ok(permit) => permit,
            Err(_) => {
                // Every place is taken: the connection idle longest makes room
                // if it has been idle a while; else the newcomer is closed.
                let longest = served.lock().ok().and_then(|served| {
                    served
                        .iter()
                        .filter_map(std::sync::Weak::upgrade)
                        .max_by_key(|open| open.idle())
                        .filter(|open| open.idle() >= YIELDS_AFTER)
                });
                let Some(longest) = longest else {
                    drop(stream);
                    continue;
                };
                longest.close.notify_one();
                match tokio::time::timeout(Duration::from_secs(1), Arc::clone(&places).acquire_owned()).await {
                    Ok(Ok(permit)) => permit,
                    Ok(Err(_)) | Err(_) => {
                        drop(stream);
                        continue;
                    }
                }
            }
        };
        let open = Arc::new(Open {
            active: std::sync::Mutex::new(tokio::time::Instant::now()),
            close: tokio::sync::Notify::new(),
        });
        if let Ok(mut served) = served.lock() {
            served.retain(|open| open.strong_count() > 0);
            served.push(Arc::downgrade(&open));
        }
        let connection = serve(stream, peer, open);
        tokio::spawn(async move {
            connection.await;
            drop(permit);
        });
    }
}

/// Whether a peer may write: not read-only, and on loopback or in one of
/// the networks allowed to write.
#[derive(Clone)]
pub struct Permission {
    pub read_only: bool,
    pub write_from: Vec<ipnet::IpNet>,
}

impl Permission {
    pub fn may_write(&self, peer: std::net::SocketAddr) -> bool {
        let ip = peer.ip().to_canonical();
        !self.read_only && (ip.is_loopback() || self.write_from.iter().any(|net| net.contains(&ip)))
    }
}
