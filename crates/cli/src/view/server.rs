//! The local web server: 127.0.0.1 only, and no client can hold it up.
//!
//! A thread per connection (tiny_http, which this replaced) let ~1500 idle
//! connections exhaust threads, one endless header line grow a buffer
//! until the process aborted, and one client that never read block the
//! rest. Here one thread watches every connection with mio (readiness
//! polling, the I/O layer under tokio) and reads each request whole within
//! fixed limits (`http.rs`: a head of 16 KiB, a body of 64 KiB), in 10 s at
//! most; at most 512 connections are kept (a new one pushes out the oldest
//! still sending). Whole requests go through a bounded queue (full: 503) to
//! a fixed pool of workers, which run the vision pipeline; their replies
//! are written back without blocking, in 30 s at most, and the connection
//! is closed, so a client that pipelines requests and never reads holds one
//! slot, not a thread. A hand-made loop over mio rather than an async
//! stack (hyper on tokio) keeps the dependencies small for a page that
//! asks a few things at a time.

use std::collections::BTreeMap;
use std::io::{ErrorKind, Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use mio::net::{TcpListener, TcpStream};
use mio::{Events, Interest, Poll, Token, Waker};

use super::http::{Incoming, Received, Reply, Request, MAX_BODY, MAX_HEAD};

/// The port tried first when none is given.
pub const DEFAULT_PORT: u16 = 8650;
/// How many ports after it are tried when it is busy.
const PORTS_TRIED: u16 = 20;
/// Connections kept open at once: within the usual limit of 1024 open
/// files, with room for the rest of the process.
const MAX_CONNECTIONS: usize = 512;
/// The time a client has to send its whole request.
const READ_TIME: Duration = Duration::from_secs(10);
/// The time a client has to take the whole reply.
const WRITE_TIME: Duration = Duration::from_secs(30);
/// Whole requests waiting for a worker; more are answered 503.
const QUEUED: usize = 16;
/// How often deadlines are looked at (and a refused accept retried).
const TICK: Duration = Duration::from_millis(100);

const LISTENER: Token = Token(0);
const WAKER: Token = Token(1);

/// What the server serves.
pub trait Handler: Send + Sync + 'static {
    /// Cheap checks, made as a request arrives: a refusal is the answer,
    /// and the request never reaches a worker.
    fn admit(&self, request: &Request) -> Result<(), Reply>;
    /// The answer, made on a worker.
    fn answer(&self, request: &Request) -> Reply;
}

/// A listener on 127.0.0.1: on `port` (0: one the system picks; busy: an
/// error), or on 8650 or the next free port.
pub fn bind(port: Option<u16>) -> Result<(std::net::TcpListener, u16)> {
    let open = |p: u16| std::net::TcpListener::bind(("127.0.0.1", p));
    let listener = match port {
        Some(p) => match open(p) {
            Ok(s) => s,
            Err(e) => bail!("--port {p}: cannot listen on 127.0.0.1:{p} ({e}); give another port, or 0 for any free one"),
        },
        None => {
            let mut tried = DEFAULT_PORT..DEFAULT_PORT + PORTS_TRIED;
            loop {
                let Some(p) = tried.next() else {
                    bail!(
                        "ports {DEFAULT_PORT}–{} on 127.0.0.1 are all busy: give --port",
                        DEFAULT_PORT + PORTS_TRIED - 1
                    );
                };
                if let Ok(s) = open(p) {
                    break s;
                }
            }
        }
    };
    let port = listener.local_addr()?.port();
    Ok((listener, port))
}

/// The server's threads, answering until closed.
pub struct Serving {
    closing: Arc<AtomicBool>,
    waker: Arc<Waker>,
    poller: JoinHandle<()>,
    workers: Vec<JoinHandle<()>>,
}

impl Serving {
    /// Stops answering and closes the port (a request being answered is
    /// finished first).
    pub fn close(self) {
        self.closing.store(true, Ordering::Relaxed);
        let _ = self.waker.wake();
        let _ = self.poller.join();
        for w in self.workers {
            let _ = w.join();
        }
    }
}

