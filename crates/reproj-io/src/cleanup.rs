//! What an interrupted command leaves behind, and who may write an output.
//!
//! - Every temporary file and staged directory reproj is writing is registered while it exists;
//!   [`remove_registered`] removes them all (the CLI calls it on SIGINT/SIGTERM before exiting), so
//!   a Ctrl-C during `render --frames` leaves no hidden 19 MB directory.
//! - A process killed outright (SIGKILL, a power cut) cannot clean up: the next writer of the same
//!   output sweeps the hidden siblings whose process is gone ([`sweep_stale`]).
//! - [`OutputLock`]: one writer per output. A second `analyze` to the same `--out` would skew the
//!   first one's timings and race for the file; it is refused, naming the process that holds it.
//!   A lock records more than its writer's pid (see [`crate::holder`]), so a lock whose pid was
//!   given to another process since is seen as stale and taken over.
//!
//! Cleanup comes after the writers: a signal arrives on its own thread while the main thread (or
//! a frame writer) may be creating a file in the very directory being removed, and would create
//! it again. So every file or directory reproj creates is created under a shared gate
//! ([`while_open`]); [`remove_registered`] takes the gate exclusively, which waits for the
//! creations under way, marks the process as closing, and removes what is registered before it
//! lets go. From then on every writer is refused ([`WriteError::Interrupted`]) and creates nothing.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, RwLock};

use crate::error::WriteError;
use crate::holder::{Holder, Liveness};

static REGISTERED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The gate: `true` once [`remove_registered`] has started.
static CLOSING: RwLock<bool> = RwLock::new(false);

/// Run `create` (which makes files or directories reproj must clean up) unless cleanup has
/// started, in which case `path` is refused and nothing is created. Cleanup waits for a `create`
/// under way to finish.
pub(crate) fn while_open<T>(
    path: &Path,
    create: impl FnOnce() -> Result<T, WriteError>,
) -> Result<T, WriteError> {
    let closing = CLOSING.read().unwrap_or_else(|e| e.into_inner());
    if *closing {
        return Err(WriteError::Interrupted {
            path: path.to_owned(),
        });
    }
    create()
}

/// Whether [`remove_registered`] has run or is running: the process is being interrupted, and
/// every write is refused.
pub fn cleanup_started() -> bool {
    *CLOSING.read().unwrap_or_else(|e| e.into_inner())
}

pub(crate) fn register(path: &Path) {
    if let Ok(mut r) = REGISTERED.lock() {
        r.push(path.to_owned());
    }
}

pub(crate) fn unregister(path: &Path) {
    if let Ok(mut r) = REGISTERED.lock()
        && let Some(i) = r.iter().rposition(|p| p == path)
    {
        r.swap_remove(i);
    }
}

/// Remove every registered temporary file, staged directory and lock: what a signal handler
/// calls before the process exits. It first waits for the files being created to be created,
/// and from then on every write of the process is refused, so nothing reappears once this
/// returns.
pub fn remove_registered() {
    let mut closing = CLOSING.write().unwrap_or_else(|e| e.into_inner());
    *closing = true;
    let paths = match REGISTERED.lock() {
        Ok(mut r) => std::mem::take(&mut *r),
        Err(e) => std::mem::take(&mut *e.into_inner()),
    };
    for p in paths {
        if p.is_dir() {
            let _ = std::fs::remove_dir_all(&p);
        } else {
            let _ = std::fs::remove_file(&p);
        }
    }
    drop(closing);
}

/// The identity in a temporary sibling's name `.{name}.{what}{tag}-{n}` (see `temp_sibling` and
/// [`Holder::tag`]; an older name holds the pid alone), with the boot id and host short.
fn sibling_holder(file: &str, name: &str) -> Option<Holder> {
    let rest = file
        .strip_prefix('.')?
        .strip_prefix(name)?
        .strip_prefix('.')?;
    let rest = ["staged", "old", "tmp"]
        .iter()
        .find_map(|w| rest.strip_prefix(w))?;
    let (tag, n) = rest.rsplit_once('-')?;
    (!n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())).then_some(())?;
    Holder::parse_tag(tag)
}

