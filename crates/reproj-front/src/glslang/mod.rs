//! GLSL through glslang, the reference compiler: GLSL text → SPIR-V → naga.
//!
//! naga's own GLSL front end lacks what shader authors write for Vulkan (combined image samplers
//! `sampler2D`, `layout(offset = N)` push constants, arrays of textures), so GLSL is compiled by
//! `glslangValidator` (Debian `glslang-tools`, installed by `scripts/ensure-tools.sh`) run as a
//! subprocess, with `-g` so the SPIR-V carries `OpLine`. A subprocess, not the `shaderc` crate: the
//! crate needs the system's shaderc library (not installed on every machine, and building it from
//! C++ source takes far too long here) while the validator binary is the same glslang and is
//! already one of the project's tools. Its combined image samplers are split ([`split`]), naga's
//! SPIR-V front end reads the result, and each span (a byte range of the SPIR-V binary) becomes
//! the GLSL line its `OpLine` names, so diagnostics and node positions point into the GLSL file.
//! Without the binary, naga's GLSL front end reads what it can ([`crate::parse`]). A shader that
//! uses a specialization constant inside a constant expression (`OpSpecConstantOp`, which naga
//! does not read) has its specialization constants frozen at their defaults by `spirv-opt`.

mod columns;
mod matrix_inputs;
mod push_constants;
pub mod split;

use std::collections::BTreeSet;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::diagnostic::{Message, SourceDiagnostic};
use crate::input::{DefValue, ShaderInput};
use crate::shader::{FrontError, Lang, Shader, validator};

pub use split::SplitSampler;

/// The glslang binary reproj runs; `REPROJ_GLSLANG` names another.
pub fn glslang_program() -> String {
    std::env::var("REPROJ_GLSLANG").unwrap_or_else(|_| "glslangValidator".to_owned())
}

