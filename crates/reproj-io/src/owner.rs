//! Whose file is it? Before a command spends minutes rendering, [`check_target`] makes sure its
//! output path can be written and that writing it replaces nothing but reproj's own output: a
//! user's notes given by mistake as `--out` are refused, not overwritten.

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::write::WriteError;

/// What an existing file at an output path must be for reproj to replace it.
#[derive(Debug, Clone, Copy)]
pub enum Owner {
    /// A JSON document whose top-level `"schema"` is one of these (a profile, a report).
    Json(&'static [&'static str]),
    /// A text file holding this marker within its first 4 KiB (the HTML report's title).
    Marker(&'static str),
    /// An image of the kind its extension names (`.svg`, `.png`): the charts beside a profile.
    Image,
}

impl Owner {
    /// Whether `bytes`, the start (or all) of an existing file at `path`, is reproj's.
    fn owns(self, path: &Path, bytes: &[u8]) -> bool {
        match self {
            Owner::Json(schemas) => serde_json::from_slice::<serde_json::Value>(bytes)
                .ok()
                .and_then(|v| v.get("schema")?.as_str().map(str::to_owned))
                .is_some_and(|s| schemas.contains(&s.as_str())),
            Owner::Marker(m) => {
                let head = &bytes[..bytes.len().min(4096)];
                String::from_utf8_lossy(head).contains(m)
            }
            Owner::Image => match path.extension().and_then(|e| e.to_str()) {
                Some("png") => bytes.starts_with(b"\x89PNG\r\n\x1a\n"),
                Some("svg") => {
                    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(512)]);
                    let head = head.trim_start();
                    head.starts_with("<svg") || head.starts_with("<?xml")
                }
                _ => false,
            },
        }
    }

    fn what(self) -> String {
        match self {
            Owner::Json(schemas) => format!("a {} document", schemas.join(" or ")),
            Owner::Marker(_) => "a page reproj wrote".into(),
            Owner::Image => "a chart reproj wrote".into(),
        }
    }
}

/// Check, before any work, that `path` can be written by this command: it is not a directory, an
/// existing file there is `owner`'s (reproj's own output of this kind), and its directory (or the
/// nearest existing ancestor, which the write would create the rest under) accepts new files.
///
/// Nothing is left behind: the writability probe is a hidden file removed at once.
pub fn check_target(path: &Path, owner: Owner) -> Result<(), WriteError> {
    let refuse = |why: String| {
        Err(WriteError::NotOurs {
            path: path.to_owned(),
            why,
        })
    };
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(io(path, e)),
        Ok(m) if m.is_dir() => return refuse("it is a directory; give a file path".into()),
        Ok(m) if m.file_type().is_symlink() => {
            return refuse("it is a symbolic link; give the file itself".into());
        }
        Ok(m) if !m.is_file() => return refuse("it is not a regular file".into()),
        Ok(_) => {
            let mut bytes = Vec::new();
            let limit = match owner {
                // A profile is read whole to check its schema (a few MB at most).
                Owner::Json(_) => 256 << 20,
                Owner::Marker(_) | Owner::Image => 4096,
            };
            std::fs::File::open(path)
                .and_then(|f| f.take(limit).read_to_end(&mut bytes))
                .map_err(|e| io(path, e))?;
            if !owner.owns(path, &bytes) {
                return refuse(format!(
                    "it exists and is not {}; reproj only replaces its own output (move it, or choose another path)",
                    owner.what()
                ));
            }
        }
    }
    probe_dir(path)
}

/// The nearest existing ancestor of `path`'s directory must be a directory that accepts a new file.
fn probe_dir(path: &Path) -> Result<(), WriteError> {
    let mut dir: PathBuf = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_owned);
    loop {
        match std::fs::metadata(&dir) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(WriteError::NotOurs {
                    path: path.to_owned(),
                    why: format!("{} is not a directory", dir.display()),
                });
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => match dir.parent() {
                Some(p) if !p.as_os_str().is_empty() => dir = p.to_owned(),
                _ => {
                    dir = PathBuf::from(".");
                    break;
                }
            },
            Err(e) => return Err(io(&dir, e)),
        }
    }
    let probe = dir.join(format!(".reproj-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(io(path, e)),
    }
}

fn io(path: &Path, source: std::io::Error) -> WriteError {
    WriteError::Io {
        path: path.to_owned(),
        source,
    }
}

/// [`check_target`], then [`crate::write_file`]: the last check just before the rename.
pub fn write_owned_file(path: &Path, bytes: &[u8], owner: Owner) -> Result<(), WriteError> {
    check_target(path, owner)?;
    crate::write_file(path, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PROFILE: Owner = Owner::Json(&["reproj.profile"]);

    #[test]
    fn new_paths_and_own_files_pass_foreign_ones_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a/b/p.json");
        check_target(&p, PROFILE).unwrap();
        assert!(!dir.path().join("a").exists(), "the check creates nothing");
        let own = dir.path().join("own.json");
        std::fs::write(&own, r#"{"schema": "reproj.profile", "version": 7}"#).unwrap();
        check_target(&own, PROFILE).unwrap();
        let notes = dir.path().join("u.txt");
        std::fs::write(&notes, "notes").unwrap();
        let e = check_target(&notes, PROFILE).unwrap_err().to_string();
        assert!(
            e.contains("u.txt") && e.contains("not a reproj.profile"),
            "{e}"
        );
        let other = dir.path().join("s.json");
        std::fs::write(&other, r#"{"schema": "reproj.session"}"#).unwrap();
        assert!(check_target(&other, PROFILE).is_err());
        let e = check_target(dir.path(), PROFILE).unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        assert!(write_owned_file(&notes, b"{}", PROFILE).is_err());
        assert_eq!(std::fs::read_to_string(&notes).unwrap(), "notes");
        let under_file = notes.join("p.json");
        assert!(check_target(&under_file, PROFILE).is_err());
    }

    #[test]
    fn pages_and_charts() {
        let dir = tempfile::tempdir().unwrap();
        let page = dir.path().join("r.html");
        std::fs::write(&page, "<html><title>reproj report — x</title>").unwrap();
        check_target(&page, Owner::Marker("<title>reproj report")).unwrap();
        std::fs::write(&page, "<html><title>mine</title>").unwrap();
        assert!(check_target(&page, Owner::Marker("<title>reproj report")).is_err());
        let svg = dir.path().join("p.tradeoff.svg");
        std::fs::write(&svg, "<svg width=\"1\"></svg>").unwrap();
        check_target(&svg, Owner::Image).unwrap();
        let png = dir.path().join("p.tradeoff.png");
        std::fs::write(&png, "text").unwrap();
        assert!(check_target(&png, Owner::Image).is_err());
    }
}
