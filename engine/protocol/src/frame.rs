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
/// Each read asks for as much as the buffer holds, so a frame that has arrived whole comes in
/// one read (length prefix and payload together, and the start of the next frame if it is
/// there too) instead of one read for the prefix and one for the payload. A read that times
/// out (`WouldBlock`/`TimedOut`) keeps what was already read, so a socket with a short read
/// timeout can be polled without losing its place in the stream. The buffer is reused, so
/// steady-state reading does not allocate.
pub struct FrameReader<R> {
    inner: R,
    /// Received bytes live in `buf[start..end]`; the buffer's length is its usable size.
    buf: Vec<u8>,
    start: usize,
    end: usize,
    /// Bytes of the frame handed out last, dropped at the next call.
    handed_out: usize,
    max: usize,
}

/// What one read asks for at least: percepts are 1–25 kB.
const READ_SIZE: usize = 64 * 1024;

impl<R: Read> FrameReader<R> {
    pub fn new(inner: R) -> Self {
        Self::with_limit(inner, DEFAULT_MAX_FRAME)
    }

    pub fn with_limit(inner: R, max: usize) -> Self {
        Self {
            inner,
            buf: vec![0; READ_SIZE],
            start: 0,
            end: 0,
            handed_out: 0,
            max,
        }
    }

    pub fn get_ref(&self) -> &R {
        &self.inner
    }

    /// Drop the frame handed out last; then where the next whole frame lies in the buffer
    /// (`Ok(Ok((start, len)))`, handed out now), or how many bytes from `start` it needs
    /// (`Ok(Err(wanted))`).
    fn take_whole(&mut self) -> Result<Result<(usize, usize), usize>, FrameError> {
        self.start += std::mem::take(&mut self.handed_out);
        let held = self.end - self.start;
        if held < 4 {
            return Ok(Err(4));
        }
        let header: [u8; 4] = self.buf[self.start..self.start + 4]
            .try_into()
            .expect("four bytes");
        let len = u32::from_be_bytes(header) as usize;
        if len > self.max {
            // The stream has lost its framing: nothing after this can be trusted.
            self.start = self.end;
            return Err(FrameError::TooLarge(len, self.max));
        }
        if held < 4 + len {
            return Ok(Err(4 + len));
        }
        self.handed_out = 4 + len;
        Ok(Ok((self.start + 4, len)))
    }

    /// The next frame if it is already whole in the buffer, without reading: after one read
    /// brought several frames (a server catching up), the rest are taken from here so that
    /// a read happens only when the socket has something.
    pub fn buffered_frame(&mut self) -> Option<Result<&[u8], FrameError>> {
        match self.take_whole() {
            Ok(Ok((start, len))) => Some(Ok(&self.buf[start..start + len])),
            Ok(Err(_)) => None,
            Err(e) => Some(Err(e)),
        }
    }

    /// Block until the next whole frame has arrived and return its payload.
    pub fn read_frame(&mut self) -> Result<&[u8], FrameError> {
        loop {
            let wanted = match self.take_whole()? {
                Ok((start, len)) => return Ok(&self.buf[start..start + len]),
                Err(wanted) => wanted,
            };
            let held = self.end - self.start;
            // Room for the rest of this frame after the bytes held, at the buffer's front.
            if self.start > 0 {
                self.buf.copy_within(self.start..self.end, 0);
                self.end -= self.start;
                self.start = 0;
            }
            if self.buf.len() < wanted {
                self.buf.resize(wanted, 0);
            }
            match self.inner.read(&mut self.buf[self.end..]) {
                Ok(0) if held == 0 => return Err(FrameError::Closed),
                Ok(0) if held < 4 => return Err(FrameError::Truncated(held, 4)),
                Ok(0) => return Err(FrameError::Truncated(held - 4, wanted - 4)),
                Ok(n) => self.end += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(FrameError::Io(e)),
            }
        }
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

    /// Counts the reads it serves (whole chunks of what it holds).
    struct Counted<'a> {
        data: &'a [u8],
        reads: usize,
    }

    impl Read for Counted<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            self.reads += 1;
            let n = buf.len().min(self.data.len());
            buf[..n].copy_from_slice(&self.data[..n]);
            self.data = &self.data[n..];
            Ok(n)
        }
    }

    #[test]
    fn a_frame_that_has_arrived_whole_takes_one_read() {
        let payload = vec![b'x'; 3000];
        let mut wire = Vec::new();
        encode_frame(&payload, &mut wire);
        let mut reader = FrameReader::new(Counted {
            data: &wire,
            reads: 0,
        });
        assert_eq!(reader.read_frame().unwrap(), &payload[..]);
        assert_eq!(reader.get_ref().reads, 1);
        // Several frames in one read are handed out one by one without reading again.
        let mut wire = Vec::new();
        for i in 0..5u8 {
            encode_frame(&[b'a' + i; 10], &mut wire);
        }
        let mut reader = FrameReader::new(Counted {
            data: &wire,
            reads: 0,
        });
        for i in 0..5u8 {
            assert_eq!(reader.read_frame().unwrap(), &[b'a' + i; 10]);
        }
        assert_eq!(reader.get_ref().reads, 1);
        // A frame larger than the buffer grows it.
        let big = vec![b'y'; 3 * READ_SIZE];
        let mut wire = Vec::new();
        encode_frame(&big, &mut wire);
        let mut reader = FrameReader::new(&wire[..]);
        assert_eq!(reader.read_frame().unwrap(), &big[..]);
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

    #[test]
    fn frames_already_buffered_are_handed_out_without_another_read() {
        let mut bytes = Vec::new();
        for payload in [&b"(a)"[..], b"(bb)", b"(ccc)"] {
            bytes.extend_from_slice(&(payload.len() as u32).to_be_bytes());
            bytes.extend_from_slice(payload);
        }
        // The third frame arrives only partly with the first read.
        let cut = bytes.len() - 2;
        let mut reader = FrameReader::new(Trickle {
            data: &bytes[..cut],
            chunk: usize::MAX,
        });
        assert_eq!(reader.read_frame().unwrap(), b"(a)");
        assert_eq!(reader.buffered_frame().unwrap().unwrap(), b"(bb)");
        assert!(reader.buffered_frame().is_none(), "the third is not whole");
        let mut corrupt = FrameReader::with_limit(&[0u8, 0, 0, 2, b'o', b'k', 0, 9, 0, 0][..], 8);
        assert_eq!(corrupt.read_frame().unwrap(), b"ok");
        assert!(matches!(
            corrupt.buffered_frame(),
            Some(Err(FrameError::TooLarge(..)))
        ));
    }
}
