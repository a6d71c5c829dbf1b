//! Free loopback ports for a server: the requested ones if free, else ones chosen outside the
//! range the OS hands out for outgoing connections.

use crate::ServerError;
use std::net::TcpListener;

/// Ports chosen for a server without requested ones: below Linux's ephemeral range
/// (32768–60999). A free port from the OS (`bind(0)`) lies in that range, and between our
/// check and the server's own bind any outgoing connection on the machine (agents, other
/// tests' monitors) may be handed it as its source port: CI once lost a test to that.
const AUTO_PORTS: std::ops::Range<u16> = 20000..32000;

/// The requested ports if free, else free ones from `AUTO_PORTS`.
pub(crate) fn choose_ports(
    agent: Option<u16>,
    monitor: Option<u16>,
) -> Result<(u16, u16), ServerError> {
    use std::hash::{BuildHasher, RandomState};
    let requested =
        |p: u16| TcpListener::bind(("127.0.0.1", p)).map_err(|_| ServerError::PortTaken(p));
    let random = RandomState::new();
    let mut candidates = (0u32..).map(|k| {
        let span = u64::from(AUTO_PORTS.end - AUTO_PORTS.start);
        AUTO_PORTS.start + (random.hash_one(k) % span) as u16
    });
    let mut free = |held: Option<u16>| -> Result<TcpListener, ServerError> {
        candidates
            .by_ref()
            .take(500)
            .filter(|&p| Some(p) != held)
            .find_map(|p| TcpListener::bind(("127.0.0.1", p)).ok())
            .ok_or_else(|| {
                ServerError::Io(
                    format!("finding a free port in {AUTO_PORTS:?}"),
                    std::io::Error::from(std::io::ErrorKind::AddrInUse),
                )
            })
    };
    let port_of = |l: &TcpListener| {
        l.local_addr()
            .map(|a| a.port())
            .map_err(|e| ServerError::Io("port".into(), e))
    };
    // Hold both at once so the same port cannot be chosen twice.
    let a = match agent {
        Some(p) => requested(p)?,
        None => free(monitor)?,
    };
    let m = match monitor {
        Some(p) => requested(p)?,
        None => free(Some(port_of(&a)?))?,
    };
    Ok((port_of(&a)?, port_of(&m)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chosen_ports_are_free_distinct_and_outside_the_ephemeral_range() {
        let _turn = crate::PORT_TESTS.lock().unwrap_or_else(|p| p.into_inner());
        for _ in 0..20 {
            let (a, m) = choose_ports(None, None).unwrap();
            assert_ne!(a, m);
            assert!(
                AUTO_PORTS.contains(&a) && AUTO_PORTS.contains(&m),
                "{a} {m}"
            );
            // Free: both can be bound now that the check has let them go.
            let _a = TcpListener::bind(("127.0.0.1", a)).unwrap();
            let _m = TcpListener::bind(("127.0.0.1", m)).unwrap();
        }
    }

    #[test]
    fn a_requested_port_that_is_taken_is_named() {
        let _turn = crate::PORT_TESTS.lock().unwrap_or_else(|p| p.into_inner());
        let taken = TcpListener::bind(("127.0.0.1", 0)).unwrap();
        let port = taken.local_addr().unwrap().port();
        assert!(matches!(
            choose_ports(Some(port), None),
            Err(ServerError::PortTaken(p)) if p == port
        ));
        // A free requested port is kept; the other is chosen. (Not the port just dropped: in the
        // ephemeral range any connection on the machine may take it at once, as happened in CI.)
        let (free, _) = choose_ports(None, None).unwrap();
        let (a, m) = choose_ports(Some(free), None).unwrap();
        assert_eq!(a, free);
        assert!(AUTO_PORTS.contains(&m) && m != free);
    }
}