/// Remove the hidden temporary siblings of `path` (staged directories, temporary files, old
/// directories being replaced) left by processes that no longer run, by the test locks use
/// ([`Holder::liveness`]): a sibling whose pid now belongs to a process that started later, or
/// that was written before the last boot, is swept; one of a running process (this one
/// included), or written on another host, is kept.
pub fn sweep_stale(path: &Path) {
    let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
        return;
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let me = Holder::me().short();
    for e in entries.flatten() {
        let file = e.file_name();
        let Some(holder) = file.to_str().and_then(|f| sibling_holder(f, name)) else {
            continue;
        };
        if holder.liveness(&me) == Liveness::Running {
            continue;
        }
        let p = e.path();
        if e.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(&p);
        } else {
            let _ = std::fs::remove_file(&p);
        }
    }
}

/// The lock file of an output: `{out}.lock`, holding the writer's identity (pid, start time, boot
/// id, host: see [`crate::holder`]). Removed on drop (and by [`remove_registered`] on a signal); a
/// lock whose process is gone, or whose pid now belongs to another process, is taken over.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
}

impl OutputLock {
    /// Take the lock of `out`, or say who holds it.
    pub fn acquire(out: &Path) -> Result<OutputLock, WriteError> {
        let mut name = out.file_name().unwrap_or_default().to_owned();
        name.push(".lock");
        let path = out.with_file_name(name);
        if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| WriteError::Io {
                path: dir.to_owned(),
                source,
            })?;
        }
        let me = Holder::me();
        for _ in 0..2 {
            let created = while_open(&path, || {
                let opened = std::fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(&path);
                if let Ok(mut f) = opened.as_ref() {
                    use std::io::Write;
                    let _ = f.write_all(me.to_text().as_bytes());
                    register(&path);
                }
                Ok(opened)
            })?;
            match created {
                Ok(_) => return Ok(OutputLock { path }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let holder = std::fs::read_to_string(&path)
                        .ok()
                        .and_then(|t| Holder::parse(&t));
                    match holder {
                        Some(h) if h != me && h.liveness(&me) == Liveness::Running => {
                            return Err(WriteError::Locked {
                                path: out.to_owned(),
                                lock: path,
                                holder: h.describe(&me),
                            });
                        }
                        // Stale (its process is gone, or its pid is another process's now),
                        // this process's own, or unreadable: take it over.
                        _ => {
                            let _ = std::fs::remove_file(&path);
                        }
                    }
                }
                Err(source) => return Err(WriteError::Io { path, source }),
            }
        }
        Err(WriteError::Io {
            path,
            source: std::io::Error::other("the lock file keeps coming back"),
        })
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        unregister(&self.path);
        let _ = std::fs::remove_file(&self.path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sibling_names_parse() {
        let pid = |f: &str, name: &str| sibling_holder(f, name).map(|h| h.pid);
        assert_eq!(pid(".out.staged123-0", "out"), Some(123));
        assert_eq!(pid(".p.json.tmp77-12", "p.json"), Some(77));
        assert_eq!(pid(".out.old9-1", "out"), Some(9));
        assert_eq!(pid(".out.staged123", "out"), None);
        assert_eq!(pid(".other.staged1-0", "out"), None);
        assert_eq!(pid("out.staged1-0", "out"), None);
        assert_eq!(pid(".out.staged12.x3-0", "out"), None);
        // What this process's writers name their siblings: the whole identity, short.
        let me = Holder::me();
        let file = format!(".out.staged{}-4", me.tag());
        assert_eq!(sibling_holder(&file, "out"), Some(me.short()));
        let full = Holder {
            pid: 5,
            start: Some(77),
            boot: Some("b".into()),
            host: Some("h".into()),
        };
        let file = format!(".out.tmp{}-0", full.tag());
        assert_eq!(sibling_holder(&file, "out"), Some(full.short()));
    }

    #[test]
    fn stale_siblings_are_swept_live_ones_kept() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("frames");
        // A pid far above any Linux pid_max: no such process.
        let dead = dir.path().join(".frames.staged4999999-0");
        std::fs::create_dir_all(dead.join("x")).unwrap();
        let live = dir
            .path()
            .join(format!(".frames.staged{}-0", std::process::id()));
        std::fs::create_dir(&live).unwrap();
        let mine = dir
            .path()
            .join(format!(".frames.staged{}-1", Holder::me().tag()));
        std::fs::create_dir(&mine).unwrap();
        let other = dir.path().join(".notes.tmp4999999-0");
        std::fs::write(&other, "x").unwrap();
        sweep_stale(&out);
        assert!(!dead.exists());
        assert!(live.exists() && mine.exists() && other.exists());
    }

    /// The sweep tells a sibling's writer as locks do: a reused pid or another boot is stale,
    /// a running process (its start time matching) or another host is kept.
    #[test]
    fn a_sibling_whose_pid_was_reused_is_swept_one_of_a_running_process_kept() {
        let me = Holder::me();
        let (Some(start), Some(init_start)) = (me.start, crate::holder::start_time(1)) else {
            return; // no /proc: a reused pid cannot be told from its writer
        };
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("frames");
        let sibling = |h: &Holder, n: u32| {
            let p = dir.path().join(format!(".frames.staged{}-{n}", h.tag()));
            std::fs::create_dir_all(p.join("frame_000.png")).unwrap();
            p
        };
        // Pid 1 runs, but it did not write this: that process started at another time.
        let reused = sibling(
            &Holder {
                pid: 1,
                start: Some(init_start + start + 1),
                ..me.clone()
            },
            0,
        );
        // Pid 1 with its real start time: running, kept.
        let init = Holder {
            pid: 1,
            start: Some(init_start),
            ..me.clone()
        };
        let running = sibling(&init, 1);
        // Written before the last boot: stale whatever its pid.
        let rebooted = sibling(
            &Holder {
                boot: Some("00000000-0000-0000-0000-000000000000".into()),
                ..init.clone()
            },
            2,
        );
        // Another host's process cannot be checked from here: kept, even with no such pid here.
        let remote = sibling(
            &Holder {
                pid: 4_999_999,
                host: Some("elsewhere".into()),
                ..me.clone()
            },
            3,
        );
        // This process: kept.
        let mine = sibling(&me, 4);
        sweep_stale(&out);
        assert!(!reused.exists() && !rebooted.exists());
        assert!(running.exists() && remote.exists() && mine.exists());
    }

    #[test]
    fn one_writer_per_output_and_stale_locks_are_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("p.json");
        let lock = OutputLock::acquire(&out).unwrap();
        let lock_path = dir.path().join("p.json.lock");
        assert!(lock_path.exists());
        drop(lock);
        assert!(!lock_path.exists());
        // Held by a running process (pid 1, init): refused, naming it.
        std::fs::write(&lock_path, "1\n").unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(e.contains("pid 1") && e.contains("p.json"), "{e}");
        // Held by a process that is gone: taken over.
        std::fs::write(&lock_path, "4999999\n").unwrap();
        let lock = OutputLock::acquire(&out).unwrap();
        let text = std::fs::read_to_string(&lock_path).unwrap();
        assert_eq!(Holder::parse(&text), Some(Holder::me()));
        drop(lock);
    }

    #[test]
    fn a_lock_whose_pid_was_reused_is_taken_over() {
        let me = Holder::me();
        let (Some(start), Some(init_start)) = (me.start, crate::holder::start_time(1)) else {
            return; // no /proc: a reused pid cannot be told from its writer
        };
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("p.json");
        let lock_path = dir.path().join("p.json.lock");
        // Pid 1 runs, but it is not the process that wrote this lock: that one started at
        // another time (then exited, and its pid went to a new process).
        let reused = Holder {
            pid: 1,
            start: Some(init_start + start + 1),
            ..me.clone()
        };
        std::fs::write(&lock_path, reused.to_text()).unwrap();
        let lock = OutputLock::acquire(&out).unwrap();
        drop(lock);
        // The same pid with its real start time: held, and named.
        let held = Holder {
            pid: 1,
            start: Some(init_start),
            ..me.clone()
        };
        std::fs::write(&lock_path, held.to_text()).unwrap();
        let e = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(e.contains("(pid 1)"), "{e}");
        // Written before the last boot: stale whatever its pid.
        let rebooted = Holder {
            boot: Some("00000000-0000-0000-0000-000000000000".into()),
            ..held
        };
        std::fs::write(&lock_path, rebooted.to_text()).unwrap();
        drop(OutputLock::acquire(&out).unwrap());
    }
}
