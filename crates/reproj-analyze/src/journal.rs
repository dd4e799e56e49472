//! The analysis journal: every finished replay, appended to a file beside the profile as it
//! completes, so an interrupted `analyze` (killed, out of time, a crash) resumes where it stopped.
//!
//! Format: JSON Lines. The first line is a header naming the journal's schema and a key over
//! everything that decides a replay's result (shader, session, periods, nodes, strategies, options,
//! adapter); a journal with another key is from another analysis and is started over. Each further
//! line is one replay: node (or set of nodes, `set`), strategy, block, Δn and its measurement or
//! failure — or one race (the strategies' interleaved timing against the original, whose
//! report decides the winner and the set-aside rule, so a resumed run must not time it again). A line is written with one `write` of the whole line and synced, so a kill leaves at
//! most one torn last line, which reading ignores.

use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};

pub(crate) use reproj_models::journal::{ReplayKey, ReplayResult};
use reproj_models::journal::{header_line, original_line, race_line, record_line};
use reproj_models::profile::OriginalRecord;

use crate::AnalyzeError;

/// Where the journal lives and whether to use what it holds.
#[derive(Debug, Clone)]
pub struct JournalOptions {
    pub path: PathBuf,
    /// Start over, ignoring (and truncating) an existing journal.
    pub fresh: bool,
}

/// An open journal.
#[derive(Debug)]
pub(crate) struct Journal {
    path: PathBuf,
    file: std::fs::File,
    done: HashMap<ReplayKey, ReplayResult>,
    original: Option<OriginalRecord>,
    /// Races' reports (`reproj.bench` as JSON), by key.
    races: HashMap<ReplayKey, serde_json::Value>,
    /// Replays answered from the journal in this run.
    pub reused: usize,
    /// Replays recorded in this run.
    pub recorded: usize,
    /// Races answered from the journal, and raced and recorded, in this run.
    pub races_reused: usize,
    pub races_recorded: usize,
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> AnalyzeError + '_ {
    move |source| AnalyzeError::Io {
        path: path.to_owned(),
        source,
    }
}

impl Journal {
    /// Open (or start) the journal for an analysis whose settings hash to `key`. Returns the
    /// journal and, when an existing one was set aside, why.
    pub(crate) fn open(
        opts: &JournalOptions,
        key: &str,
    ) -> Result<(Journal, Option<String>), AnalyzeError> {
        let path = &opts.path;
        let mut done = HashMap::new();
        let mut original = None;
        let mut races = HashMap::new();
        let mut note = None;
        if !opts.fresh && path.exists() {
            // Bytes, not text: a journal damaged by a crash or a disk error (invalid UTF-8) is
            // read as far as its lines parse; the damaged ones are dropped, never a hard error.
            let bytes = std::fs::read(path).map_err(io(path))?;
            let parsed = reproj_models::journal::parse(&String::from_utf8_lossy(&bytes), key);
            if parsed.header_matches {
                done = parsed.done;
                original = parsed.original;
                races = parsed.races;
                if parsed.dropped > 0 {
                    note = Some(format!(
                        "{}: {} damaged or invalid line(s) dropped (their replays run again)",
                        path.display(),
                        parsed.dropped
                    ));
                }
            } else {
                note = Some(format!(
                    "{}: from another analysis (shader, session or settings differ); starting over",
                    path.display()
                ));
            }
        }
        // Start the file afresh: the header, then what is kept (a torn tail dropped). Written
        // atomically, then appended to.
        let mut text = header_line(key);
        if let Some(o) = &original {
            text.push_str(&original_line(o));
        }
        for (k, r) in &done {
            text.push_str(&record_line(k, r));
        }
        for (k, r) in &races {
            text.push_str(&race_line(k, r.clone()));
        }
        reproj_io::write_file(path, text.as_bytes())?;
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(io(path))?;
        Ok((
            Journal {
                path: path.clone(),
                file,
                done,
                original,
                races,
                reused: 0,
                recorded: 0,
                races_reused: 0,
                races_recorded: 0,
            },
            note,
        ))
    }

    /// Replays the journal holds.
    pub(crate) fn len(&self) -> usize {
        self.done.len()
    }

    /// The recorded result of a replay, if this journal has it.
    pub(crate) fn get(&mut self, key: &ReplayKey) -> Option<ReplayResult> {
        let r = self.done.get(key).cloned();
        if r.is_some() {
            self.reused += 1;
        }
        r
    }

    /// Append a finished replay (one write, synced).
    pub(crate) fn record(
        &mut self,
        key: ReplayKey,
        result: &ReplayResult,
    ) -> Result<(), AnalyzeError> {
        self.append(&record_line(&key, result))?;
        self.done.insert(key, result.clone());
        self.recorded += 1;
        Ok(())
    }

    /// A race's recorded report (unchecked JSON), if this journal has it.
    pub(crate) fn race(&self, key: &ReplayKey) -> Option<&serde_json::Value> {
        self.races.get(key)
    }

    /// Count a race answered from the journal.
    pub(crate) fn reuse_race(&mut self) {
        self.races_reused += 1;
    }

    /// Append a finished race's report (one write, synced).
    pub(crate) fn record_race(
        &mut self,
        key: ReplayKey,
        report: serde_json::Value,
    ) -> Result<(), AnalyzeError> {
        self.append(&race_line(&key, report.clone()))?;
        self.races.insert(key, report);
        self.races_recorded += 1;
        Ok(())
    }

    /// The original shader's record: the journal's when it has one, else `measured`, recorded.
    pub(crate) fn original(
        &mut self,
        measured: OriginalRecord,
    ) -> Result<OriginalRecord, AnalyzeError> {
        if let Some(o) = &self.original {
            return Ok(o.clone());
        }
        self.append(&original_line(&measured))?;
        self.original = Some(measured.clone());
        Ok(measured)
    }

    fn append(&mut self, line: &str) -> Result<(), AnalyzeError> {
        self.file
            .write_all(line.as_bytes())
            .and_then(|()| self.file.sync_data())
            .map_err(io(&self.path))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use reproj_models::profile::Measurement;

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
    fn damaged_and_invalid_lines_are_dropped_and_the_rest_resumes() {
        let dir = tempfile::tempdir().unwrap();
        let opts = JournalOptions {
            path: dir.path().join("p.journal"),
            fresh: false,
        };
        let (mut j, note) = Journal::open(&opts, "k").unwrap();
        assert!(note.is_none());
        j.record(key(2), &Ok((measurement(3.0), vec![1.0])))
            .unwrap();
        drop(j);
        // A record with a negative frame time, then bytes that are not UTF-8 (a damaged tail).
        let mut bytes = std::fs::read(&opts.path).unwrap();
        bytes.extend(record_line(&key(4), &Ok((measurement(-5.0), vec![]))).as_bytes());
        bytes.extend([0xff, 0xfe, b'{', b'\n']);
        std::fs::write(&opts.path, &bytes).unwrap();
        let (j, note) = Journal::open(&opts, "k").unwrap();
        assert_eq!(j.len(), 1);
        let note = note.unwrap();
        assert!(note.contains("2 damaged or invalid"), "{note}");
        // The rewritten journal holds only what is valid.
        let text = std::fs::read_to_string(&opts.path).unwrap();
        assert_eq!(text.lines().count(), 2, "{text}");
    }
}
