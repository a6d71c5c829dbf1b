//! Length-prefixed framing: a 4-byte big-endian payload length, then the payload.

use std::io::{self, Read};

/// Largest payload we accept from a server. Real percepts are 1–25 kB; anything far larger is
/// a corrupt or hostile length prefix, and honouring it would let the peer make us allocate
/// without bound.
pub const DEFAULT_MAX_FRAME: usize = 1 << 20;

/// Why no frame could be read.
#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    #[error("frame of {0} bytes announced, more than the {1}-byte limit: the stream is corrupt")]
    TooLarge(usize, usize),
    #[error("the server closed the connection")]
    Closed,
    #[error("the server closed the connection in the middle of a frame ({0} of {1} bytes read)")]
    Truncated(usize, usize),
    #[error(transparent)]
    Io(#[from] io::Error),
}

/// Reads whole frames from a byte stream, however the bytes are split across reads.
///
/// A read that times out (`WouldBlock`/`TimedOut`) keeps what was already read, so a socket
/// with a short read timeout can be polled without losing its place in the stream. The buffer
/// is reused between frames, so steady-state reading does not allocate.
pub struct FrameReader<R> {
    inner: R,
    buf: Vec<u8>,
    max: usize,
    header: [u8; 4],
    /// Bytes of the current frame read so far (header first, then payload).
    filled: usize,
}

impl<R: Read> FrameReader<R> {
    pub fn new(inner: R) -> Self {
        Self::with_limit(inner, DEFAULT_MAX_FRAME)
    }

    pub fn with_limit(inner: R, max: usize) -> Self {
        Self {
            inner,
            buf: Vec::with_capacity(4096),
            max,
            header: [0; 4],
            filled: 0,
        }
    }

    pub fn get_ref(&self) -> &R {
        &self.inner
    }

    /// Block until the next whole frame has arrived and return its payload.
    pub fn read_frame(&mut self) -> Result<&[u8], FrameError> {
        while self.filled < 4 {
            match self.inner.read(&mut self.header[self.filled..]) {
                Ok(0) if self.filled == 0 => return Err(FrameError::Closed),
                Ok(0) => return Err(FrameError::Truncated(self.filled, 4)),
                Ok(n) => self.filled += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(FrameError::Io(e)),
            }
            if self.filled == 4 {
                let len = u32::from_be_bytes(self.header) as usize;
                if len > self.max {
                    self.filled = 0;
                    return Err(FrameError::TooLarge(len, self.max));
                }
                self.buf.clear();
                self.buf.resize(len, 0);
            }
        }
        let len = self.buf.len();
        while self.filled - 4 < len {
            match self.inner.read(&mut self.buf[self.filled - 4..]) {
                Ok(0) => return Err(FrameError::Truncated(self.filled - 4, len)),
                Ok(n) => self.filled += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(FrameError::Io(e)),
            }
        }
        self.filled = 0;
        Ok(&self.buf)
    }
}

/// True for the errors a socket read timeout produces.
pub fn is_timeout(e: &FrameError) -> bool {
    matches!(e, FrameError::Io(io) if matches!(io.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut))
}

/// Append `payload` as one frame to `out`.
///
/// An empty payload makes rcssservermj wait for a frame that never comes and drop the agent,
/// so the caller must never send one; this is checked in debug builds.
pub fn encode_frame(payload: &[u8], out: &mut Vec<u8>) {
    debug_assert!(!payload.is_empty(), "an empty frame stalls rcssservermj");
    out.extend_from_slice(&(payload.len() as u32).to_be_bytes());
    out.extend_from_slice(payload);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reader that hands out at most `chunk` bytes per call.
    struct Trickle<'a> {
        data: &'a [u8],
        chunk: usize,
    }

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = self.chunk.min(buf.len()).min(self.data.len());
            buf[..n].copy_from_slice(&self.data[..n]);
            self.data = &self.data[n..];
            Ok(n)
        }
    }

    #[test]
    fn frames_split_over_many_reads_are_reassembled() {
        let mut wire = Vec::new();
        encode_frame(b"(time (now 1.00))", &mut wire);
        encode_frame(b"(syn)", &mut wire);
        let mut reader = FrameReader::new(Trickle {
            data: &wire,
            chunk: 1,
        });
        assert_eq!(reader.read_frame().unwrap(), b"(time (now 1.00))");
        assert_eq!(reader.read_frame().unwrap(), b"(syn)");
        assert!(matches!(reader.read_frame(), Err(FrameError::Closed)));
    }

    #[test]
    fn oversized_and_truncated_frames_are_errors() {
        let wire = (16u32 << 20).to_be_bytes();
        let mut reader = FrameReader::new(&wire[..]);
        assert!(matches!(
            reader.read_frame(),
            Err(FrameError::TooLarge(_, _))
        ));
        let mut wire = 10u32.to_be_bytes().to_vec();
        wire.extend_from_slice(b"abc");
        let mut reader = FrameReader::new(&wire[..]);
        assert!(matches!(
            reader.read_frame(),
            Err(FrameError::Truncated(3, 10))
        ));
        let mut reader = FrameReader::new(&[0u8, 0][..]);
        assert!(matches!(
            reader.read_frame(),
            Err(FrameError::Truncated(2, 4))
        ));
    }

    /// Reads that time out in the middle of a frame do not lose the bytes already read.
    struct Stutter {
        data: Vec<u8>,
        pos: usize,
        calls: usize,
    }

    impl Read for Stutter {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            self.calls += 1;
            if self.calls.is_multiple_of(2) {
                return Err(io::ErrorKind::WouldBlock.into());
            }
            let n = 3.min(buf.len()).min(self.data.len() - self.pos);
            buf[..n].copy_from_slice(&self.data[self.pos..self.pos + n]);
            self.pos += n;
            Ok(n)
        }
    }

    #[test]
    fn timeouts_mid_frame_resume_where_they_stopped() {
        let mut data = Vec::new();
        encode_frame(b"(time (now 2.00))(GS (t 0))", &mut data);
        let mut reader = FrameReader::new(Stutter {
            data,
            pos: 0,
            calls: 0,
        });
        let mut timeouts = 0;
        let frame = loop {
            match reader.read_frame() {
                Ok(f) => break f.to_vec(),
                Err(e) if is_timeout(&e) => timeouts += 1,
                Err(e) => panic!("{e}"),
            }
        };
        assert_eq!(frame, b"(time (now 2.00))(GS (t 0))");
        assert!(timeouts > 5);
    }
}
