//! Our own output: every command prints through [`stdout`], which remembers a failed write so
//! that the process ends with [`EXIT_STDOUT`] and says so.
//!
//! Why: `reproj nodes x.wgsl > /dev/full` used to exit 1 (a "bug"), and with stdout closed
//! (`>&-`) Rust's runtime puts `/dev/null` in its place, so the output was lost with exit 0.
//! A reader that went away (`| head`) is still not an error ([`super::finish`]).

use std::io::Write;
use std::sync::Mutex;

/// The exit code for output that could not be written to stdout (full disk, closed stdout).
pub const EXIT_STDOUT: u8 = 5;

/// The first failed write to stdout, in words.
static FAILED: Mutex<Option<String>> = Mutex::new(None);

/// The locked stdout, recording failures.
pub struct Out {
    lock: std::io::StdoutLock<'static>,
    closed: bool,
}

/// The process's stdout for a command's output.
pub fn stdout() -> Out {
    Out {
        lock: std::io::stdout().lock(),
        closed: closed_at_start(),
    }
}

/// Why writing stdout failed, when it did.
pub fn failure() -> Option<String> {
    FAILED.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

impl Out {
    fn check<T>(&self, r: std::io::Result<T>) -> std::io::Result<T> {
        if let Err(e) = &r
            && e.kind() != std::io::ErrorKind::BrokenPipe
        {
            let mut failed = FAILED.lock().unwrap_or_else(|e| e.into_inner());
            failed.get_or_insert_with(|| e.to_string());
        }
        r
    }

    fn closed_error(&self) -> std::io::Error {
        std::io::Error::other("stdout is closed")
    }
}

impl Write for Out {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.closed {
            let e = self.closed_error();
            return self.check(Err(e));
        }
        let r = self.lock.write(buf);
        self.check(r)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if self.closed {
            return Ok(());
        }
        let r = self.lock.flush();
        self.check(r)
    }
}

/// True when stdout was closed when the process started. Rust's runtime then opens `/dev/null`
/// read-write in its place (a shell's `> /dev/null` opens it write-only), which Linux's
/// `/proc/self/fdinfo` shows. Elsewhere, false. A caller's own read-write `/dev/null` (Python's
/// `subprocess.DEVNULL`) cannot be told apart from it: docs/USAGE.md says so.
fn closed_at_start() -> bool {
    let Ok(target) = std::fs::read_link("/proc/self/fd/1") else {
        return false;
    };
    if target != std::path::Path::new("/dev/null") {
        return false;
    }
    let Ok(info) = std::fs::read_to_string("/proc/self/fdinfo/1") else {
        return false;
    };
    info.lines()
        .find_map(|l| l.strip_prefix("flags:"))
        .and_then(|f| u32::from_str_radix(f.trim(), 8).ok())
        .is_some_and(|flags| flags & 0o3 == 0o2)
}
