//! The versioned-JSON reader: every document reproj reads back (session, profile, manifest)
//! names its `"schema"` and `"version"`; they are checked first, so an old or foreign file gets
//! "this is a reproj.profile version 1, this reproj reads 2–4" rather than a missing field.

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

/// What kind of document is expected.
#[derive(Debug, Clone)]
pub struct Kind {
    /// The `"schema"` string, e.g. `reproj.profile`.
    pub schema: &'static str,
    /// The versions this reproj reads.
    pub versions: RangeInclusive<u32>,
    /// What to do about a version this reproj does not read (e.g. "re-run `reproj analyze`"),
    /// appended to that message; empty for none.
    pub hint: &'static str,
}

/// A document that could not be read. Every variant names the file; `Syntax` and `Field` also
/// the place in it.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Not a regular file, too large, or not text ([`crate::read_input`]).
    #[error(transparent)]
    Input(#[from] crate::InputError),
    /// Not JSON at all.
    #[error("{path}:{line}:{column}: not valid JSON: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// JSON, but not a document of the expected schema.
    #[error("{path}: field `schema`: expected \"{expected}\", found {found}")]
    Schema {
        path: PathBuf,
        expected: &'static str,
        found: String,
    },
    /// The right schema in a version this reproj does not read.
    #[error("{path}: field `version`: {schema} version {found} is not one this reproj reads ({}){}", versions(.supported), hint_suffix(.hint))]
    Version {
        path: PathBuf,
        schema: &'static str,
        found: String,
        supported: RangeInclusive<u32>,
        hint: &'static str,
    },
    /// A field is missing or has the wrong type. `field` is its path, e.g. `geometry.objects[0].mesh`.
    #[error("{path}: field `{field}`: {message}")]
    Field {
        path: PathBuf,
        field: String,
        message: String,
    },
}

fn hint_suffix(hint: &str) -> String {
    if hint.is_empty() {
        String::new()
    } else {
        format!("; {hint}")
    }
}

fn versions(r: &RangeInclusive<u32>) -> String {
    if r.start() == r.end() {
        format!("version {}", r.start())
    } else {
        format!("versions {} to {}", r.start(), r.end())
    }
}

/// Read and parse the versioned JSON document at `path`.
pub fn read_json<T: DeserializeOwned>(path: &Path, kind: &Kind) -> Result<T, ReadError> {
    let text = crate::read_input_string(path, crate::InputKind::Json)?;
    parse_json(&text, path, kind)
}

/// Parse a versioned JSON document; `path` is used in messages only.
pub fn parse_json<T: DeserializeOwned>(
    text: &str,
    path: &Path,
    kind: &Kind,
) -> Result<T, ReadError> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| ReadError::Syntax {
        path: path.to_owned(),
        line: e.line(),
        column: e.column(),
        message: strip_position(&e.to_string()),
    })?;
    let shown =
        |v: Option<&serde_json::Value>| v.map_or_else(|| "nothing".into(), |v| v.to_string());
    let schema = value.get("schema");
    if schema.and_then(|s| s.as_str()) != Some(kind.schema) {
        return Err(ReadError::Schema {
            path: path.to_owned(),
            expected: kind.schema,
            found: shown(schema),
        });
    }
    let version = value.get("version");
    let readable = version
        .and_then(serde_json::Value::as_u64)
        .is_some_and(|v| u32::try_from(v).is_ok_and(|v| kind.versions.contains(&v)));
    if !readable {
        return Err(ReadError::Version {
            path: path.to_owned(),
            schema: kind.schema,
            found: shown(version),
            supported: kind.versions.clone(),
            hint: kind.hint,
        });
    }
    // Typed, from the text again: serde_json then reports the line and column of a bad field.
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        ReadError::Field {
            path: path.to_owned(),
            field: if field == "." {
                "(document)".into()
            } else {
                field
            },
            message: e.into_inner().to_string(),
        }
    })
}

/// serde_json's syntax messages end in " at line L column C"; the error shows those up front.
fn strip_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_owned(),
        None => message.to_owned(),
    }
}
