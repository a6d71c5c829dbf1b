//! The typed blackboard: per-agent memory shared by the nodes of a tree.

use crate::library::Library;
use crate::value::{Value, ValueType};
use std::collections::HashMap;

/// Typed per-agent memory that survives library reloads.
#[derive(Debug, Clone)]
pub struct Blackboard {
    keys: HashMap<String, (u32, ValueType)>,
    pub(crate) values: Vec<Value>,
}

impl Blackboard {
    pub(crate) fn new(library: &Library) -> Self {
        let layout = library.blackboard_layout();
        let keys = layout
            .entries
            .iter()
            .enumerate()
            .map(|(i, (k, ty, _))| (k.clone(), (i as u32, *ty)))
            .collect();
        Self {
            keys,
            values: layout.entries.iter().map(|(_, _, v)| v.clone()).collect(),
        }
    }

    /// A new layout's blackboard keeping the values of entries whose key and type are unchanged.
    pub(crate) fn migrate(&self, library: &Library) -> Self {
        let mut next = Self::new(library);
        for (key, (slot, ty)) in &next.keys {
            if let Some((old_slot, old_ty)) = self.keys.get(key) {
                if old_ty == ty {
                    next.values[*slot as usize] = self.values[*old_slot as usize].clone();
                }
            }
        }
        next
    }

    /// Every entry, in slot order (the order of the library's declarations).
    pub fn entries(&self) -> impl Iterator<Item = (&str, &Value)> {
        let mut keys: Vec<(&str, u32)> = self
            .keys
            .iter()
            .map(|(k, (slot, _))| (k.as_str(), *slot))
            .collect();
        keys.sort_by_key(|(_, slot)| *slot);
        keys.into_iter()
            .map(move |(k, slot)| (k, &self.values[slot as usize]))
    }

    pub fn get(&self, key: &str) -> Option<&Value> {
        self.keys
            .get(key)
            .map(|(slot, _)| &self.values[*slot as usize])
    }

    /// Writes an entry; refuses unknown keys and values of the wrong type.
    pub fn set(&mut self, key: &str, value: Value) -> Result<(), String> {
        let (slot, ty) = self
            .keys
            .get(key)
            .ok_or_else(|| format!("unknown blackboard entry `{key}`"))?;
        if !value.value_type().fits(*ty) {
            return Err(format!(
                "blackboard entry `{key}` is {ty}, not {}",
                value.value_type()
            ));
        }
        self.values[*slot as usize] = value.coerce(*ty);
        Ok(())
    }
}
