//! Parsing, validation and entry-point choice.

use std::path::{Path, PathBuf};

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

/// A parsed and validated WGSL module with its source text, kept together so that every later
/// diagnostic can point into the text.
#[derive(Debug, Clone)]
pub struct Shader {
    /// Path used in diagnostics (`file:line:col`).
    pub path: PathBuf,
    pub source: String,
    pub module: naga::Module,
    pub info: ModuleInfo,
}

/// Everything that can go wrong in the front end. Each variant renders as one clear message; the
/// parse and validation variants carry naga's full diagnostic (file:line and a caret).
#[derive(Debug, thiserror::Error)]
pub enum FrontError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{diagnostic}")]
    Parse { diagnostic: String },
    #[error("{diagnostic}")]
    Validation { diagnostic: String },
    #[error("{path}: the module has no @fragment entry point")]
    NoFragmentEntry { path: PathBuf },
    #[error("{path}: the module has several @fragment entry points ({}); choose one with --entry", names.join(", "))]
    AmbiguousEntry { path: PathBuf, names: Vec<String> },
    #[error("{path}: no @fragment entry point named `{name}` (fragment entry points: {})", available.join(", "))]
    UnknownEntry {
        path: PathBuf,
        name: String,
        available: Vec<String>,
    },
    /// `diagnostic`: the message with the source line and a caret under the construct, rendered
    /// like naga's parse errors ([`Shader::unsupported`]).
    #[error("{diagnostic}")]
    Unsupported {
        location: String,
        what: String,
        diagnostic: String,
    },
    /// An unsupported construct inside the IR, before it is given a file location.
    #[error("unsupported: {what}")]
    UnsupportedAt { span: naga::Span, what: String },
    /// A bug in reproj: an invariant did not hold.
    #[error("internal error: {what}")]
    Internal { what: String },
}

/// Validator used everywhere in reproj: every check on, every capability allowed.
pub fn validator() -> Validator {
    Validator::new(ValidationFlags::all(), Capabilities::all())
}

/// Read a shader file from disk, then [`parse_shader`].
pub fn load_file(path: &Path) -> Result<Shader, FrontError> {
    let source = std::fs::read_to_string(path).map_err(|source| FrontError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse_shader(path, source)
}

/// Parse WGSL text and validate the module. Errors carry naga's rendered diagnostic.
pub fn parse_shader(path: &Path, source: String) -> Result<Shader, FrontError> {
    let path_str = path.display().to_string();
    let module = naga::front::wgsl::parse_str(&source).map_err(|e| FrontError::Parse {
        diagnostic: e.emit_to_string_with_path(&source, &path_str),
    })?;
    let info = validator().validate(&module).map_err(|e| {
        let mut diagnostic = e.emit_to_string_with_path(&source, &path_str);
        if !e.spans().any(|(span, _)| span.to_range().is_some()) {
            // naga gives some errors (a whole entry point's) no span: name the place ourselves.
            let at = unspanned_location(&e, &module, &source, &path_str);
            diagnostic = match diagnostic.strip_prefix("error: ") {
                Some(rest) => format!("error: {at}{rest}"),
                None => format!("{at}{diagnostic}"),
            };
        }
        FrontError::Validation { diagnostic }
    })?;
    Ok(Shader {
        path: path.to_owned(),
        source,
        module,
        info,
    })
}

/// `path:line:col: ` of the entry point or function a span-less validation error names (or just
/// `path: `), so every diagnostic says where.
fn unspanned_location(
    e: &naga::WithSpan<naga::valid::ValidationError>,
    module: &naga::Module,
    source: &str,
    path: &str,
) -> String {
    use naga::valid::ValidationError as V;
    let name = match e.as_inner() {
        V::EntryPoint { name, .. } => Some(name.clone()),
        V::Function { handle, .. } => module.functions[*handle].name.clone(),
        _ => None,
    };
    let at = name.and_then(|name| {
        let needle = format!("fn {name}");
        source
            .match_indices(&needle)
            .find(|(i, _)| {
                !source[i + needle.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
            })
            .map(|(i, _)| i)
    });
    match at {
        Some(i) => {
            let line = source[..i].matches('\n').count() + 1;
            let col = i - source[..i].rfind('\n').map_or(0, |n| n + 1) + 1;
            format!("{path}:{line}:{col}: ")
        }
        None => format!("{path}: "),
    }
}

impl Shader {
    /// Index of the fragment entry point: `name` if given, else the only one.
    pub fn fragment_entry(&self, name: Option<&str>) -> Result<usize, FrontError> {
        let frags: Vec<(usize, &naga::EntryPoint)> = self
            .module
            .entry_points
            .iter()
            .enumerate()
            .filter(|(_, ep)| ep.stage == naga::ShaderStage::Fragment)
            .collect();
        let names = || {
            frags
                .iter()
                .map(|(_, ep)| ep.name.clone())
                .collect::<Vec<_>>()
        };
        match name {
            Some(n) => frags
                .iter()
                .find(|(_, ep)| ep.name == n)
                .map(|(i, _)| *i)
                .ok_or_else(|| FrontError::UnknownEntry {
                    path: self.path.clone(),
                    name: n.to_owned(),
                    available: names(),
                }),
            None => match frags.as_slice() {
                [] => Err(FrontError::NoFragmentEntry {
                    path: self.path.clone(),
                }),
                [(i, _)] => Ok(*i),
                _ => Err(FrontError::AmbiguousEntry {
                    path: self.path.clone(),
                    names: names(),
                }),
            },
        }
    }

    /// `file:line:col` of a span, for one-line messages.
    /// An unsupported-construct error at `span`: `file:line:col`, and the source line with a caret
    /// under the construct (codespan, as naga renders parse errors).
    pub fn unsupported(&self, span: naga::Span, what: impl Into<String>) -> FrontError {
        use codespan_reporting::diagnostic::{Diagnostic, Label};
        use codespan_reporting::files::SimpleFile;
        let what = what.into();
        let location = self.location(span);
        let path = self.path.display().to_string();
        let files = SimpleFile::new(path, self.source.as_str());
        let mut diagnostic = Diagnostic::error().with_message(format!("unsupported: {what}"));
        if let Some(range) = span.to_range() {
            diagnostic = diagnostic.with_labels(vec![Label::primary((), range)]);
        }
        let diagnostic = codespan_reporting::term::emit_into_string(
            &codespan_reporting::term::Config::default(),
            &files,
            &diagnostic,
        )
        .unwrap_or_else(|_| format!("error: {location}: unsupported: {what}\n"));
        FrontError::Unsupported {
            location,
            what,
            diagnostic,
        }
    }

    pub fn location(&self, span: naga::Span) -> String {
        if span.is_defined() {
            let loc = span.location(&self.source);
            format!(
                "{}:{}:{}",
                self.path.display(),
                loc.line_number,
                loc.line_position
            )
        } else {
            self.path.display().to_string()
        }
    }
}
