//! The interface the agent implements to give trees their world: queries, conditions, actions.

use crate::value::{Status, Value, Vec2};
use crate::vocabulary::NativeId;

/// Evaluated arguments of a native call, in the order of the node's declared parameters
/// (omitted parameters hold their defaults, Ints are widened to Float where declared).
#[derive(Debug, Clone, Copy)]
pub struct Args<'a>(pub &'a [Value]);

impl<'a> Args<'a> {
    pub fn get(&self, index: usize) -> Option<&'a Value> {
        self.0.get(index)
    }
    pub fn float(&self, index: usize) -> f64 {
        self.0.get(index).map_or(0.0, Value::as_f64)
    }
    pub fn int(&self, index: usize) -> i64 {
        match self.0.get(index) {
            Some(Value::Int(i)) => *i,
            other => other.map_or(0, |v| v.as_f64() as i64),
        }
    }
    pub fn bool(&self, index: usize) -> bool {
        self.0.get(index).is_some_and(Value::as_bool)
    }
    pub fn vec2(&self, index: usize) -> Vec2 {
        self.0.get(index).map_or(Vec2::default(), Value::as_vec2)
    }
    pub fn str(&self, index: usize) -> &'a str {
        self.0.get(index).map_or("", Value::as_str)
    }
    pub fn len(&self) -> usize {
        self.0.len()
    }
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// What the agent provides to the trees: its world queries, conditions and actions.
pub trait Host {
    /// Simulation time in seconds, used by Timeout, Cooldown and Wait.
    fn now(&self) -> f64;
    fn query(&self, id: NativeId, args: Args) -> Value;
    fn condition(&self, id: NativeId, args: Args) -> bool;
    /// Called every tick while the action runs.
    fn action(&mut self, id: NativeId, args: Args) -> Status;
    /// Called when a running action is abandoned (its branch lost, timed out or was reloaded away).
    fn halt(&mut self, _id: NativeId, _args: Args) {}
}
