//! The runtime's reader of files: a variant's manifest and passes, a capture's base session.
//!
//! The same door rules as the reproj CLI's reader (`read_input` in reproj-io, which this crate
//! cannot link: it depends on no other reproj crate, and a test checks that both readers agree):
//! a path is checked with `std::fs::metadata` before it is opened, so a folder, a named pipe
//! (which would block on open) or a device (`/dev/zero` never ends) is refused; at most the
//! limit plus one byte is read, so a file past the limit is refused with its size rather than
//! read to the end ([`ReadLimits`], raised by the application); a pass is a file of the variant's
//! folder, and a link out of it is refused ([`inside`]). No error shows a file's text.

use std::io::Read;
use std::path::{Path, PathBuf};

/// The largest files the runtime reads, in bytes. The defaults are the reproj CLI's: 64 MiB for
/// a JSON document, 16 MiB for a shader. Raise them with [`crate::Variant::load_with`] or
/// [`crate::SessionCapture::from_file_with`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReadLimits {
    /// A manifest or a base session.
    pub json_bytes: u64,
    /// A pass file.
    pub shader_bytes: u64,
}

impl Default for ReadLimits {
    fn default() -> Self {
        ReadLimits {
            json_bytes: 64 << 20,
            shader_bytes: 16 << 20,
        }
    }
}

/// What a file is read as: its limit and the words of messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FileKind {
    Json,
    Shader,
}

impl FileKind {
    fn limit(self, limits: &ReadLimits) -> u64 {
        match self {
            FileKind::Json => limits.json_bytes,
            FileKind::Shader => limits.shader_bytes,
        }
    }

    fn what(self) -> &'static str {
        match self {
            FileKind::Json => "JSON document",
            FileKind::Shader => "shader",
        }
    }

    fn field(self) -> &'static str {
        match self {
            FileKind::Json => "json_bytes",
            FileKind::Shader => "shader_bytes",
        }
    }
}

/// A file that was not read. Every variant names the file; none shows its content.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FileError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A folder, a named pipe, a device or a socket: reading it would fail, block or never end.
    #[error("cannot read {path}: it is {what}, not a regular file")]
    NotAFile { path: PathBuf, what: &'static str },
    /// Larger than its limit.
    #[error(
        "cannot read {path}: {size} is over the {limit}-byte limit for a {kind} (raise `ReadLimits::{field}`)"
    )]
    TooLarge {
        path: PathBuf,
        /// The size, in words: "1234567 bytes", or "more than N bytes" when it was not known.
        size: String,
        limit: u64,
        kind: &'static str,
        /// The [`ReadLimits`] field that raises it.
        field: &'static str,
    },
    /// Text was expected.
    #[error("cannot read {path}: it is not UTF-8 text (byte {offset})")]
    NotText { path: PathBuf, offset: usize },
}

impl FileError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            FileError::Io { path, .. }
            | FileError::NotAFile { path, .. }
            | FileError::TooLarge { path, .. }
            | FileError::NotText { path, .. } => path,
        }
    }
}

/// The text of `path`, read as `kind`: a regular file (after links) within its limit.
pub(crate) fn read_text(
    path: &Path,
    kind: FileKind,
    limits: &ReadLimits,
) -> Result<String, FileError> {
    let io = |source| FileError::Io {
        path: path.to_owned(),
        source,
    };
    let too_large = |size: String| FileError::TooLarge {
        path: path.to_owned(),
        size,
        limit: kind.limit(limits),
        kind: kind.what(),
        field: kind.field(),
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(FileError::NotAFile {
            path: path.to_owned(),
            what: file_type_words(&meta.file_type()),
        });
    }
    let limit = kind.limit(limits);
    if meta.len() > limit {
        return Err(too_large(format!("{} bytes", meta.len())));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit.saturating_add(1)).read_to_end(&mut bytes))
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(format!("more than {limit} bytes")));
    }
    String::from_utf8(bytes).map_err(|e| FileError::NotText {
        path: path.to_owned(),
        offset: e.utf8_error().valid_up_to(),
    })
}

