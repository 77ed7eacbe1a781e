//! Bounds on the HTTP server's connections (HTTP and HTTPS alike):
//! - at most `connections` at once; a newcomer that finds every place taken
//!   gets the place of the connection idle longest, when that one has been
//!   idle for a second at least, else it waits up to a second for a place
//!   and is closed if none frees;
//! - a connection on which nothing moved (no byte read, none written) for
//!   `idle` is closed: a client that opened a connection and left (hyper
//!   has no header timeout without a timer) does not keep its place;
//! - a connection whose client stops reading is closed once a write has
//!   waited `stall` for it (an event stream to a client that never reads
//!   would otherwise keep its buffers, and its place, for ever).

use axum::extract::connect_info::Connected;
use axum::serve::IncomingStream;
use futures_util::task::AtomicWaker;
use std::future::Future as _;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Weak};
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::sync::{OwnedSemaphorePermit, Semaphore};
use tokio::time::Instant;

/// HTTP connections served at once by default.
pub const MOST_CONNECTIONS: usize = 256;
/// How long a write may wait for a client that does not read, by default.
pub const STALL: Duration = Duration::from_secs(10);
/// How long nothing may move on a connection, by default.
pub const IDLE: Duration = Duration::from_secs(60);
/// A connection idle this long gives its place to a newcomer when every
/// place is taken.
const YIELDS_AFTER: Duration = Duration::from_secs(1);

/// What the guard holds against one connection.
#[derive(Clone, Copy, Debug)]
pub struct Bounds {
    pub connections: usize,
    pub idle: Duration,
    pub stall: Duration,
}

/// The peer of a guarded connection (what the access layer asks).
#[derive(Clone, Copy, Debug)]
pub struct Peer(pub SocketAddr);

/// When a connection last moved, and whether it was told to close.
struct Activity {
    born: Instant,
    /// Milliseconds after `born` of the last byte read or written.
    last: AtomicU64,
    closed: AtomicBool,
    /// The task reading the connection, woken when it is told to close.
    reader: AtomicWaker,
}

impl Activity {
    fn new() -> Activity {
        Activity {
            born: Instant::now(),
            last: AtomicU64::new(0),
            closed: AtomicBool::new(false),
            reader: AtomicWaker::new(),
        }
    }

    fn touch(&self) {
        let now = self.born.elapsed().as_millis() as u64;
        self.last.store(now, Ordering::Relaxed);
    }

    fn last_moved(&self) -> Instant {
        self.born + Duration::from_millis(self.last.load(Ordering::Relaxed))
    }

    fn idle(&self) -> Duration {
        self.last_moved().elapsed()
    }

    fn close(&self) {
        self.closed.store(true, Ordering::Relaxed);
        self.reader.wake();
    }
}

/// The places for connections, and who holds them.
struct Places {
    semaphore: Arc<Semaphore>,
    held: Mutex<Vec<Weak<Activity>>>,
}

impl Places {
    fn new(connections: usize) -> Places {
        Places {
            semaphore: Arc::new(Semaphore::new(connections.max(1))),
            held: Mutex::new(Vec::new()),
        }
    }

    /// A place for a newcomer: a free one, or the one of the connection
    /// idle longest (idle a second at least), or one that frees within a
    /// second; `None`: the newcomer is closed.
    async fn take(&self) -> Option<(OwnedSemaphorePermit, Arc<Activity>)> {
        let permit = match Arc::clone(&self.semaphore).try_acquire_owned() {
            Ok(permit) => permit,
            Err(_) => {
                let longest = self.held.lock().ok().and_then(|held| {
                    held.iter()
                        .filter_map(Weak::upgrade)
                        .max_by_key(|activity| activity.idle())
                        .filter(|activity| activity.idle() >= YIELDS_AFTER)
                });
                if let Some(longest) = longest {
                    longest.close();
                }
                let waited = tokio::time::timeout(Duration::from_secs(1), Arc::clone(&self.semaphore).acquire_owned());
                match waited.await {
                    Ok(Ok(permit)) => permit,
                    Ok(Err(_)) | Err(_) => return None,
                }
            }
        };
        let activity = Arc::new(Activity::new());
        if let Ok(mut held) = self.held.lock() {
            held.retain(|activity| activity.strong_count() > 0);
            held.push(Arc::downgrade(&activity));
        }
        Some((permit, activity))
    }
}

/// A TCP listener whose connections are `Guarded`.
pub struct GuardedListener {
    listener: tokio::net::TcpListener,
    places: Places,
    bounds: Bounds,
}

impl GuardedListener {
    pub fn new(listener: tokio::net::TcpListener, bounds: Bounds) -> GuardedListener {
        GuardedListener {
            listener,
            places: Places::new(bounds.connections),
            bounds,
        }
    }

    /// The next connection that gets a place.
    async fn next(&mut self) -> (Guarded<tokio::net::TcpStream>, SocketAddr) {
        loop {
            let (stream, peer) = match self.listener.accept().await {
                Ok(accepted) => accepted,
                Err(_) => {
                    // Out of file descriptors or similar: try again shortly.
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            };
            if let Some((place, activity)) = self.places.take().await {
                let _ = stream.set_nodelay(true);
                return (Guarded::new(stream, self.bounds, place, activity), peer);
            }
        }
    }
}

impl axum::serve::Listener for GuardedListener {
    type Io = Guarded<tokio::net::TcpStream>;
    type Addr = SocketAddr;

    async fn accept(&mut self) -> (Self::Io, Self::Addr) {
        self.next().await
    }

    fn local_addr(&self) -> std::io::Result<Self::Addr> {
        self.listener.local_addr()
    }
}

impl Connected<IncomingStream<'_, GuardedListener>> for Peer {
    fn connect_info(stream: IncomingStream<'_, GuardedListener>) -> Self {
        Peer(*stream.remote_addr())
    }
}