/// Answers requests with `workers` threads until closed.
pub fn spawn(
    listener: std::net::TcpListener,
    handler: Arc<dyn Handler>,
    workers: usize,
) -> Result<Serving> {
    listener.set_nonblocking(true)?;
    let mut listener = TcpListener::from_std(listener);
    let poll = Poll::new().context("cannot poll the viewer's connections")?;
    poll.registry()
        .register(&mut listener, LISTENER, Interest::READABLE)?;
    let waker = Arc::new(Waker::new(poll.registry(), WAKER)?);
    let (jobs, queue) = mpsc::sync_channel::<(usize, Request)>(QUEUED);
    let queue = Arc::new(Mutex::new(queue));
    let (replies, answered) = mpsc::channel::<(usize, Vec<u8>)>();
    let workers = (0..workers)
        .map(|_| {
            let (queue, replies) = (queue.clone(), replies.clone());
            let (handler, waker) = (handler.clone(), waker.clone());
            std::thread::spawn(move || work(&queue, &*handler, &replies, &waker))
        })
        .collect();
    let closing = Arc::new(AtomicBool::new(false));
    let mut lp = Loop {
        poll,
        listener,
        connections: BTreeMap::new(),
        next: 2,
        handler,
        jobs,
        answered,
    };
    let flag = closing.clone();
    let poller = std::thread::spawn(move || lp.run(&flag));
    Ok(Serving {
        closing,
        waker,
        poller,
        workers,
    })
}

/// A worker: answers queued requests until the queue closes.
fn work(
    queue: &Mutex<Receiver<(usize, Request)>>,
    handler: &dyn Handler,
    replies: &Sender<(usize, Vec<u8>)>,
    waker: &Waker,
) {
    loop {
        let job = queue.lock().unwrap_or_else(|e| e.into_inner()).recv();
        let Ok((id, request)) = job else { return };
        // A failure inside one answer is that request's 500, not a worker
        // lost.
        let reply =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| handler.answer(&request)))
                .unwrap_or_else(|_| Reply::error(500, "the viewer failed on this request".into()));
        if replies.send((id, reply.bytes())).is_err() {
            return;
        }
        let _ = waker.wake();
    }
}

struct Connection {
    stream: TcpStream,
    state: State,
    /// When it is dropped unless done (none while a worker answers).
    deadline: Instant,
}

enum State {
    /// What it has sent so far.
    Reading(Incoming),
    /// Its request is with a worker.
    Working,
    /// The reply and how much of it is sent.
    Writing(Vec<u8>, usize),
}

/// What becomes of a connection after some progress.
enum Next {
    Keep,
    Close,
}

struct Loop {
    poll: Poll,
    listener: TcpListener,
    /// By number, so the first is the oldest.
    connections: BTreeMap<usize, Connection>,
    next: usize,
    handler: Arc<dyn Handler>,
    jobs: SyncSender<(usize, Request)>,
    answered: Receiver<(usize, Vec<u8>)>,
}

impl Loop {
    fn run(&mut self, closing: &AtomicBool) {
        let mut events = Events::with_capacity(256);
        let mut accept_later = false;
        while !closing.load(Ordering::Relaxed) {
            if let Err(e) = self.poll.poll(&mut events, Some(TICK)) {
                if e.kind() != ErrorKind::Interrupted {
                    eprintln!("scotopia: the viewer's server stopped: {e}");
                    return;
                }
            }
            for event in events.iter() {
                match event.token() {
                    LISTENER => accept_later = self.accept(),
                    WAKER => {}
                    Token(id) => self.advance(id),
                }
            }
            if accept_later {
                accept_later = self.accept();
            }
            while let Ok((id, bytes)) = self.answered.try_recv() {
                self.reply(id, bytes);
            }
            let now = Instant::now();
            self.connections
                .retain(|_, c| matches!(c.state, State::Working) || c.deadline > now);
        }
    }

