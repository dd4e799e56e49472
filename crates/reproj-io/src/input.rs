//! The one reader of user files: shaders, sessions, profiles, manifests, meshes and images all go
//! through [`read_input`].
//!
//! Why one: a path on the command line (or in a session or manifest) may name anything. A named
//! pipe blocks forever on open, `/dev/zero` or `/dev/urandom` never end, a folder cannot be read,
//! and a multi-gigabyte file exhausts memory. So the path is checked with `std::fs::metadata`
//! *before* it is opened (only regular files are read), and at most the kind's limit plus one byte
//! is read, so that an oversized file (or one whose size the metadata does not tell, like those
//! in `/proc`) is refused with its size and the limit rather than read to the end.

use std::io::Read;
use std::path::{Path, PathBuf};

/// The environment variable that replaces every kind's size limit, in MiB (e.g.
/// `REPROJ_MAX_INPUT_MB=2048` for a very large mesh).
pub const MAX_INPUT_ENV: &str = "REPROJ_MAX_INPUT_MB";

/// What a file is read as: it decides the size limit and the word used in messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputKind {
    /// A shader (WGSL, GLSL, SPIR-V) or a module it imports: 16 MiB.
    Shader,
    /// A JSON document: session, profile, manifest, capture: 64 MiB.
    Json,
    /// A mesh, a glTF file or an image: 512 MiB.
    Asset,
}

impl InputKind {
    /// The default limit, in MiB.
    pub fn default_limit_mib(self) -> u64 {
        match self {
            InputKind::Shader => 16,
            InputKind::Json => 64,
            InputKind::Asset => 512,
        }
    }

    /// The limit in bytes: [`MAX_INPUT_ENV`] when set to a positive whole number, else the default.
    pub fn limit(self) -> u64 {
        let mib = std::env::var(MAX_INPUT_ENV)
            .ok()
            .and_then(|v| v.trim().parse::<u64>().ok())
            .filter(|&m| m > 0)
            .unwrap_or_else(|| self.default_limit_mib());
        mib.saturating_mul(1 << 20)
    }

    fn what(self) -> &'static str {
        match self {
            InputKind::Shader => "shader",
            InputKind::Json => "JSON document",
            InputKind::Asset => "mesh or image",
        }
    }
}

/// A user file that was not read. Every variant names the file; none shows its content.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A folder, a named pipe, a device or a socket: reading it would fail, block or never end.
    #[error("cannot read {path}: it is {what}, not a regular file")]
    NotAFile { path: PathBuf, what: &'static str },
    /// Larger than the kind's limit.
    #[error(
        "cannot read {path}: {size} is over the {limit_mib} MiB limit for a {kind} (set {MAX_INPUT_ENV} to raise it)"
    )]
    TooLarge {
        path: PathBuf,
        /// The size, in words: "1234567 bytes", or "more than N bytes" when it was not known.
        size: String,
        limit_mib: u64,
        kind: &'static str,
    },
    /// Text was expected.
    #[error("cannot read {path}: it is not UTF-8 text (byte {offset})")]
    NotText { path: PathBuf, offset: usize },
}

impl InputError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            InputError::Io { path, .. }
            | InputError::NotAFile { path, .. }
            | InputError::TooLarge { path, .. }
            | InputError::NotText { path, .. } => path,
        }
    }

    /// True when the file does not exist (callers that have a fallback, or a friendlier message,
    /// for a missing file).
    pub fn is_not_found(&self) -> bool {
        matches!(self, InputError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound)
    }
}

/// Refuse `path` unless it is a regular file (after symbolic links) within `kind`'s limit; checked
/// before anything opens it. Also for readers that open the file themselves (tobj, image, glTF).
pub fn check_input(path: &Path, kind: InputKind) -> Result<(), InputError> {
    let meta = std::fs::metadata(path).map_err(|source| InputError::Io {
        path: path.to_owned(),
        source,
    })?;
    if !meta.is_file() {
        return Err(InputError::NotAFile {
            path: path.to_owned(),
            what: file_type_words(&meta.file_type()),
        });
    }
    let limit = kind.limit();
    if meta.len() > limit {
        return Err(too_large(path, kind, format!("{} bytes", meta.len())));
    }
    Ok(())
}

/// The bytes of the user file `path`, read as `kind`: a regular file within the limit.
pub fn read_input(path: &Path, kind: InputKind) -> Result<Vec<u8>, InputError> {
    check_input(path, kind)?;
    let limit = kind.limit();
    let io = |source| InputError::Io {
        path: path.to_owned(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(path, kind, format!("more than {limit} bytes")));
    }
    Ok(bytes)
}

/// [`read_input`] as UTF-8 text.
pub fn read_input_string(path: &Path, kind: InputKind) -> Result<String, InputError> {
    let bytes = read_input(path, kind)?;
    String::from_utf8(bytes).map_err(|e| InputError::NotText {
        path: path.to_owned(),
        offset: e.utf8_error().valid_up_to(),
    })
}

fn too_large(path: &Path, kind: InputKind, size: String) -> InputError {
    InputError::TooLarge {
        path: path.to_owned(),
        size,
        limit_mib: kind.limit() >> 20,
        kind: kind.what(),
    }
}

/// What a non-regular file is, in words.
fn file_type_words(t: &std::fs::FileType) -> &'static str {
    if t.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a named pipe";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regular_file_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.wgsl");
        std::fs::write(&p, "fn f() {}").unwrap();
        assert_eq!(
            read_input_string(&p, InputKind::Shader).unwrap(),
            "fn f() {}"
        );
    }

    #[test]
    fn a_folder_and_a_device_are_refused_before_opening() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_input(dir.path(), InputKind::Json).unwrap_err();
        assert!(e.to_string().contains("a folder"), "{e}");
        #[cfg(unix)]
        {
            let e = read_input(Path::new("/dev/zero"), InputKind::Asset).unwrap_err();
            assert!(e.to_string().contains("a device"), "{e}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_named_pipe_is_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("pipe.wgsl");
        let ok = std::process::Command::new("mkfifo")
            .arg(&p)
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "mkfifo");
        let e = read_input(&p, InputKind::Shader).unwrap_err();
        assert!(e.to_string().contains("a named pipe"), "{e}");
    }

    #[test]
    fn the_limit_names_the_size_and_the_limit() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("big.wgsl");
        let f = std::fs::File::create(&p).unwrap();
        f.set_len((16 << 20) + 1).unwrap();
        let e = read_input(&p, InputKind::Shader).unwrap_err();
        let m = e.to_string();
        assert!(
            m.contains("big.wgsl") && m.contains("16777217 bytes") && m.contains("16 MiB"),
            "{m}"
        );
    }

    #[test]
    fn a_file_that_is_not_text_names_the_byte() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("s.json");
        std::fs::write(&p, b"{\xff}").unwrap();
        let e = read_input_string(&p, InputKind::Json).unwrap_err();
        assert!(e.to_string().contains("byte 1"), "{e}");
    }
}
