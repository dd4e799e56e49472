//! What a parsed [`Shader`] answers: its WGSL form (for the replay), the fragment entry point a
//! name picks, and the `path:line:col` of a span in diagnostics.

use super::{FrontError, Lang, Shader, parse_text, write_wgsl};
use crate::diagnostic::{Message, SourceDiagnostic};
use crate::directives::{HiddenEntries, HiddenEntry};

impl Shader {
    /// The same shader with WGSL source text, as the replay renders it: itself for WGSL (and
    /// SPIR-V, whose source is already WGSL, and a GLSL shader's WGSL form), naga's WGSL of the
    /// module for GLSL and for a WGSL shader whose reading filled in bindings or `flat`s its text
    /// leaves out ([`Shader::filled_in`]). Spans of the result point into the WGSL.
    pub fn to_wgsl(&self) -> Result<Shader, FrontError> {
        if (self.lang != Lang::Glsl && !self.filled_in) || self.wgsl_form {
            return Ok(self.clone());
        }
        let path = self.path.display();
        let wgsl = write_wgsl(&self.module, &self.info).map_err(|what| FrontError::Internal {
            what: format!("{path}: {what}"),
        })?;
        let shader =
            parse_text(&self.path, Lang::Wgsl, wgsl).map_err(|e| FrontError::Internal {
                what: format!("naga's WGSL of {path} does not parse again: {e}"),
            })?;
        Ok(Shader {
            lang: self.lang,
            split_samplers: self.split_samplers.clone(),
            warnings: self.warnings.clone(),
            hidden_entries: self.hidden_entries.clone(),
            wgsl_form: true,
            ..shader
        })
    }

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
                .ok_or_else(|| {
                    let named: Vec<HiddenEntry> = self
                        .hidden_entries
                        .iter()
                        .filter(|h| h.name == n)
                        .cloned()
                        .collect();
                    FrontError::UnknownEntry {
                        path: self.path.clone(),
                        name: n.to_owned(),
                        available: names(),
                        hidden: HiddenEntries(if named.is_empty() {
                            self.hidden_entries.clone()
                        } else {
                            named
                        }),
                    }
                }),
            None => match frags.as_slice() {
                [] => Err(FrontError::NoFragmentEntry {
                    path: self.path.clone(),
                    hidden: HiddenEntries(self.hidden_entries.clone()),
                }),
                [(i, _)] => Ok(*i),
                _ => Err(FrontError::AmbiguousEntry {
                    path: self.path.clone(),
                    names: names(),
                }),
            },
        }
    }

    /// The span of the name of the function `name` in the source (`fn name` in WGSL, `void name`
    /// in GLSL), for errors about a whole entry point, whose IR has no span; undefined when not
    /// found (a SPIR-V module's names, say).
    pub fn entry_span(&self, name: &str) -> naga::Span {
        let src = &self.source;
        ["fn ", "void "]
            .iter()
            .find_map(|kw| {
                let needle = format!("{kw}{name}");
                src.match_indices(&needle)
                    .find(|(i, _)| {
                        let end = i + needle.len();
                        let before_ok = src[..*i]
                            .chars()
                            .next_back()
                            .is_none_or(|c| !c.is_alphanumeric() && c != '_');
                        let after_ok =
                            !src[end..].starts_with(|c: char| c.is_alphanumeric() || c == '_');
                        before_ok && after_ok
                    })
                    .map(|(i, _)| {
                        let start = (i + kw.len()) as u32;
                        naga::Span::new(start, start + name.len() as u32)
                    })
            })
            .unwrap_or_default()
    }

    /// An unsupported-construct error at `span`: `file:line:col`, and the source line with a caret
    /// under the construct (codespan, as naga renders parse errors).
    pub fn unsupported(&self, span: naga::Span, what: impl Into<String>) -> FrontError {
        let mut m = Message::new(format!("unsupported: {}", what.into()));
        match span.to_range() {
            Some(range) => m.labels.push((range, String::new())),
            None => m.at = Some(self.location(span)),
        }
        FrontError::Unsupported(SourceDiagnostic::new(
            self.path.clone(),
            &self.source,
            vec![m],
        ))
    }

    /// `file:line:col` of a span, for one-line messages.
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
