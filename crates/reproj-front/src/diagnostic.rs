//! Diagnostics kept as data until they are shown.
//!
//! A parse error, a validation error or an unsupported construct is a [`SourceDiagnostic`]: the
//! file, its text and, per message, the byte ranges it is about. Libraries pass it up unrendered
//! (its `Display` is one line, `file:line:col: message`, for logs and progress notes); the CLI
//! renders it whole with [`SourceDiagnostic::render`] — the source line and a caret under the
//! construct, as naga renders WGSL errors.

use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;

/// One message and the places it is about (the first label is the primary one).
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    pub text: String,
    /// Byte ranges into the source and what each one is.
    pub labels: Vec<(Range<usize>, String)>,
    /// Further lines (naga's error chain, hints).
    pub notes: Vec<String>,
    /// Where to say it is when there is no label (`file:line:col` found another way).
    pub at: Option<String>,
}

impl Message {
    pub fn new(text: impl Into<String>) -> Message {
        Message {
            text: text.into(),
            labels: Vec::new(),
            notes: Vec::new(),
            at: None,
        }
    }
}

/// Messages about one shader's source.
#[derive(Debug, Clone, PartialEq)]
pub struct SourceDiagnostic {
    pub path: PathBuf,
    pub source: Arc<str>,
    pub messages: Vec<Message>,
}

impl SourceDiagnostic {
    pub fn new(path: PathBuf, source: &str, messages: Vec<Message>) -> SourceDiagnostic {
        SourceDiagnostic {
            path,
            source: Arc::from(source),
            messages,
        }
    }

    /// `file:line:col` of the first message's primary label (or its `at`, or the file).
    pub fn location(&self) -> String {
        let Some(m) = self.messages.first() else {
            return self.path.display().to_string();
        };
        match m.labels.first() {
            Some((range, _)) => {
                let start = range.start.min(self.source.len());
                let prefix = &self.source[..start];
                let line = prefix.matches('\n').count() + 1;
                let col = start - prefix.rfind('\n').map_or(0, |n| n + 1) + 1;
                format!("{}:{line}:{col}", self.path.display())
            }
            None => {
                m.at.clone()
                    .unwrap_or_else(|| self.path.display().to_string())
            }
        }
    }

    /// Every message with its source lines and carets (codespan).
    pub fn render(&self) -> String {
        use codespan_reporting::diagnostic::{Diagnostic, Label};
        use codespan_reporting::files::SimpleFile;
        use codespan_reporting::term;
        let path = self.path.display().to_string();
        let text = printable(&self.source);
        let files = SimpleFile::new(path.as_str(), text.as_str());
        let config = term::Config::default();
        let mut out = String::new();
        for m in &self.messages {
            let mut d = Diagnostic::error().with_notes(m.notes.clone());
            let labels: Vec<Label<()>> = m
                .labels
                .iter()
                .filter(|(r, _)| r.end <= text.len())
                .enumerate()
                .map(|(i, (r, msg))| {
                    let l = if i == 0 {
                        Label::primary((), r.clone())
                    } else {
                        Label::secondary((), r.clone())
                    };
                    l.with_message(msg.clone())
                })
                .collect();
            d = if labels.is_empty() {
                let at = m.at.clone().unwrap_or_else(|| path.clone());
                d.with_message(format!("{at}: {}", m.text))
            } else {
                d.with_message(m.text.clone()).with_labels(labels)
            };
            if term::emit_to_string(&mut out, &config, &files, &d).is_err() {
                return format!("error: {self}\n");
            }
        }
        out
    }
}

impl std::fmt::Display for SourceDiagnostic {
    /// One line: `file:line:col: message` (and how many more messages there are).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let text = self.messages.first().map_or("", |m| m.text.as_str());
        write!(f, "{}: {text}", self.location())?;
        if self.messages.len() > 1 {
            write!(f, " (and {} more)", self.messages.len() - 1)?;
        }
        Ok(())
    }
}

/// The source with control characters (other than line breaks and tabs) blanked byte for byte,
/// so the terminal shows the line and every byte range stays where it was.
fn printable(source: &str) -> String {
    source
        .chars()
        .flat_map(|c| {
            let blank = c.is_control() && !matches!(c, '\n' | '\r' | '\t');
            let n = if blank { c.len_utf8() } else { 1 };
            std::iter::repeat_n(if blank { ' ' } else { c }, n)
        })
        .collect()
}

