//! Data files shipped with the engine or named by the user: read, parsed and validated, with every
//! error located in its file.

use crate::location::{parse_ron, Located};
use serde::de::DeserializeOwned;
use std::path::Path;

/// Why a data file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{}", .0.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("\n"))]
    Invalid(Vec<Located>),
    #[error("no built-in {kind} named `{name}` (known: {known})")]
    UnknownBuiltin {
        kind: &'static str,
        name: String,
        known: String,
    },
}

/// A kind of data file: what it is called, what ships with the engine, how it is checked.
pub(crate) trait DataFile: Sized + DeserializeOwned {
    const KIND: &'static str;
    /// Shipped files as (name, text).
    const BUILTIN: &'static [(&'static str, &'static str)];
    /// Every semantic problem, located in `text` where possible.
    fn problems(&self, file: &str, text: &str) -> Vec<Located>;
}

pub(crate) fn builtin_names<T: DataFile>() -> Vec<&'static str> {
    T::BUILTIN.iter().map(|(name, _)| *name).collect()
}

/// A shipped file by name (case-insensitive), parsed and validated.
pub(crate) fn builtin<T: DataFile>(name: &str) -> Result<T, DataError> {
    let (file, text) = T::BUILTIN
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .ok_or_else(|| DataError::UnknownBuiltin {
            kind: T::KIND,
            name: name.to_string(),
            known: builtin_names::<T>().join(", "),
        })?;
    from_ron(&format!("<builtin>/{file}.ron"), text)
}

pub(crate) fn load<T: DataFile>(path: &Path) -> Result<T, DataError> {
    let text = std::fs::read_to_string(path).map_err(|source| DataError::Io {
        path: path.display().to_string(),
        source,
    })?;
    from_ron(&path.display().to_string(), &text)
}

/// Parse and validate RON text; `file` names the source in error messages.
pub(crate) fn from_ron<T: DataFile>(file: &str, text: &str) -> Result<T, DataError> {
    let value: T = parse_ron(file, text).map_err(|e| DataError::Invalid(vec![e]))?;
    let errors = value.problems(file, text);
    if errors.is_empty() {
        Ok(value)
    } else {
        Err(DataError::Invalid(errors))
    }
}
