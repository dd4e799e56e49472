//! The atomic writer: single files and whole directories.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

pub use crate::error::WriteError;

/// Test hook: when this environment variable names a file (`report.json`) or an output
/// directory (`out`), writing that file or committing that directory fails with an injected I/O
/// error after everything before it was written, as a full disk would.
pub const FAIL_ENV: &str = "REPROJ_IO_FAIL";

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> WriteError + '_ {
    move |source| WriteError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Fail as the test hook says (see [`FAIL_ENV`]).
fn injected(path: &Path) -> std::io::Result<()> {
    let Some(name) = std::env::var_os(FAIL_ENV) else {
        return Ok(());
    };
    if path.file_name() == Some(name.as_os_str()) {
        return Err(std::io::Error::other(format!(
            "injected failure ({FAIL_ENV})"
        )));
    }
    Ok(())
}

/// A name for a temporary sibling of `path`: hidden, unique within the process and across
/// processes, and naming its writer as a lock does (pid, start time, boot and host:
/// [`crate::holder::Holder::tag`]), so that [`crate::sweep_stale`] sweeps it once that process
/// is gone, even when its pid was given to another.
fn temp_sibling(path: &Path, what: &str) -> PathBuf {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let me = crate::holder::Holder::me().tag();
    path.with_file_name(format!(".{name}.{what}{me}-{n}"))
}

fn parent_of(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Write `bytes` to `path` atomically, creating its directory: a temporary file in the same
/// directory, synced, then renamed over `path`. On any error the temporary file is removed and
/// `path` keeps what it had.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    crate::cleanup::while_open(path, || write_file_now(path, bytes))
}

fn write_file_now(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let dir = parent_of(path);
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    crate::cleanup::sweep_stale(path);
    let tmp = temp_sibling(path, "tmp");
    crate::cleanup::register(&tmp);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        injected(path)?;
        std::fs::rename(&tmp, path)
    })();
    crate::cleanup::unregister(&tmp);
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(path)(e)
    })
}

/// Write several files that belong together (the charts of one profile) so that a failure
/// leaves all of them as they were: every file is first written to a temporary sibling, and only
/// when all are written are they renamed into place.
pub fn write_files(files: &[(PathBuf, Vec<u8>)]) -> Result<(), WriteError> {
    let Some((first, _)) = files.first() else {
        return Ok(());
    };
    crate::cleanup::while_open(first, || write_files_now(files))
}

fn write_files_now(files: &[(PathBuf, Vec<u8>)]) -> Result<(), WriteError> {
    let mut temps: Vec<PathBuf> = Vec::new();
    let clean = |temps: &[PathBuf]| {
        for t in temps {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, bytes) in files {
        let dir = parent_of(path);
        let tmp = temp_sibling(path, "tmp");
        let result = std::fs::create_dir_all(dir).and_then(|()| {
            let mut f = std::fs::File::create(&tmp)?;
            temps.push(tmp.clone());
            f.write_all(bytes)?;
            f.sync_all()?;
            injected(path)
        });
        if let Err(e) = result {
            clean(&temps);
            return Err(io(path)(e));
        }
    }
    for (i, ((path, _), tmp)) in files.iter().zip(&temps).enumerate() {
        if let Err(e) = std::fs::rename(tmp, path) {
            clean(&temps[i..]);
            return Err(io(path)(e));
        }
    }
    Ok(())
}

/// Which existing output directory [`StagedDir`] may replace.
#[derive(Debug, Clone, Copy)]
pub enum Replace {
    /// A directory holding only plain files with these extensions (what the command writes);
    /// anything else (a subdirectory, a foreign file) makes it refuse, so a mistyped `--out .`
    /// cannot delete a project.
    OwnFiles(&'static [&'static str]),
}

impl Replace {
    fn check(self, out: &Path) -> Result<(), WriteError> {
        let refuse = |why: String| {
            Err(WriteError::Refused {
                path: out.to_owned(),
                why,
            })
        };
        match std::fs::symlink_metadata(out) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
            Err(e) => return Err(io(out)(e)),
            Ok(m) if !m.is_dir() => return refuse("it is not a directory".into()),
            Ok(_) => {}
        }
        let Replace::OwnFiles(exts) = self;
        for e in std::fs::read_dir(out).map_err(io(out))? {
            let e = e.map_err(io(out))?;
            let path = e.path();
            let name = e.file_name().to_string_lossy().into_owned();
            let is_file = e.file_type().is_ok_and(|t| t.is_file());
            let ext = path.extension().and_then(|x| x.to_str()).unwrap_or("");
            if !is_file || !exts.contains(&ext) {
                return refuse(format!(
                    "it holds `{name}`, which reproj does not write there"
                ));
            }
        }
        Ok(())
    }
}

/// A whole output directory written aside and swapped in at the end.
///
/// [`StagedDir::new`] checks that `out` may be replaced and makes an empty temporary sibling;
/// files go there ([`StagedDir::write`], or any writer given [`StagedDir::path`]);
/// [`StagedDir::commit`] renames the old directory aside, renames the staged one into place and
/// removes the old one. Dropped without a commit, the staged directory is removed.
#[derive(Debug)]
pub struct StagedDir {
    out: PathBuf,
    path: PathBuf,
    done: bool,
}

impl StagedDir {
    pub fn new(out: &Path, replace: Replace) -> Result<StagedDir, WriteError> {
        crate::cleanup::while_open(out, || StagedDir::new_now(out, replace))
    }

    fn new_now(out: &Path, replace: Replace) -> Result<StagedDir, WriteError> {
        replace.check(out)?;
        let parent = parent_of(out);
        std::fs::create_dir_all(parent).map_err(io(parent))?;
        crate::cleanup::sweep_stale(out);
        let path = temp_sibling(out, "staged");
        std::fs::create_dir(&path).map_err(io(&path))?;
        crate::cleanup::register(&path);
        Ok(StagedDir {
            out: out.to_owned(),
            path,
            done: false,
        })
    }

    /// The staging directory: write here, then [`commit`](Self::commit).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The directory this will replace.
    pub fn out(&self) -> &Path {
        &self.out
    }

    /// Write `name` (relative to the directory) into the staging directory.
    pub fn write(&self, name: impl AsRef<Path>, bytes: &[u8]) -> Result<(), WriteError> {
        let name = name.as_ref();
        let path = self.path.join(name);
        let shown = self.out.join(name);
        crate::cleanup::while_open(&shown, || {
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir).map_err(io(&shown))?;
            }
            (|| {
                injected(&path)?;
                std::fs::write(&path, bytes)
            })()
            .map_err(io(&shown))
        })
    }

    /// Put the staged directory in place of the output directory.
    pub fn commit(self) -> Result<(), WriteError> {
        let out = self.out.clone();
        crate::cleanup::while_open(&out, || self.commit_now())
    }

    fn commit_now(mut self) -> Result<(), WriteError> {
        let out = self.out.clone();
        injected(&out).map_err(io(&out))?;
        let old = temp_sibling(&out, "old");
        let had_old = out.exists();
        if had_old {
            std::fs::rename(&out, &old).map_err(io(&out))?;
        }
        if let Err(e) = std::fs::rename(&self.path, &out) {
            if had_old {
                let _ = std::fs::rename(&old, &out);
            }
            return Err(io(&out)(e));
        }
        self.done = true;
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        crate::cleanup::unregister(&self.path);
        if !self.done {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}