/// Whether the glslang binary can be run.
pub fn glslang_available() -> bool {
    Command::new(glslang_program())
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Why glslang did not give a module.
#[derive(Debug)]
pub(crate) enum GlslangError {
    /// The binary could not be started.
    Missing,
    /// The GLSL does not compile, or the SPIR-V is not read: the diagnostic to show.
    Front(FrontError),
}

/// Compile fragment-shader GLSL with glslang and read it as a [`Shader`] whose spans point into
/// `source`; `input`'s defs are macros (`-DNAME=VALUE`, a bool 1 or 0) and its include folders
/// are searched after the shader's.
pub(crate) fn parse(
    path: &Path,
    source: String,
    input: &ShaderInput,
) -> Result<Shader, GlslangError> {
    let mut words = compile(path, &source, input)?;
    if split::has_spec_constant_op(&words) {
        words = freeze_spec_constants(path, &source, &words)?;
    }
    let parse_error = |text: String| {
        GlslangError::Front(FrontError::Parse(SourceDiagnostic::new(
            path.to_owned(),
            &source,
            vec![Message::new(text)],
        )))
    };
    let (words, samplers) = split::split_combined_samplers(&words)
        .map_err(|e| parse_error(format!("glslang's SPIR-V: {e}")))?;
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let options = naga::front::spv::Options {
        adjust_coordinate_space: false,
        strict_capabilities: false,
        block_ctx_dump_prefix: None,
    };
    let mut module = naga::front::spv::parse_u8_slice(&bytes, &options).map_err(|e| {
        let reason = format!("naga cannot read glslang's SPIR-V of this shader: {e}");
        match naga_gap(&source) {
            Some((range, what)) => {
                let mut m = Message::new(format!("unsupported: {what}"));
                m.labels.push((range, String::new()));
                GlslangError::Front(FrontError::Unsupported(SourceDiagnostic::new(
                    path.to_owned(),
                    &source,
                    vec![m, Message::new(reason)],
                )))
            }
            None => parse_error(reason),
        }
    })?;
    let lines = line_spans(&source, &split::line_table(&words));
    remap_spans(&mut module, &|span| lines.map(span));
    allow_nonuniform_derivatives(&mut module);
    matrix_inputs::split_matrix_inputs(&mut module);
    push_constants::pad_push_constants(&mut module);
    let info = validator().validate(&module).map_err(|e| {
        GlslangError::Front(FrontError::Validation(SourceDiagnostic::new(
            path.to_owned(),
            &source,
            crate::diagnostic::from_validation(&e, None),
        )))
    })?;
    columns::narrow_spans(&mut module, &info, &source);
    Ok(Shader {
        path: path.to_owned(),
        lang: Lang::Glsl,
        source,
        module,
        info,
        split_samplers: samplers,
        warnings: Vec::new(),
        hidden_entries: Vec::new(),
        wgsl_form: false,
        filled_in: false,
    })
}

/// glslang's SPIR-V of `source` (fragment stage, Vulkan rules, with `OpLine`).
fn compile(path: &Path, source: &str, input: &ShaderInput) -> Result<Vec<u32>, GlslangError> {
    static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let out = std::env::temp_dir().join(format!("reproj-glslang-{}-{n}.spv", std::process::id()));
    // `#include "x.glsl"` (GL_GOOGLE_include_directive) is resolved beside the shader's file, as
    // glslang does when it reads the file itself.
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let includes = std::iter::once(dir)
        .chain(input.include_dirs.iter().map(PathBuf::as_path))
        .map(|d| {
            let mut include = std::ffi::OsString::from("-I");
            include.push(d);
            include
        });
    let defines = macros(input)
        .into_iter()
        .map(|(name, value)| format!("-D{name}={value}"));
    let mut child = Command::new(glslang_program())
        .args(["--stdin", "-S", "frag", "-V", "-g"])
        .args(includes)
        .args(defines)
        .arg("-o")
        .arg(&out)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|_| GlslangError::Missing)?;
    let written = {
        use std::io::Write;
        let mut stdin = child.stdin.take().expect("stdin is piped");
        stdin.write_all(with_include_directive(source).as_bytes())
    };
    let output = child
        .wait_with_output()
        .map_err(|_| GlslangError::Missing)?;
    let bytes = std::fs::read(&out);
    let _ = std::fs::remove_file(&out);
    let bytes = match (output.status.success(), written, bytes) {
        (true, Ok(()), Ok(bytes)) => bytes,
        _ => {
            let text = String::from_utf8_lossy(&output.stdout).into_owned()
                + &String::from_utf8_lossy(&output.stderr);
            return Err(GlslangError::Front(FrontError::Parse(
                SourceDiagnostic::new(path.to_owned(), source, messages(&text, source)),
            )));
        }
    };
    if !bytes.len().is_multiple_of(4) {
        return Err(GlslangError::Front(FrontError::Internal {
            what: format!(
                "glslang wrote {} bytes of SPIR-V, not whole words",
                bytes.len()
            ),
        }));
    }
    Ok(bytes
        .chunks(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

/// `source` with `#extension GL_GOOGLE_include_directive : require` after its `#version` where
/// it `#include`s without asking for the extension: shaderc, the compiler most Vulkan projects
/// build with, turns it on by itself, so their shaders never ask. A `#line` after it keeps every
/// line at its number.
pub(crate) fn with_include_directive(source: &str) -> std::borrow::Cow<'_, str> {
    let includes = source
        .lines()
        .any(|l| l.trim_start().starts_with("#include"));
    if !includes || source.contains("GL_GOOGLE_include_directive") {
        return source.into();
    }
    let Some(version) = source
        .lines()
        .position(|l| l.trim_start().starts_with("#version"))
    else {
        return source.into();
    };
    let mut out = String::with_capacity(source.len() + 64);
    for (i, line) in source.split_inclusive('\n').enumerate() {
        out.push_str(line);
        if i == version {
            if !line.ends_with('\n') {
                out.push('\n');
            }
            // `#line N`: the next line is line N (1-based), as it was.
            out.push_str(&format!(
                "#extension GL_GOOGLE_include_directive : require\n#line {}\n",
                i + 2
            ));
        }
    }
    out.into()
}

/// `input`'s defs as GLSL macros, name and value (a bool is 1 or 0).
pub(crate) fn macros(input: &ShaderInput) -> Vec<(String, String)> {
    input
        .all_defs()
        .into_iter()
        .map(|(name, v)| {
            let value = match v {
                DefValue::Bool(b) => u8::from(b).to_string(),
                v => v.to_string(),
            };
            (name, value)
        })
        .collect()
}

/// Every identifier of `source` and of the files it `#include`s (found beside `path` or in
/// `include_dirs`, followed a few levels down): the words a GLSL macro can be read by.
pub(crate) fn words_read(path: &Path, source: &str, include_dirs: &[PathBuf]) -> BTreeSet<String> {
    let dir = path.parent().unwrap_or(Path::new(".")).to_owned();
    let dirs: Vec<PathBuf> = std::iter::once(dir)
        .chain(include_dirs.iter().cloned())
        .collect();
    let mut words = BTreeSet::new();
    let mut texts = vec![(source.to_owned(), 0)];
    let mut seen = BTreeSet::new();
    while let Some((text, depth)) = texts.pop() {
        for line in text.lines() {
            let included = line.trim_start().strip_prefix("#include").map(|r| r.trim());
            if let Some(name) = included.and_then(|r| r.strip_prefix('"')?.split('"').next())
                && depth < 8
                && seen.insert(name.to_owned())
                && let Some(t) = dirs
                    .iter()
                    .find_map(|d| std::fs::read_to_string(d.join(name)).ok())
            {
                texts.push((t, depth + 1));
            }
        }
        words.extend(
            text.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .filter(|w| !w.is_empty())
                .map(str::to_owned),
        );
    }
    words
}

/// The module with every specialization constant at its default value, and the constant
/// expressions on them folded (`spirv-opt --freeze-spec-const --fold-spec-const-op-composite`):
/// naga's reader takes specialization constants (as overrides) but not `OpSpecConstantOp`.
fn freeze_spec_constants(
    path: &Path,
    source: &str,
    words: &[u32],
) -> Result<Vec<u32>, GlslangError> {
    let unsupported = |what: String| {
        GlslangError::Front(FrontError::Unsupported(SourceDiagnostic::new(
            path.to_owned(),
            source,
            vec![Message::new(format!(
                "unsupported: a specialization constant inside a constant expression ({what})"
            ))],
        )))
    };
    let mut child = Command::new("spirv-opt")
        .args([
            "--freeze-spec-const",
            "--fold-spec-const-op-composite",
            "-",
            "-o",
            "-",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|_| {
            unsupported("freezing it at its default needs spirv-opt: install spirv-tools (scripts/ensure-tools.sh)".into())
        })?;
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let written = {
        use std::io::Write;
        let mut stdin = child.stdin.take().expect("stdin is piped");
        stdin.write_all(&bytes)
    };
    let output = child
        .wait_with_output()
        .map_err(|e| unsupported(format!("spirv-opt failed: {e}")))?;
    if !output.status.success() || written.is_err() || !output.stdout.len().is_multiple_of(4) {
        return Err(unsupported(format!(
            "spirv-opt failed: {}",
            String::from_utf8_lossy(&output.stderr).trim()
        )));
    }
    Ok(output
        .stdout
        .chunks(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

/// glslang's `ERROR: 0:12: 'x' : undeclared identifier` lines as messages at their line.
fn messages(text: &str, source: &str) -> Vec<Message> {
    let lines = line_ranges(source);
    let mut out: Vec<Message> = text
        .lines()
        .filter_map(|l| l.strip_prefix("ERROR: "))
        .filter(|l| !l.contains("compilation errors.  No code generated"))
        .map(|l| {
            // `<string>:<line>: <message>`; the string is 0 (or the file name) for --stdin.
            let mut parts = l.splitn(3, ':');
            let located = match (parts.next(), parts.next(), parts.next()) {
                (Some(_), Some(line), Some(rest)) => {
                    line.trim().parse::<usize>().ok().map(|n| (n, rest.trim()))
                }
                _ => None,
            };
            match located {
                Some((n, rest)) => {
                    let mut m = Message::new(rest.to_owned());
                    if let Some(range) = n.checked_sub(1).and_then(|i| lines.get(i)) {
                        m.labels.push((range.clone(), String::new()));
                    }
                    m
                }
                None => Message::new(l.trim().to_owned()),
            }
        })
        .collect();
    if out.is_empty() {
        // Not a located error (a usage message, a crash): its first line.
        out.push(Message::new(format!(
            "glslang cannot compile this shader: {}",
            text.trim().lines().next().unwrap_or("no message")
        )));
    }
    out
}

/// Each line's text, trimmed of indentation, line end and a final `;`, as byte ranges.
fn line_ranges(source: &str) -> Vec<Range<usize>> {
    let mut ranges = Vec::new();
    let mut start = 0;
    for line in source.split_inclusive('\n') {
        let trimmed_start = line.len() - line.trim_start().len();
        let text = line.trim();
        let text = text.strip_suffix(';').unwrap_or(text).trim_end();
        let from = start + trimmed_start;
        ranges.push(from..from + text.len());
        start += line.len();
    }
    ranges
}

/// SPIR-V byte offsets → GLSL line ranges.
struct LineSpans {
    /// (instruction's bytes, its line's range in the GLSL), sorted.
    instructions: Vec<(Range<usize>, Range<usize>)>,
}

fn line_spans(source: &str, table: &[(Range<usize>, u32)]) -> LineSpans {
    let ranges = line_ranges(source);
    LineSpans {
        instructions: table
            .iter()
            .filter_map(|(bytes, line)| {
                let range = ranges.get((*line as usize).checked_sub(1)?)?;
                Some((bytes.clone(), range.clone()))
            })
            .collect(),
    }
}

impl LineSpans {
    /// The GLSL line of the instruction a span starts in, or no span.
    fn map(&self, span: naga::Span) -> naga::Span {
        let Some(range) = span.to_range() else {
            return naga::Span::default();
        };
        let i = self
            .instructions
            .partition_point(|(bytes, _)| bytes.start <= range.start);
        match i.checked_sub(1).map(|i| &self.instructions[i]) {
            Some((bytes, line)) if bytes.contains(&range.start) => naga::Span::from(line.clone()),
            _ => naga::Span::default(),
        }
    }
}

/// Every span of `module` through `f`.
fn remap_spans(module: &mut naga::Module, f: &dyn Fn(naga::Span) -> naga::Span) {
    fn arena<T>(a: &mut naga::Arena<T>, f: &dyn Fn(naga::Span) -> naga::Span) {
        let mut rebuilt = naga::Arena::new();
        for (_, value, span) in a.drain() {
            rebuilt.append(value, f(span));
        }
        *a = rebuilt;
    }
    fn block(b: &mut naga::Block, f: &dyn Fn(naga::Span) -> naga::Span) {
        for (statement, span) in b.span_iter_mut() {
            if let Some(span) = span {
                *span = f(*span);
            }
            match statement {
                naga::Statement::Block(inner) => block(inner, f),
                naga::Statement::If { accept, reject, .. } => {
                    block(accept, f);
                    block(reject, f);
                }
                naga::Statement::Switch { cases, .. } => {
                    for case in cases {
                        block(&mut case.body, f);
                    }
                }
                naga::Statement::Loop {
                    body, continuing, ..
                } => {
                    block(body, f);
                    block(continuing, f);
                }
                _ => {}
            }
        }
    }
    fn function(fun: &mut naga::Function, f: &dyn Fn(naga::Span) -> naga::Span) {
        arena(&mut fun.expressions, f);
        arena(&mut fun.local_variables, f);
        block(&mut fun.body, f);
    }
    // Types, constants and globals come before any OpLine: they get no span.
    let none = &|_| naga::Span::default();
    let mut types = naga::UniqueArena::new();
    for (_, ty) in module.types.iter() {
        types.insert(ty.clone(), naga::Span::default());
    }
    module.types = types;
    arena(&mut module.constants, none);
    arena(&mut module.overrides, none);
    arena(&mut module.global_variables, none);
    arena(&mut module.global_expressions, none);
    for (_, fun) in module.functions.iter_mut() {
        function(fun, f);
    }
    let mut functions = naga::Arena::new();
    for (_, fun, span) in module.functions.drain() {
        functions.append(fun, f(span));
    }
    module.functions = functions;
    for ep in &mut module.entry_points {
        function(&mut ep.function, f);
    }
}

/// GLSL has no uniformity rule: an implicit derivative (`texture`) in non-uniform control flow has
/// an undefined value there, not a compile error, and Vulkan samples sample shadow maps inside
/// such branches. The module says so as WGSL does, with a global
/// `diagnostic(off, derivative_uniformity)`, which the WGSL written from it keeps (so that `tint`
/// accepts what glslang accepted).
fn allow_nonuniform_derivatives(module: &mut naga::Module) {
    crate::ir::derivative_uniformity_off(module);
}

/// GLSL that glslang compiles and naga 30's SPIR-V reader cannot read: a word of the source, and
/// what to tell the user about it.
const NAGA_GAPS: &[(&str, &str)] = &[
    (
        "subpassInput",
        "an input attachment (`subpassInput`, read with `subpassLoad`): naga 30's SPIR-V reader \
         has no subpass-data images; bind the attachment as a `sampler2D` and read it with \
         `texelFetch`",
    ),
    (
        "gl_ShadingRateEXT",
        "the fragment shading rate (`gl_ShadingRateEXT`, GL_EXT_fragment_shading_rate): naga 30's \
         SPIR-V reader does not take the SPV_KHR_fragment_shading_rate extension",
    ),
];

/// The first construct of [`NAGA_GAPS`] in `source` (a whole word, or its prefix: `subpassInputMS`),
/// with its byte range, when naga has refused glslang's SPIR-V.
fn naga_gap(source: &str) -> Option<(Range<usize>, &'static str)> {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    NAGA_GAPS.iter().find_map(|&(word, what)| {
        source.match_indices(word).find_map(|(at, _)| {
            let before = source[..at].chars().next_back();
            let end = at
                + source[at..]
                    .find(|c: char| !ident(c))
                    .unwrap_or(source.len() - at);
            (!before.is_some_and(ident)).then_some((at..end, what))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::naga_gap;

    #[test]
    fn naga_gaps_are_found_as_words_at_their_place() {
        let source = "layout (input_attachment_index = 0, binding = 0) uniform subpassInput c;";
        let (range, what) = naga_gap(source).unwrap();
        assert_eq!(&source[range], "subpassInput");
        assert!(what.contains("input attachment"), "{what}");
        let ms = "uniform subpassInputMS samples;";
        assert_eq!(&ms[naga_gap(ms).unwrap().0], "subpassInputMS");
        let rate = "void main() { if ((gl_ShadingRateEXT & 1) == 1) { c = vec4(1.0); } }";
        let (range, what) = naga_gap(rate).unwrap();
        assert_eq!(&rate[range], "gl_ShadingRateEXT");
        assert!(what.contains("shading rate"), "{what}");
        // Part of another name is not the construct.
        assert!(naga_gap("float mySubpassInput = 1.0; float xsubpassInput;").is_none());
    }
}
