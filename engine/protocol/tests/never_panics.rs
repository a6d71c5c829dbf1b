//! No input, however broken, makes the reader panic.

use libero_model::ServerKind;
use libero_protocol::{parse_percept, sexp, FrameReader};
use proptest::prelude::*;

/// Visit every node so lazily-scanned lists are fully exercised.
fn walk(text: &str) -> usize {
    let mut count = 0;
    let mut stack: Vec<sexp::List> = Vec::new();
    for item in sexp::top_level(text) {
        match item {
            Ok(sexp::Sexp::List(l)) => stack.push(l),
            Ok(_) => count += 1,
            Err(_) => break,
        }
        while let Some(l) = stack.pop() {
            for child in l.iter() {
                count += 1;
                if let Some(inner) = child.as_list() {
                    stack.push(inner);
                }
            }
        }
    }
    count
}

fn sample_like() -> impl Strategy<Value = String> {
    // Fragments of real messages shuffled together hit the typed reader's paths far more often
    // than uniform bytes do.
    let pieces = prop::sample::select(vec![
        "(",
        ")",
        " ",
        "(time (now 1.0))",
        "(GS (t 0)(pm PlayOn)(unum x)",
        "(HJ (n q_hj1)(ax nan)(vx 1))",
        "(See (B (pol 1 2))",
        "(P (team a)(id 99999999999)(head (pol 1 2 3)))",
        "(L (pol 1 2 3))",
        "(MIC hear (1 abc)(x))",
        "(hear a b c d e)",
        "(hear 1 self)",
        "(GYR (rt 1 2 3 4))",
        "é",
        "\0",
        "(FRP (n lf)(c 1 2 3)(f 1 2))",
        "-1e309",
        "(quat (n x) (q 1 0 0 0))",
    ]);
    prop::collection::vec(pieces, 0..60).prop_map(|v| v.concat())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        for server in [ServerKind::RcssMj, ServerKind::SimSpark] {
            let _ = parse_percept(&bytes, server);
        }
        if let Ok(text) = std::str::from_utf8(&bytes) {
            walk(text);
        }
        let mut reader = FrameReader::with_limit(&bytes[..], 4096);
        while reader.read_frame().is_ok() {}
    }

    #[test]
    fn message_fragments_never_panic(text in sample_like()) {
        for server in [ServerKind::RcssMj, ServerKind::SimSpark] {
            let _ = parse_percept(text.as_bytes(), server);
        }
        walk(&text);
    }
}
