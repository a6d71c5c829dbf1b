//! `cargo fuzz run percept` (nightly): any bytes through framing and both percept dialects.
#![no_main]

use libero_model::ServerKind;
use libero_protocol::{parse_percept, FrameReader};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for server in [ServerKind::RcssMj, ServerKind::SimSpark] {
        let _ = parse_percept(data, server);
    }
    let mut reader = FrameReader::with_limit(data, 1 << 16);
    while let Ok(frame) = reader.read_frame() {
        let _ = parse_percept(frame, ServerKind::RcssMj);
    }
});
