//! The analysis journal's data: its lines and how a journal's text is read back. The file itself
//! (opening, appending, syncing) is `reproj-analyze`'s; this part is pure so that it can be
//! fuzzed without a GPU stack.
//!
//! Format: JSON Lines. The first line is a [`Header`] naming the journal's schema and a key over
//! everything that decides a replay's result (shader, session, periods, nodes, strategies, options,
//! adapter); a journal with another key is from another analysis and is started over. Each further
//! line is one [`Record`]: node (or set of nodes, `set`), strategy, block, Δn and its measurement
//! or failure. A kill leaves at most one torn last line, which [`parse`] ignores.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use crate::profile::{Measurement, OriginalRecord};

/// The journal's schema name (its header's `schema`).
pub const SCHEMA: &str = "reproj.journal";
/// Version 2: measurements carry the perceptual metrics (a version 1 journal is started over).
pub const VERSION: u32 = 2;

/// The first line of a journal.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    pub schema: String,
    pub version: u32,
    pub key: String,
}

/// One replay's identity.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ReplayKey {
    pub node: u32,
    pub strategy: String,
    pub block: u32,
    pub delta_n: u32,
    /// A strategy probe over the session's first N frames; `None`: the whole session.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<u32>,
    /// A set of nodes cached together: its members in payload order (`node` is the first);
    /// empty for a single node.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub set: Vec<u32>,
    /// The reconstruction filter, when it is not the analysis's own (a filter race's challenger,
    /// `analyze --reconstruct auto`); `None`: the one the journal's header key names.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reconstruct: Option<String>,
}

impl ReplayKey {
    /// The key of the original shader's record: its frame times decide which nodes are set
    /// aside, so a resumed run must use the same ones.
    pub fn original() -> ReplayKey {
        ReplayKey {
            node: u32::MAX,
            strategy: "original".into(),
            block: 0,
            delta_n: 1,
            frames: None,
            set: Vec::new(),
            reconstruct: None,
        }
    }
}

impl ReplayKey {
    /// The key of a race: the strategies `names` of `node` (or the set `set`) timed against the
    /// original at period `delta_n` over the session's first `frames` frames (all: `None`).
    pub fn race(
        node: u32,
        set: &[u32],
        names: &[&str],
        delta_n: u32,
        frames: Option<u32>,
    ) -> ReplayKey {
        ReplayKey {
            node,
            strategy: format!("race:{}", names.join("+")),
            block: 0,
            delta_n,
            frames,
            set: set.to_vec(),
            reconstruct: None,
        }
    }
}

/// One replay's result: the measurement and mean per-pass times, or why it failed.
pub type ReplayResult = Result<(Measurement, Vec<f64>), String>;

/// One line after the header.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    #[serde(flatten)]
    pub key: ReplayKey,
    pub measurement: Option<Measurement>,
    #[serde(default)]
    pub pass_ms: Vec<f64>,
    pub failure: Option<String>,
    /// Set on the record of the original shader's replay (key: [`ReplayKey::original`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub original: Option<OriginalRecord>,
    /// Set on the record of a race (key: [`ReplayKey::race`]): the timing engine's report
    /// (`reproj.bench`), kept as JSON here (this crate does not know its type; the reader checks
    /// it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub race: Option<serde_json::Value>,
}

impl Record {
    /// Whether the record's numbers are measurements (see `Profile::check`).
    pub fn is_valid(&self) -> bool {
        self.original.as_ref().is_none_or(|o| o.check("").is_ok())
            && self
                .measurement
                .as_ref()
                .is_none_or(|m| m.check("").is_ok())
            && self.pass_ms.iter().all(|t| t.is_finite() && *t >= 0.0)
    }
}

/// What [`parse`] read of a journal's text.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Parsed {
    /// The header names this schema, version and key: the records below belong to this analysis.
    /// Otherwise the journal is from another analysis and everything else is empty.
    pub header_matches: bool,
    /// The finished replays, by key (a later line for the same key wins).
    pub done: HashMap<ReplayKey, ReplayResult>,
    /// The original shader's record, if the journal has one (the last one wins).
    pub original: Option<OriginalRecord>,
    /// The races' reports, by key (unchecked JSON: see [`Record::race`]).
    pub races: HashMap<ReplayKey, serde_json::Value>,
    /// Lines that are not empty and did not parse or whose numbers are not measurements.
    pub dropped: usize,
}

