//! Values flowing through trees: constants, blackboard entries and world-query results.

use serde::Serialize;
use std::fmt;
use std::sync::Arc;

/// A point or vector on the field, in metres, in the team's own frame (own goal at −x).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Vec2 {
    pub x: f64,
    pub y: f64,
}

impl Vec2 {
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }
    pub fn distance(self, other: Vec2) -> f64 {
        ((self.x - other.x).powi(2) + (self.y - other.y).powi(2)).sqrt()
    }
    pub fn lerp(self, other: Vec2, t: f64) -> Vec2 {
        Vec2::new(
            self.x + (other.x - self.x) * t,
            self.y + (other.y - self.y) * t,
        )
    }
}

/// The static type of a parameter, blackboard entry or query result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum ValueType {
    Bool,
    Int,
    Float,
    Vec2,
    String,
}

impl ValueType {
    pub fn name(self) -> &'static str {
        match self {
            ValueType::Bool => "Bool",
            ValueType::Int => "Int",
            ValueType::Float => "Float",
            ValueType::Vec2 => "Vec2",
            ValueType::String => "String",
        }
    }

    pub fn from_name(name: &str) -> Option<ValueType> {
        Self::ALL.into_iter().find(|ty| ty.name() == name)
    }

    pub const ALL: [ValueType; 5] = [
        ValueType::Bool,
        ValueType::Int,
        ValueType::Float,
        ValueType::Vec2,
        ValueType::String,
    ];

    /// Whether a value of type `self` may be used where `expected` is required.
    /// Integers widen to floats because `2` for a distance is what people write.
    pub fn fits(self, expected: ValueType) -> bool {
        self == expected || (self == ValueType::Int && expected == ValueType::Float)
    }

    /// Numeric types can feed utility response curves and comparisons.
    pub fn is_scalar(self) -> bool {
        matches!(self, ValueType::Bool | ValueType::Int | ValueType::Float)
    }
}

impl fmt::Display for ValueType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A runtime value. Strings are shared so cloning a value never allocates.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    Vec2(Vec2),
    String(Arc<str>),
}

impl Value {
    pub fn value_type(&self) -> ValueType {
        match self {
            Value::Bool(_) => ValueType::Bool,
            Value::Int(_) => ValueType::Int,
            Value::Float(_) => ValueType::Float,
            Value::Vec2(_) => ValueType::Vec2,
            Value::String(_) => ValueType::String,
        }
    }

    /// Scalar view used by curves and comparisons; non-scalars read as 0.
    pub fn as_f64(&self) -> f64 {
        match self {
            Value::Bool(b) => f64::from(u8::from(*b)),
            Value::Int(i) => *i as f64,
            Value::Float(f) => *f,
            Value::Vec2(_) | Value::String(_) => 0.0,
        }
    }

    pub fn as_bool(&self) -> bool {
        match self {
            Value::Bool(b) => *b,
            other => other.as_f64() != 0.0,
        }
    }

    pub fn as_vec2(&self) -> Vec2 {
        match self {
            Value::Vec2(v) => *v,
            _ => Vec2::default(),
        }
    }

    pub fn as_str(&self) -> &str {
        match self {
            Value::String(s) => s,
            _ => "",
        }
    }

    /// The zero value of a type, used for fresh blackboard entries and failed queries.
    pub fn default_of(ty: ValueType) -> Value {
        match ty {
            ValueType::Bool => Value::Bool(false),
            ValueType::Int => Value::Int(0),
            ValueType::Float => Value::Float(0.0),
            ValueType::Vec2 => Value::Vec2(Vec2::default()),
            ValueType::String => Value::String(Arc::from("")),
        }
    }

    /// Converts an Int into a Float when the declared type asks for one.
    pub fn coerce(self, ty: ValueType) -> Value {
        match (self, ty) {
            (Value::Int(i), ValueType::Float) => Value::Float(i as f64),
            (value, _) => value,
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::Int(i) => write!(f, "{i}"),
            Value::Float(x) => write!(f, "{x:?}"),
            Value::Vec2(v) => write!(f, "({:?}, {:?})", v.x, v.y),
            Value::String(s) => write!(f, "{s:?}"),
        }
    }
}

impl Serialize for Value {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Value::Bool(b) => serializer.serialize_bool(*b),
            Value::Int(i) => serializer.serialize_i64(*i),
            Value::Float(x) => serializer.serialize_f64(*x),
            Value::Vec2(v) => [v.x, v.y].serialize(serializer),
            Value::String(s) => serializer.serialize_str(s),
        }
    }
}

/// The outcome of ticking a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, serde::Deserialize)]
pub enum Status {
    Running,
    Success,
    Failure,
}

impl Status {
    pub fn from_bool(ok: bool) -> Status {
        if ok {
            Status::Success
        } else {
            Status::Failure
        }
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Status::Running => "Running",
            Status::Success => "Success",
            Status::Failure => "Failure",
        })
    }
}