/// A stream that fails once it was idle too long, told to close, or a
/// write has waited `stall` for the client.
pub struct Guarded<S> {
    inner: S,
    bounds: Bounds,
    activity: Arc<Activity>,
    /// Armed while a write waits for the client.
    waiting: Option<Pin<Box<tokio::time::Sleep>>>,
    /// Armed while a read waits: fires when the connection has been idle.
    idle: Option<Pin<Box<tokio::time::Sleep>>>,
    /// The connection's place, given back when it closes.
    _place: OwnedSemaphorePermit,
}

fn failure<T>(why: &'static str) -> Poll<std::io::Result<T>> {
    Poll::Ready(Err(std::io::Error::new(std::io::ErrorKind::TimedOut, why)))
}

impl<S> Guarded<S> {
    fn new(inner: S, bounds: Bounds, place: OwnedSemaphorePermit, activity: Arc<Activity>) -> Guarded<S> {
        Guarded {
            inner,
            bounds,
            activity,
            waiting: None,
            idle: None,
            _place: place,
        }
    }

    /// After the inner stream answered a write's `poll`: a pending write
    /// arms the deadline (or finds it passed: the client stopped reading);
    /// a done one disarms it.
    fn judge_write<T>(&mut self, cx: &mut Context<'_>, poll: Poll<std::io::Result<T>>) -> Poll<std::io::Result<T>> {
        match poll {
            Poll::Pending => {
                let stall = self.bounds.stall;
                let waiting = self.waiting.get_or_insert_with(|| Box::pin(tokio::time::sleep(stall)));
                match waiting.as_mut().poll(cx) {
                    Poll::Ready(()) => failure("the client stopped reading"),
                    Poll::Pending => Poll::Pending,
                }
            }
            Poll::Ready(result) => {
                self.waiting = None;
                if result.is_ok() {
                    self.activity.touch();
                }
                Poll::Ready(result)
            }
        }
    }

    /// While a read waits: whether the connection has been idle for its
    /// time (its timer re-armed from the last movement until then).
    fn idle_expired(&mut self, cx: &mut Context<'_>) -> bool {
        loop {
            let due = self.activity.last_moved() + self.bounds.idle;
            let timer = self.idle.get_or_insert_with(|| Box::pin(tokio::time::sleep_until(due)));
            if timer.deadline() != due {
                timer.as_mut().reset(due);
            }
            match timer.as_mut().poll(cx) {
                Poll::Pending => return false,
                // Moved since the timer was set: wait from then on.
                Poll::Ready(()) if self.activity.last_moved() + self.bounds.idle > Instant::now() => continue,
                Poll::Ready(()) => return true,
            }
        }
    }
}

impl<S: AsyncRead + Unpin> AsyncRead for Guarded<S> {
    fn poll_read(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<std::io::Result<()>> {
        self.activity.reader.register(cx.waker());
        if self.activity.closed.load(Ordering::Relaxed) {
            return failure("the place went to a newer connection");
        }
        let before = buf.filled().len();
        match Pin::new(&mut self.inner).poll_read(cx, buf) {
            Poll::Ready(result) => {
                if buf.filled().len() > before {
                    self.activity.touch();
                }
                Poll::Ready(result)
            }
            Poll::Pending if self.idle_expired(cx) => failure("idle for too long"),
            Poll::Pending => Poll::Pending,
        }
    }
}

impl<S: AsyncWrite + Unpin> AsyncWrite for Guarded<S> {
    fn poll_write(mut self: Pin<&mut Self>, cx: &mut Context<'_>, data: &[u8]) -> Poll<std::io::Result<usize>> {
        if self.activity.closed.load(Ordering::Relaxed) {
            return failure("the place went to a newer connection");
        }
        let poll = Pin::new(&mut self.inner).poll_write(cx, data);
        self.judge_write(cx, poll)
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<std::io::Result<()>> {
        let poll = Pin::new(&mut self.inner).poll_flush(cx);
        self.judge_write(cx, poll)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<std::io::Result<()>> {
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }

    fn poll_write_vectored(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buffers: &[std::io::IoSlice<'_>],
    ) -> Poll<std::io::Result<usize>> {
        if self.activity.closed.load(Ordering::Relaxed) {
            return failure("the place went to a newer connection");
        }
        let poll = Pin::new(&mut self.inner).poll_write_vectored(cx, buffers);
        self.judge_write(cx, poll)
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }
}

/// The same guard for the HTTPS server (axum-server): each accepted stream
/// takes a place and is `Guarded` before TLS is set up over it.
#[derive(Clone)]
pub struct GuardAcceptor {
    places: Arc<Places>,
    bounds: Bounds,
}

impl GuardAcceptor {
    pub fn new(bounds: Bounds) -> GuardAcceptor {
        GuardAcceptor {
            places: Arc::new(Places::new(bounds.connections)),
            bounds,
        }
    }
}

impl<S: Send + 'static> axum_server::accept::Accept<tokio::net::TcpStream, S> for GuardAcceptor {
    type Stream = Guarded<tokio::net::TcpStream>;
    type Service = S;
    type Future = Pin<Box<dyn std::future::Future<Output = std::io::Result<(Self::Stream, S)>> + Send>>;

    fn accept(&self, stream: tokio::net::TcpStream, service: S) -> Self::Future {
        let (places, bounds) = (Arc::clone(&self.places), self.bounds);
        Box::pin(async move {
            match places.take().await {
                Some((place, activity)) => {
                    let _ = stream.set_nodelay(true);
                    Ok((Guarded::new(stream, bounds, place, activity), service))
                }
                None => Err(std::io::Error::other("no place for another connection")),
            }
        })
    }
}
