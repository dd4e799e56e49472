//! Values of the shader's uniforms and storage buffers: constants, key frames, structs and
//! arrays of them, read by hand so that a bad value names what was expected.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A uniform field value: a constant (number, array, nested arrays: flattened in order),
/// `{"keys": [{"frame": f, "value": ...}, ...]}` interpolated per component, an object of a
/// struct's members by name (`{"color": [1, 1, 1], "intensity": 3}`, nesting as deep as the
/// structs do), or a list of such objects for an array of structs. An object whose only key is
/// `keys` is key frames, never a struct with a member named `keys`.
///
/// Read by hand rather than by serde's untagged enums so that a bad value names what was expected
/// and what was found.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum UniformValue {
    Keys {
        keys: Vec<UniformKey>,
    },
    Const(Value),
    /// A struct's members by name.
    Struct(BTreeMap<String, UniformValue>),
    /// The elements of an array of structs.
    Array(Vec<UniformValue>),
}

/// One step of the path of a uniform leaf inside a (nested) struct: a member name or an index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathStep<'a> {
    Member(&'a str),
    Index(usize),
}

/// The steps of a leaf path as reflection writes it (`sun.color`, `lights[2].position`).
pub fn path_steps(path: &str) -> Vec<PathStep<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (name, rest) = part.split_once('[').unwrap_or((part, ""));
        if !name.is_empty() {
            out.push(PathStep::Member(name));
        }
        for idx in rest.split('[') {
            if let Ok(i) = idx.trim_end_matches(']').parse() {
                out.push(PathStep::Index(i));
            }
        }
    }
    out
}

impl UniformValue {
    /// The value at `steps` below this one (`self` for no steps). An index into a constant list
    /// of numbers is not a step: arrays of scalars and vectors are one leaf.
    pub fn lookup(&self, steps: &[PathStep<'_>]) -> Option<&UniformValue> {
        let Some((first, rest)) = steps.split_first() else {
            return Some(self);
        };
        match (self, first) {
            (UniformValue::Struct(m), PathStep::Member(n)) => m.get(*n)?.lookup(rest),
            (UniformValue::Array(a), PathStep::Index(i)) => a.get(*i)?.lookup(rest),
            _ => None,
        }
    }

    /// Whether this is a leaf (numbers, constant or key-framed) rather than a struct or an array
    /// of structs.
    pub fn is_leaf(&self) -> bool {
        matches!(self, UniformValue::Keys { .. } | UniformValue::Const(_))
    }

    /// Read one value from JSON; the error says what was expected and what was found.
    pub fn from_json(v: serde_json::Value) -> Result<UniformValue, String> {
        use serde_json::Value as J;
        let kind = |v: &J| match v {
            J::Null => "null",
            J::Bool(_) => "a boolean",
            J::Number(_) => "a number",
            J::String(_) => "a string",
            J::Array(_) => "a list",
            J::Object(_) => "an object",
        };
        const EXPECTED: &str = "expected a number, a list of numbers, {\"keys\": [{\"frame\", \"value\"}, ...]}, an object of struct members or a list of such objects";
        match v {
            J::Object(m) if m.len() == 1 && m.contains_key("keys") => {
                let keys = m.into_iter().next().map(|(_, k)| k).unwrap_or(J::Null);
                serde_json::from_value(keys)
                    .map(|keys| UniformValue::Keys { keys })
                    .map_err(|e| format!("key frames: {e}"))
            }
            J::Object(m) => {
                let mut out = BTreeMap::new();
                for (k, v) in m {
                    let v = UniformValue::from_json(v).map_err(|e| format!("member `{k}`: {e}"))?;
                    out.insert(k, v);
                }
                Ok(UniformValue::Struct(out))
            }
            J::Array(items) if !items.is_empty() && items.iter().all(J::is_object) => {
                let mut out = Vec::new();
                for (i, v) in items.into_iter().enumerate() {
                    out.push(UniformValue::from_json(v).map_err(|e| format!("[{i}]: {e}"))?);
                }
                Ok(UniformValue::Array(out))
            }
            v => {
                let found = kind(&v);
                Value::from_json(&v)
                    .map(UniformValue::Const)
                    .ok_or_else(|| format!("{EXPECTED}; found {found}"))
            }
        }
    }
}

impl<'de> Deserialize<'de> for UniformValue {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        UniformValue::from_json(v).map_err(serde::de::Error::custom)
    }
}

/// One key of an animated uniform.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UniformKey {
    #[serde(default)]
    pub frame: f32,
    pub value: Value,
}

/// A number or a (nested) list of numbers.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum Value {
    Number(f64),
    List(Vec<Value>),
}

impl Value {
    /// A number or a (nested) list of numbers; `None` for anything else (an empty list is a list).
    fn from_json(v: &serde_json::Value) -> Option<Value> {
        match v {
            serde_json::Value::Number(n) => n.as_f64().map(Value::Number),
            serde_json::Value::Array(items) => items
                .iter()
                .map(Value::from_json)
                .collect::<Option<Vec<_>>>()
                .map(Value::List),
            _ => None,
        }
    }

    /// All numbers, depth first.
    pub fn flatten(&self) -> Vec<f64> {
        let mut out = Vec::new();
        fn go(v: &Value, out: &mut Vec<f64>) {
            match v {
                Value::Number(x) => out.push(*x),
                Value::List(l) => l.iter().for_each(|v| go(v, out)),
            }
        }
        go(self, &mut out);
        out
    }
}
