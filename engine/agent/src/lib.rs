//! Agent runtime: connection, per-cycle pipeline, team hosting, reconnects.