/// Read a journal's text for an analysis whose settings hash to `key`: the header checked, then
/// every record that parses and whose numbers are measurements. A torn or damaged line (killed
/// mid-write, a disk error) is dropped and counted, never an error.
pub fn parse(text: &str, key: &str) -> Parsed {
    let mut parsed = Parsed::default();
    let mut lines = text.lines();
    let header = lines
        .next()
        .and_then(|l| serde_json::from_str::<Header>(l).ok());
    if !header.is_some_and(|h| h.schema == SCHEMA && h.version == VERSION && h.key == key) {
        return parsed;
    }
    parsed.header_matches = true;
    for line in lines {
        // A torn last line (killed mid-write) does not parse: skip it. A record whose numbers
        // are not measurements (a negative time, NaN) is dropped and replayed again.
        let Some(r) = serde_json::from_str::<Record>(line)
            .ok()
            .filter(Record::is_valid)
        else {
            parsed.dropped += usize::from(!line.trim().is_empty());
            continue;
        };
        if r.original.is_some() {
            parsed.original = r.original;
            continue;
        }
        if let Some(race) = r.race {
            parsed.races.insert(r.key, race);
            continue;
        }
        let result = match (r.measurement, r.failure) {
            (Some(m), _) => Ok((m, r.pass_ms)),
            (None, Some(f)) => Err(f),
            (None, None) => continue,
        };
        parsed.done.insert(r.key, result);
    }
    parsed
}

/// The header line (with its newline) of a journal for `key`.
pub fn header_line(key: &str) -> String {
    let mut line = serde_json::to_string(&Header {
        schema: SCHEMA.into(),
        version: VERSION,
        key: key.into(),
    })
    .expect("a header serializes");
    line.push('\n');
    line
}

/// The line (with its newline) of the original shader's record.
pub fn original_line(o: &OriginalRecord) -> String {
    let mut line = serde_json::to_string(&Record {
        key: ReplayKey::original(),
        measurement: None,
        pass_ms: Vec::new(),
        failure: None,
        original: Some(o.clone()),
        race: None,
    })
    .expect("a record serializes");
    line.push('\n');
    line
}

/// The line (with its newline) of one replay's result.
pub fn record_line(key: &ReplayKey, result: &ReplayResult) -> String {
    let (measurement, pass_ms, failure) = match result {
        Ok((m, p)) => (Some(m.clone()), p.clone(), None),
        Err(e) => (None, Vec::new(), Some(e.clone())),
    };
    let mut line = serde_json::to_string(&Record {
        key: key.clone(),
        measurement,
        pass_ms,
        failure,
        original: None,
        race: None,
    })
    .expect("a record serializes");
    line.push('\n');
    line
}

/// The line (with its newline) of a race's report.
pub fn race_line(key: &ReplayKey, report: serde_json::Value) -> String {
    let mut line = serde_json::to_string(&Record {
        key: key.clone(),
        measurement: None,
        pass_ms: Vec::new(),
        failure: None,
        original: None,
        race: Some(report),
    })
    .expect("a record serializes");
    line.push('\n');
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    fn measurement(frame_ms: f64) -> Measurement {
        Measurement {
            delta_n: 4,
            error: 0.01,
            error_worst: None,
            flip: None,
            ssim: None,
            mse: None,
            psnr: None,
            hit_rate: 0.9,
            frame_ms,
            frames: Vec::new(),
            frame_errors: Vec::new(),
        }
    }

    fn key(delta_n: u32) -> ReplayKey {
        ReplayKey {
            node: 3,
            strategy: "3pass".into(),
            block: 4,
            delta_n,
            frames: None,
            set: Vec::new(),
            reconstruct: None,
        }
    }

    #[test]
    fn written_lines_read_back() {
        let mut text = header_line("k");
        text.push_str(&record_line(&key(2), &Ok((measurement(3.0), vec![1.0]))));
        text.push_str(&record_line(&key(4), &Err("lost".into())));
        let p = parse(&text, "k");
        assert!(p.header_matches);
        assert_eq!(p.dropped, 0);
        assert_eq!(p.done.len(), 2);
        assert_eq!(p.done[&key(4)], Err("lost".into()));
        // A race's report reads back by its key.
        let rk = ReplayKey::race(3, &[], &["2pass", "3pass"], 50, Some(40));
        text.push_str(&race_line(&rk, serde_json::json!({"rounds": 8})));
        let p = parse(&text, "k");
        assert_eq!(p.done.len(), 2);
        assert_eq!(p.races[&rk]["rounds"], 8);
        // Another analysis: nothing kept.
        assert_eq!(parse(&text, "other"), Parsed::default());
    }

    #[test]
    fn the_line_format_is_stable() {
        // Journals written by earlier builds must still resume.
        assert_eq!(
            header_line("abc"),
            "{\"schema\":\"reproj.journal\",\"version\":2,\"key\":\"abc\"}\n"
        );
        assert_eq!(
            record_line(&key(8), &Err("x".into())),
            "{\"node\":3,\"strategy\":\"3pass\",\"block\":4,\"delta_n\":8,\"measurement\":null,\"pass_ms\":[],\"failure\":\"x\"}\n"
        );
    }

    #[test]
    fn damaged_and_invalid_lines_are_dropped() {
        let mut text = header_line("k");
        text.push_str(&record_line(&key(2), &Ok((measurement(3.0), vec![1.0]))));
        text.push_str(&record_line(&key(4), &Ok((measurement(-5.0), vec![]))));
        text.push_str("{\"node\":1,\n\n  \n");
        let p = parse(&text, "k");
        assert_eq!(p.done.len(), 1);
        assert_eq!(p.dropped, 2);
    }
}