    /// Takes every waiting connection; true when accepting failed for want
    /// of resources (open files), to be tried again.
    fn accept(&mut self) -> bool {
        loop {
            match self.listener.accept() {
                Ok((mut stream, _)) => {
                    if self.connections.len() >= MAX_CONNECTIONS && !self.make_room() {
                        continue; // dropped: nothing can make way for it
                    }
                    let id = self.next;
                    self.next += 1;
                    if self
                        .poll
                        .registry()
                        .register(&mut stream, Token(id), Interest::READABLE)
                        .is_err()
                    {
                        continue;
                    }
                    let state = State::Reading(Incoming::default());
                    let deadline = Instant::now() + READ_TIME;
                    self.connections.insert(
                        id,
                        Connection {
                            stream,
                            state,
                            deadline,
                        },
                    );
                    // Anything already sent is read now.
                    self.advance(id);
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => return false,
                Err(e)
                    if matches!(
                        e.kind(),
                        ErrorKind::Interrupted | ErrorKind::ConnectionAborted
                    ) => {}
                // Out of open files (or the like): the oldest idle
                // connection makes way, and the listener waits a tick.
                Err(_) => {
                    self.make_room();
                    return true;
                }
            }
        }
    }

    /// Drops the oldest connection still sending (else the oldest being
    /// sent its reply); false if every one waits on a worker.
    fn make_room(&mut self) -> bool {
        let oldest = |want: fn(&State) -> bool, c: &BTreeMap<usize, Connection>| {
            c.iter().find(|(_, c)| want(&c.state)).map(|(&id, _)| id)
        };
        let id = oldest(|s| matches!(s, State::Reading(_)), &self.connections)
            .or_else(|| oldest(|s| matches!(s, State::Writing(..)), &self.connections));
        id.map(|id| self.connections.remove(&id)).is_some()
    }

    /// Reads or writes what the connection is ready for.
    fn advance(&mut self, id: usize) {
        let Some(c) = self.connections.get_mut(&id) else {
            return;
        };
        let next = match &mut c.state {
            State::Reading(incoming) => match read(&mut c.stream, incoming) {
                Err(()) => Next::Close,
                Ok(None) => Next::Keep,
                Ok(Some(Received::More)) => Next::Keep,
                Ok(Some(Received::Refused(reply))) => return self.reply(id, reply.bytes()),
                Ok(Some(Received::Whole(request))) => {
                    c.state = State::Working;
                    return self.dispatch(id, request);
                }
            },
            State::Working => Next::Keep,
            State::Writing(bytes, at) => write(&mut c.stream, bytes, at),
        };
        if let Next::Close = next {
            self.connections.remove(&id);
        }
    }

    /// Checks a whole request and queues it for a worker.
    fn dispatch(&mut self, id: usize, request: Request) {
        if let Err(refused) = self.handler.admit(&request) {
            return self.reply(id, refused.bytes());
        }
        match self.jobs.try_send((id, request)) {
            Ok(()) => {}
            Err(TrySendError::Full(_)) => {
                let busy = Reply::error(503, "the viewer is busy: try again".into());
                self.reply(id, busy.with("Retry-After", "1".into()).bytes());
            }
            Err(TrySendError::Disconnected(_)) => {
                self.connections.remove(&id);
            }
        }
    }

    /// Starts sending `bytes` as the connection's reply.
    fn reply(&mut self, id: usize, bytes: Vec<u8>) {
        let Some(c) = self.connections.get_mut(&id) else {
            return; // gone (dropped to make room) while a worker answered
        };
        c.state = State::Writing(bytes, 0);
        c.deadline = Instant::now() + WRITE_TIME;
        let registry = self.poll.registry();
        if registry
            .reregister(&mut c.stream, Token(id), Interest::WRITABLE)
            .is_err()
        {
            self.connections.remove(&id);
            return;
        }
        self.advance(id);
    }
}

/// Reads what has arrived: `Err` when the connection is over, `Ok(None)`
/// when nothing more is there yet, else what the bytes so far amount to.
fn read(stream: &mut TcpStream, incoming: &mut Incoming) -> Result<Option<Received>, ()> {
    let mut chunk = [0u8; 8192];
    loop {
        match stream.read(&mut chunk) {
            // Closed before a whole request.
            Ok(0) => return Err(()),
            Ok(n) => match incoming.push(&chunk[..n]) {
                Received::More => {
                    // A head over its limit is refused, a body is at most
                    // MAX_BODY: never more than this is held.
                    debug_assert!(incoming.held() <= MAX_HEAD + MAX_BODY + chunk.len());
                }
                done => return Ok(Some(done)),
            },
            Err(e) if e.kind() == ErrorKind::WouldBlock => return Ok(None),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => return Err(()),
        }
    }
}

/// Sends what the connection takes; closes it once all is sent.
fn write(stream: &mut TcpStream, bytes: &[u8], at: &mut usize) -> Next {
    while *at < bytes.len() {
        match stream.write(&bytes[*at..]) {
            Ok(0) => return Next::Close,
            Ok(n) => *at += n,
            Err(e) if e.kind() == ErrorKind::WouldBlock => return Next::Keep,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => return Next::Close,
        }
    }
    let _ = stream.flush();
    let _ = stream.shutdown(std::net::Shutdown::Write);
    Next::Close
}
