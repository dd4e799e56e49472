//! Who holds a lock: more than a pid.
//!
//! A pid alone cannot tell a lock's writer from a process that was given the same pid later (after
//! a reboot, or once pids wrap around): a stale lock would then block its output for good. So a
//! lock records its writer's pid, the process's start time (field 22 of `/proc/PID/stat`, in
//! clock ticks since boot), the boot id (`/proc/sys/kernel/random/boot_id`) and the host name.
//! The writer still runs only if the boot is the same, a process has that pid, and it started at
//! the recorded time. A lock written on another host (a shared folder) cannot be checked from
//! here and is always taken as held.
//!
//! Without `/proc` (not Linux), every process is taken as running: nothing is taken over by
//! mistake.
//!
//! A temporary sibling (a staged directory, a temporary file) carries the same identity in its
//! name ([`Holder::tag`]), the boot id and host shortened to a hash, so the sweep of stale
//! siblings uses the same test as locks: a sibling whose pid was reused is swept, and one of a
//! process running here, or on another host, is kept.

use std::path::Path;
use std::sync::OnceLock;

/// The identity of the process that wrote a lock, as recorded in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Holder {
    pub pid: u32,
    /// Start time in clock ticks since boot; `None` in a pid-only lock or without `/proc`.
    pub start: Option<u64>,
    pub boot: Option<String>,
    pub host: Option<String>,
}

/// Whether the process a lock names still runs, as far as this host can tell.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Liveness {
    /// It runs (or it cannot be told: another host, no `/proc`).
    Running,
    /// Gone: no such pid, another boot, or the pid now belongs to a process that started later.
    Gone,
}

impl Holder {
    /// This process (read from `/proc` once).
    pub fn me() -> Holder {
        static ME: OnceLock<Holder> = OnceLock::new();
        ME.get_or_init(|| {
            let pid = std::process::id();
            Holder {
                pid,
                start: start_time(pid),
                boot: read_line(Path::new("/proc/sys/kernel/random/boot_id")),
                host: read_line(Path::new("/proc/sys/kernel/hostname")),
            }
        })
        .clone()
    }

    /// The identity as a file name's part: `{pid}` then `.s{start}`, `.b{boot}`, `.h{host}` for
    /// those known, the boot id and host as 8 hex digits of their hash ([`Holder::short`]).
    pub fn tag(&self) -> String {
        let short = self.short();
        let mut s = short.pid.to_string();
        if let Some(t) = short.start {
            s += &format!(".s{t}");
        }
        if let Some(b) = &short.boot {
            s += &format!(".b{b}");
        }
        if let Some(h) = &short.host {
            s += &format!(".h{h}");
        }
        s
    }

    /// Parse [`tag`](Self::tag)'s format (a pid alone is what older names hold); `None` when it
    /// is not one. The boot id and host are the short forms: compare with [`Holder::short`].
    pub fn parse_tag(tag: &str) -> Option<Holder> {
        let mut parts = tag.split('.');
        let pid = parts.next()?;
        if pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        let mut h = Holder {
            pid: pid.parse().ok()?,
            start: None,
            boot: None,
            host: None,
        };
        let hex = |v: &str| {
            (v.len() == 8 && v.bytes().all(|b| b.is_ascii_hexdigit())).then(|| v.to_owned())
        };
        for part in parts {
            match part.split_at_checked(1)? {
                ("s", v) if h.start.is_none() => h.start = Some(v.parse().ok()?),
                ("b", v) if h.boot.is_none() => h.boot = Some(hex(v)?),
                ("h", v) if h.host.is_none() => h.host = Some(hex(v)?),
                _ => return None,
            }
        }
        Some(h)
    }

    /// The same identity with the boot id and host replaced by 8 hex digits of their FNV-1a hash:
    /// what a name holds ([`Holder::tag`]), and what a parsed tag is compared with.
    pub fn short(&self) -> Holder {
        let hash = |s: &String| crate::content_hash(s.as_bytes())[..8].to_owned();
        Holder {
            pid: self.pid,
            start: self.start,
            boot: self.boot.as_ref().map(hash),
            host: self.host.as_ref().map(hash),
        }
    }

    /// The lock file's text: the pid alone on the first line (what older locks hold), then
    /// `key=value` lines.
    pub fn to_text(&self) -> String {
        let mut s = format!("{}\n", self.pid);
        if let Some(t) = self.start {
            s += &format!("start={t}\n");
        }
        if let Some(b) = &self.boot {
            s += &format!("boot={b}\n");
        }
        if let Some(h) = &self.host {
            s += &format!("host={h}\n");
        }
        s
    }

    /// Parse [`to_text`](Self::to_text)'s format (unknown keys ignored); `None` when the first
    /// line is not a pid.
    pub fn parse(text: &str) -> Option<Holder> {
        let mut lines = text.lines();
        let pid = lines.next()?.trim().parse().ok()?;
        let mut h = Holder {
            pid,
            start: None,
            boot: None,
            host: None,
        };
        for line in lines {
            match line.trim().split_once('=') {
                Some(("start", v)) => h.start = v.parse().ok(),
                Some(("boot", v)) if !v.is_empty() => h.boot = Some(v.to_owned()),
                Some(("host", v)) if !v.is_empty() => h.host = Some(v.to_owned()),
                _ => {}
            }
        }
        Some(h)
    }

