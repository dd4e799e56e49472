//! Loading a session: parse the JSON (the failing field named by its path), expand its glTF
//! scene (`gltf::expand`), put key frames in order, validate. Above [`crate::session`]
//! (the types, validation, animation) and `gltf`, which both sit below it: the session
//! types know nothing of glTF files.

use std::path::Path;

use crate::session::{SESSION_KIND, Session, SessionError};

impl Session {
    /// Read, parse and validate a session file. Relative paths inside it resolve against its
    /// directory.
    pub fn load(path: impl AsRef<Path>) -> Result<Session, SessionError> {
        let path = path.as_ref();
        let text = reproj_io::read_input_string(path, reproj_io::InputKind::Json)
            .map_err(reproj_io::ReadError::from)?;
        let base = path.parent().map(Path::to_owned).unwrap_or_default();
        Self::from_json(&text, path, &base)
    }

    /// Parse and validate session JSON text. `path` is used in messages, `base_dir` resolves
    /// relative paths.
    pub fn from_json(text: &str, path: &Path, base_dir: &Path) -> Result<Session, SessionError> {
        let mut s: Session = reproj_io::parse_json(text, path, &SESSION_KIND)?;
        s.base_dir = base_dir.to_owned();
        s.path = path.to_owned();
        crate::gltf::expand(&mut s)?;
        s.sort_keys();
        s.validate()?;
        Ok(s)
    }
}
