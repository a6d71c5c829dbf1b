//! Shared helpers for the live tests.