    /// Whether this holder still runs, seen from `me` (see the module documentation).
    pub fn liveness(&self, me: &Holder) -> Liveness {
        if matches!((&self.host, &me.host), (Some(a), Some(b)) if a != b) {
            return Liveness::Running;
        }
        if matches!((&self.boot, &me.boot), (Some(a), Some(b)) if a != b) {
            return Liveness::Gone;
        }
        if !alive(self.pid) {
            return Liveness::Gone;
        }
        match (self.start, start_time(self.pid)) {
            (Some(recorded), Some(now)) if recorded != now => Liveness::Gone,
            _ => Liveness::Running,
        }
    }

    /// The holder for messages: `pid 12` or `pid 12 on host h` when it is not this host.
    pub fn describe(&self, me: &Holder) -> String {
        match &self.host {
            Some(h) if me.host.as_ref().is_some_and(|m| m != h) => {
                format!("pid {} on host {h}", self.pid)
            }
            _ => format!("pid {}", self.pid),
        }
    }
}

/// Whether a process `pid` exists. Without `/proc` every pid is taken as running.
fn alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// Process `pid`'s start time in clock ticks since boot: field 22 of `/proc/PID/stat`. The
/// second field (the command name) is in parentheses and may hold spaces and parentheses, so the
/// fields are counted from the last `)`.
pub(crate) fn start_time(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    parse_start_time(&stat)
}

fn parse_start_time(stat: &str) -> Option<u64> {
    let rest = &stat[stat.rfind(')')? + 1..];
    // After the name: field 3 (state) is the first; field 22 is the 20th.
    rest.split_whitespace().nth(19)?.parse().ok()
}

fn read_line(path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.trim();
    (!line.is_empty() && !line.contains('\n')).then(|| line.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_start_time_is_field_22_whatever_the_name() {
        let fields: Vec<String> = (3..=30).map(|i| i.to_string()).collect();
        let stat = format!("77 (a) b) (c) {}", fields.join(" "));
        assert_eq!(parse_start_time(&stat), Some(22));
        assert_eq!(parse_start_time("77 (x) S 1"), None);
        if Path::new("/proc/self/stat").exists() {
            assert!(start_time(std::process::id()).is_some());
        }
    }

    #[test]
    fn text_round_trips_and_old_locks_parse() {
        let me = Holder::me();
        assert_eq!(Holder::parse(&me.to_text()), Some(me.clone()));
        let old = Holder::parse("42\n").unwrap();
        assert_eq!(
            (old.pid, old.start, old.boot, old.host),
            (42, None, None, None)
        );
        assert_eq!(Holder::parse("x\nstart=1"), None);
    }

    #[test]
    fn tags_round_trip_short_and_old_names_parse() {
        let me = Holder::me();
        assert_eq!(Holder::parse_tag(&me.tag()), Some(me.short()));
        let full = Holder {
            pid: 9,
            start: Some(123),
            boot: Some("0f1e2d3c-aaaa-bbbb-cccc-000011112222".into()),
            host: Some("a host.example".into()),
        };
        let tag = full.tag();
        assert!(tag.starts_with("9.s123.b") && !tag.contains(' '), "{tag}");
        assert_eq!(Holder::parse_tag(&tag), Some(full.short()));
        let old = Holder::parse_tag("42").unwrap();
        assert_eq!(
            (old.pid, old.start, old.boot, old.host),
            (42, None, None, None)
        );
        for bad in ["", "x", "4.s", "4.sx", "4.bxyz", "4.s1.s2", "4.q1", "-4"] {
            assert_eq!(Holder::parse_tag(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_reused_pid_another_boot_or_a_dead_pid_is_gone() {
        let me = Holder::me();
        assert_eq!(me.liveness(&me), Liveness::Running);
        if me.start.is_none() {
            return; // no /proc: nothing can be told apart
        }
        // The pid of a live process that started at another time: the pid was reused.
        let reused = Holder {
            start: me.start.map(|t| t + 12345),
            ..me.clone()
        };
        assert_eq!(reused.liveness(&me), Liveness::Gone);
        let rebooted = Holder {
            boot: Some("another-boot".into()),
            ..me.clone()
        };
        assert_eq!(rebooted.liveness(&me), Liveness::Gone);
        let dead = Holder {
            pid: 4_999_999,
            ..me.clone()
        };
        assert_eq!(dead.liveness(&me), Liveness::Gone);
        // Another host cannot be checked from here: held.
        let remote = Holder {
            host: Some("elsewhere".into()),
            pid: 4_999_999,
            ..me.clone()
        };
        assert_eq!(remote.liveness(&me), Liveness::Running);
        assert_eq!(remote.describe(&me), "pid 4999999 on host elsewhere");
        assert_eq!(me.describe(&me), format!("pid {}", me.pid));
    }
}