/// How deep naga's WGSL parser lets expressions and statements nest (its `track_recursion`);
/// deeper, it fails with an "internal" error that has no position.
pub const WGSL_NESTING_LIMIT: usize = 200;

/// A WGSL parse error as data. naga's recursion-limit error has no span: it is given the place
/// in `source` where the nesting goes past the limit (see [`too_deep`]).
pub(crate) fn from_wgsl(e: &naga::front::wgsl::ParseError, source: &str) -> Vec<Message> {
    if e.labels().next().is_none() && e.notes().any(|n| n.contains("recursion limit")) {
        return vec![too_deep(source)];
    }
    vec![Message {
        text: e.message().to_owned(),
        labels: e
            .labels()
            .filter_map(|(span, l)| Some((span.to_range()?, l.to_owned())))
            .collect(),
        notes: e.notes().map(str::to_owned).collect(),
        at: None,
    }]
}

/// The message for WGSL nested past [`WGSL_NESTING_LIMIT`]: labelled at the first `(`, `[` or `{`
/// (outside comments) whose depth reaches the limit, less the statement and expression levels
/// around the outermost one (or at the deepest one, for nesting naga counts another way).
fn too_deep(source: &str) -> Message {
    let opening = nesting(source);
    let at = opening
        .iter()
        .find(|&&(_, depth)| depth >= WGSL_NESTING_LIMIT - 1)
        .or_else(|| opening.iter().max_by_key(|&&(_, depth)| depth));
    Message {
        text: format!(
            "expressions and blocks nest too deeply (the WGSL parser allows {WGSL_NESTING_LIMIT} levels)"
        ),
        labels: at
            .map(|&(offset, depth)| (offset..offset + 1, format!("nesting depth {depth} here")))
            .into_iter()
            .collect(),
        notes: vec![format!(
            "naga's WGSL parser stops at {WGSL_NESTING_LIMIT} nested expressions, calls and blocks: \
             split the expression with `let`s"
        )],
        at: None,
    }
}

/// Each opening bracket of WGSL text outside comments (`(`, `[`, `{`) with the depth it opens.
fn nesting(source: &str) -> Vec<(usize, usize)> {
    let bytes = source.as_bytes();
    let mut out = Vec::new();
    let (mut depth, mut block_comments, mut i) = (0usize, 0usize, 0usize);
    while i < bytes.len() {
        let pair = (bytes[i], bytes.get(i + 1).copied());
        match pair {
            (b'/', Some(b'*')) => {
                block_comments += 1;
                i += 2;
                continue;
            }
            (b'*', Some(b'/')) if block_comments > 0 => {
                block_comments -= 1;
                i += 2;
                continue;
            }
            _ if block_comments > 0 => {}
            (b'/', Some(b'/')) => {
                i += bytes[i..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .unwrap_or(bytes.len() - i);
                continue;
            }
            (b'(' | b'[' | b'{', _) => {
                depth += 1;
                out.push((i, depth));
            }
            (b')' | b']' | b'}', _) => depth = depth.saturating_sub(1),
            _ => {}
        }
        i += 1;
    }
    out
}

/// GLSL parse errors as data (naga reports every error it found).
pub(crate) fn from_glsl(e: &naga::front::glsl::ParseErrors) -> Vec<Message> {
    e.errors
        .iter()
        .map(|err| Message {
            text: err.kind.to_string(),
            labels: err
                .meta
                .to_range()
                .map(|r| (r, String::new()))
                .into_iter()
                .collect(),
            notes: Vec::new(),
            at: None,
        })
        .collect()
}

/// A validation error as data: its spans, and its error chain as notes.
pub(crate) fn from_validation(
    e: &naga::WithSpan<naga::valid::ValidationError>,
    at: Option<String>,
) -> Vec<Message> {
    let mut notes = Vec::new();
    let mut source = std::error::Error::source(e.as_inner());
    while let Some(next) = source {
        notes.push(next.to_string());
        source = next.source();
    }
    vec![Message {
        text: e.as_inner().to_string(),
        labels: e
            .spans()
            .filter_map(|(span, l)| Some((span.to_range()?, l.clone())))
            .collect(),
        notes,
        at,
    }]
}