/// `dir/name`, when `name` names a file of the folder `dir`: one plain component (no folder,
/// no `..`), and, when it exists, not a link out of `dir`. Otherwise why not, in words.
pub(crate) fn inside(dir: &Path, name: &str) -> Result<PathBuf, String> {
    let mut parts = Path::new(name).components();
    if !matches!(
        (parts.next(), parts.next()),
        (Some(std::path::Component::Normal(_)), None)
    ) {
        return Err(format!(
            "`{name}` is not a file name in the variant's directory"
        ));
    }
    let path = dir.join(name);
    let base = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    // Through links: both canonical, when the file exists (a missing file fails when it is
    // read, naming it).
    if let (Ok(f), Ok(b)) = (std::fs::canonicalize(&path), std::fs::canonicalize(base))
        && !f.starts_with(&b)
    {
        return Err(format!(
            "`{name}` is a link out of the variant's directory: a manifest names files beside it"
        ));
    }
    Ok(path)
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

    /// The files both readers are given: (name, how it is made).
    fn hostile_files(dir: &Path) -> Vec<PathBuf> {
        let mut out = Vec::new();
        let regular = dir.join("regular.json");
        std::fs::write(&regular, "{\"a\": 1}").unwrap();
        out.push(regular);
        let folder = dir.join("folder.json");
        std::fs::create_dir(&folder).unwrap();
        out.push(folder);
        let big = dir.join("big.json");
        std::fs::File::create(&big)
            .unwrap()
            .set_len((64 << 20) + 1)
            .unwrap();
        out.push(big);
        let at_limit = dir.join("at_limit.json");
        std::fs::File::create(&at_limit)
            .unwrap()
            .set_len(64 << 20)
            .unwrap();
        out.push(at_limit);
        let binary = dir.join("binary.json");
        std::fs::write(&binary, b"{\xff}").unwrap();
        out.push(binary);
        out.push(dir.join("missing.json"));
        #[cfg(unix)]
        {
            out.push(PathBuf::from("/dev/zero"));
            let pipe = dir.join("pipe.json");
            let made = std::process::Command::new("mkfifo")
                .arg(&pipe)
                .status()
                .is_ok_and(|s| s.success());
            assert!(made, "mkfifo");
            out.push(pipe);
            let link = dir.join("link.json");
            std::os::unix::fs::symlink(dir.join("regular.json"), &link).unwrap();
            out.push(link);
        }
        out
    }

    /// The runtime reads what the CLI reads and refuses what it refuses, at the same default
    /// limits: a folder, a pipe (without blocking), a device, a file one byte past the limit, a
    /// file that is not text.
    #[test]
    fn the_runtime_and_the_cli_readers_agree() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(
            std::env::var_os(reproj_io::MAX_INPUT_ENV),
            None,
            "the CLI's limits are its defaults"
        );
        for path in hostile_files(dir.path()) {
            let ours = read_text(&path, FileKind::Json, &ReadLimits::default());
            let cli = reproj_io::read_input_string(&path, reproj_io::InputKind::Json);
            assert_eq!(
                ours.is_ok(),
                cli.is_ok(),
                "{}: runtime {ours:?}, CLI {cli:?}",
                path.display()
            );
            if let (Ok(a), Ok(b)) = (&ours, &cli) {
                assert_eq!(a, b, "{}", path.display());
            }
            if let Err(e) = ours {
                assert_eq!(e.path(), path);
                assert!(e.to_string().contains(&path.display().to_string()), "{e}");
            }
        }
        assert_eq!(
            ReadLimits::default().shader_bytes,
            reproj_io::InputKind::Shader.default_limit_mib() << 20
        );
        assert_eq!(
            ReadLimits::default().json_bytes,
            reproj_io::InputKind::Json.default_limit_mib() << 20
        );
    }

    #[test]
    fn a_file_past_the_limit_names_its_size_and_the_limit_to_raise() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("pass.wgsl");
        std::fs::write(&p, "0123456789").unwrap();
        let small = ReadLimits {
            shader_bytes: 9,
            ..ReadLimits::default()
        };
        let m = read_text(&p, FileKind::Shader, &small)
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("pass.wgsl")
                && m.contains("10 bytes")
                && m.contains("9-byte limit")
                && m.contains("ReadLimits::shader_bytes")
                && !m.contains("0123"),
            "{m}"
        );
        let raised = ReadLimits {
            shader_bytes: 10,
            ..small
        };
        assert_eq!(
            read_text(&p, FileKind::Shader, &raised).unwrap(),
            "0123456789"
        );
    }

    #[test]
    fn a_pass_is_a_file_of_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("pass1.wgsl"), "").unwrap();
        assert_eq!(inside(d, "pass1.wgsl").unwrap(), d.join("pass1.wgsl"));
        // A missing file is for the read to name.
        assert_eq!(inside(d, "pass9.wgsl").unwrap(), d.join("pass9.wgsl"));
        for bad in [
            "",
            "..",
            ".",
            "/etc/passwd",
            "sub/pass.wgsl",
            "../pass1.wgsl",
        ] {
            let e = inside(d, bad).unwrap_err();
            assert!(e.contains("not a file name"), "{bad}: {e}");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/etc/passwd", d.join("out.wgsl")).unwrap();
            let e = inside(d, "out.wgsl").unwrap_err();
            assert!(e.contains("a link out of the variant's directory"), "{e}");
            std::os::unix::fs::symlink(d.join("pass1.wgsl"), d.join("alias.wgsl")).unwrap();
            assert!(inside(d, "alias.wgsl").is_ok());
        }
    }
}
