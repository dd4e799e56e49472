//! Session files: what a scene needs to drive a fragment shader, and nothing more.
//!
//! A session is a JSON document (`sessions/*.json`) with `"schema": "reproj.session"` and
//! `"version": 1`. The full field reference, with units and defaults, is `SESSION.md` beside this
//! crate's `Cargo.toml`; in short:
//!
//! ```json
//! {
//!   "schema": "reproj.session", "version": 1,
//!   "resolution": [256, 256], "frames": 150, "fps": 30,
//!   "geometry": { "objects": [ { "mesh": { "sphere": { "radius": 1.0, "segments": 64 } },
//!                                "transform": { "keys": [ { "frame": 0, "rotation": { "axis_angle": { "axis": [0,1,0], "deg": 0 } } },
//!                                                         { "frame": 149, "rotation": { "axis_angle": { "axis": [0,1,0], "deg": 90 } } } ] } } ] },
//!   "camera": { "orbit": { "center": [0,0,0], "radius": 3, "height": 0.5, "start_deg": 0, "end_deg": 30 } },
//!   "light":  { "keys": [ { "frame": 0, "position": [4,4,4] } ] },
//!   "uniforms": { "shininess": 32, "base_color": [1, 0.9, 0.8], "wobble": { "keys": [ { "frame": 0, "value": 0 }, { "frame": 149, "value": 1 } ] } },
//!   "textures": { "albedo_map": { "kind": "noise", "size": 256, "params": { "scale": 8 } } },
//!   "samplers": { "linear_sampler": { "filter": "linear", "address": "repeat" } },
//!   "inputs": { "0": "position", "1": "normal", "2": "uv" }
//! }
//! ```
//!
//! Every key-framed quantity is linearly interpolated over the frame index and held constant
//! before its first key and after its last one; a single key is a constant.
//! Loading reports malformed documents with the JSON path of the offending field
//! (`camera.keys[1].eye: invalid length 2, expected an array of length 3`).

use std::path::{Path, PathBuf};

mod animate;
mod schema;
mod validate;

pub use animate::{CameraState, FrameState};
pub use schema::*;

/// The `$id` of the session's JSON Schema (the repository's copy, `docs/session.schema.json`).
pub const SESSION_SCHEMA_ID: &str = "https://example.invalid/reproj/docs/session.schema.json";

/// The session's JSON Schema (draft 2020-12), as published in `docs/session.schema.json` for
/// editors and other tools: generated from the types the loader reads, with its `$id`, and
/// `schema` and `version` held by `const`. The loader stays the authority (it also checks ranges,
/// key order and that files exist, and names the field at fault).
pub fn session_schema() -> serde_json::Value {
    let mut schema =
        serde_json::to_value(schemars::schema_for!(Session)).expect("a schema serializes");
    let root = schema.as_object_mut().expect("a schema is an object");
    root.insert("$id".into(), SESSION_SCHEMA_ID.into());
    let properties = root
        .get_mut("properties")
        .and_then(|p| p.as_object_mut())
        .expect("the session has properties");
    for (field, value) in [
        ("schema", serde_json::Value::from(SESSION_KIND.schema)),
        (
            "version",
            serde_json::Value::from(*SESSION_KIND.versions.end()),
        ),
    ] {
        if let Some(p) = properties.get_mut(field).and_then(|p| p.as_object_mut()) {
            p.insert("const".into(), value);
        }
    }
    schema
}

static OUTSIDE_PATHS_ALLOWED: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Let sessions name files outside their folder, for this process (`--allow-outside-paths`).
pub fn allow_outside_paths() {
    OUTSIDE_PATHS_ALLOWED.store(true, std::sync::atomic::Ordering::Relaxed);
}

/// True when [`allow_outside_paths`] was called (`--allow-outside-paths`).
pub fn outside_paths_allowed() -> bool {
    OUTSIDE_PATHS_ALLOWED.load(std::sync::atomic::Ordering::Relaxed)
}

/// Resolve `p`, named by a document in `base_dir` (a session, a variant's manifest), against that
/// folder. A path that leaves it (absolute, `..` above it, or a link out of it) is refused unless
/// [`allow_outside_paths`] was called: a document names files beside it, and one from elsewhere
/// must not read `/etc/passwd` or a user's keys. `document` names the document in the message
/// ("session", "manifest").
pub fn resolve_inside(base_dir: &Path, p: &Path, document: &str) -> Result<PathBuf, String> {
    let full = if p.is_absolute() {
        p.to_owned()
    } else {
        base_dir.join(p)
    };
    if outside_paths_allowed() {
        return Ok(full);
    }
    let lexically_inside = !p.is_absolute() && {
        let mut depth = 0i32;
        p.components().all(|c| {
            match c {
                std::path::Component::ParentDir => depth -= 1,
                std::path::Component::Normal(_) => depth += 1,
                _ => {}
            }
            depth >= 0
        })
    };
    let base = if base_dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base_dir
    };
    // Through links: both canonical, when the file exists (a missing file fails later, with
    // its own message).
    let linked_inside = match (std::fs::canonicalize(&full), std::fs::canonicalize(base)) {
        (Ok(f), Ok(b)) => f.starts_with(b),
        _ => true,
    };
    if lexically_inside && linked_inside {
        Ok(full)
    } else {
        Err(format!(
            "`{}` is outside the {document}'s folder {}: a {document} names files beside it (copy the file there, or pass --allow-outside-paths)",
            p.display(),
            base.display()
        ))
    }
}

impl Session {
    /// Resolve a path from the session file against its directory ([`resolve_inside`]: a path
    /// leaving it is refused unless [`allow_outside_paths`] was called).
    pub fn resolve(&self, p: &Path) -> Result<PathBuf, String> {
        resolve_inside(&self.base_dir, p, "session")
    }

    /// A short name for reports: the file name, else the description.
    pub fn display_name(&self) -> String {
        if self.path.as_os_str().is_empty() {
            self.description
                .clone()
                .unwrap_or_else(|| "(inline session)".into())
        } else {
            self.path.display().to_string()
        }
    }
}
