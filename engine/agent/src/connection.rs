//! A TCP connection to a server: frames in, frames out.

use libero_protocol::{FrameError, FrameReader};
use std::io::{self, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

/// How long one read waits before the caller gets to check for shutdown and silence.
pub const POLL: Duration = Duration::from_millis(100);

pub struct Connection {
    reader: FrameReader<TcpStream>,
    writer: TcpStream,
}

/// A TCP stream to `host:port` with Nagle off (each reply goes out at once).
pub(crate) fn connect(host: &str, port: u16) -> io::Result<TcpStream> {
    let addr = (host, port).to_socket_addrs()?.next().ok_or_else(|| {
        io::Error::new(io::ErrorKind::NotFound, format!("{host} does not resolve"))
    })?;
    let stream = TcpStream::connect_timeout(&addr, Duration::from_secs(2))?;
    stream.set_nodelay(true)?;
    Ok(stream)
}

impl Connection {
    pub fn open(host: &str, port: u16) -> io::Result<Self> {
        let stream = connect(host, port)?;
        stream.set_read_timeout(Some(POLL))?;
        let writer = stream.try_clone()?;
        Ok(Self {
            reader: FrameReader::new(stream),
            writer,
        })
    }

    /// The next frame; a read timeout comes back as an error for which
    /// [`libero_protocol::is_timeout`] holds, with the stream position kept.
    pub fn read_frame(&mut self) -> Result<&[u8], FrameError> {
        self.reader.read_frame()
    }

    /// Send already-framed bytes in one write.
    pub fn send(&mut self, framed: &[u8]) -> io::Result<()> {
        self.writer.write_all(framed)
    }

    /// Split borrow: the reader's frame and the writer at once.
    pub fn parts(&mut self) -> (&mut FrameReader<TcpStream>, &mut TcpStream) {
        (&mut self.reader, &mut self.writer)
    }
}
