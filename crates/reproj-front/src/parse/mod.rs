//! Parsing, validation and entry-point choice, for the three input languages.
//!
//! WGSL and GLSL (fragment stage) keep their own text as the source that diagnostics and node
//! positions point into. GLSL is compiled by glslang ([`crate::glslang`]); naga's GLSL front end
//! reads it only where glslang is not installed. SPIR-V has no text: its module is written out as
//! WGSL by naga and parsed again, so that every span points into that WGSL.

use std::path::Path;

use crate::diagnostic::{self, Message, SourceDiagnostic};
pub use crate::directives::needs_composing;
use crate::input::ShaderInput;
pub use crate::shader::{FrontError, Lang, Shader, validator};

use naga::valid::ModuleInfo;

mod shader;

/// Refuse a file whose extension names a GLSL stage other than the fragment one: read as WGSL
/// it would fail with a syntax error that never says why.
pub(crate) fn refuse_other_stage(path: &Path) -> Result<(), FrontError> {
    let Some(ext) = path.extension().and_then(|e| e.to_str()) else {
        return Ok(());
    };
    let stage = match ext.to_ascii_lowercase().as_str() {
        "vert" => "vertex",
        "comp" => "compute",
        "geom" => "geometry",
        "tesc" => "tessellation control",
        "tese" => "tessellation evaluation",
        "mesh" => "mesh",
        "task" => "task",
        _ => return Ok(()),
    };
    Err(FrontError::NotFragmentStage {
        path: path.to_owned(),
        ext: ext.to_owned(),
        stage,
    })
}

/// WGSL with `#import`s (`crate::compose`, feature `compose`): composed with naga_oil, validated, and its WGSL made
/// the source text, as for SPIR-V.
#[cfg(feature = "compose")]
pub fn parse_composed(path: &Path, source: &str) -> Result<Shader, FrontError> {
    parse_composed_with(path, source, &ShaderInput::default())
}

/// [`parse_composed`] with `input`'s defs and import paths; what composing found (defs nobody
/// reads, entry points the defs leave out) kept with the shader.
#[cfg(feature = "compose")]
pub fn parse_composed_with(
    path: &Path,
    source: &str,
    input: &ShaderInput,
) -> Result<Shader, FrontError> {
    let composed = crate::compose::compose_with(path, source, input)?;
    let shader = reparse_as_wgsl(path, &composed.module, "composed")?;
    Ok(Shader {
        warnings: composed.warnings,
        hidden_entries: composed.hidden,
        ..shader
    })
}

/// Without the `compose` feature: refused at the first preprocessor line ([`parse_composed`]).
#[cfg(not(feature = "compose"))]
pub fn parse_composed_with(
    path: &Path,
    source: &str,
    _input: &ShaderInput,
) -> Result<Shader, FrontError> {
    parse_composed(path, source)
}

/// Without the `compose` feature (the light build): refused at the first preprocessor line.
#[cfg(not(feature = "compose"))]
pub fn parse_composed(path: &Path, source: &str) -> Result<Shader, FrontError> {
    let mut m = crate::Message::new(
        "the shader uses naga_oil's preprocessor (`#import`, `#define_import_path`, `#ifdef`...), \
         and this reproj was built without it (the `compose` feature of reproj-cli, on by default; \
         the light build leaves it out)",
    );
    let mut at = 0;
    for line in source.split_inclusive('\n') {
        let trimmed = line.trim_start();
        if trimmed.starts_with('#') {
            let start = at + (line.len() - trimmed.len());
            m.labels.push((
                start..start + trimmed.trim_end().len(),
                "preprocessor line".into(),
            ));
            break;
        }
        at += line.len();
    }
    Err(FrontError::Unsupported(crate::SourceDiagnostic::new(
        path.to_owned(),
        source,
        vec![m],
    )))
}

/// A module read from another form (SPIR-V, composed WGSL), validated and written as WGSL, which
/// is then parsed as the shader's source text (its spans point there). `what` names the form in
/// messages. Its spans are not into any text the user has: errors are reported without them.
fn reparse_as_wgsl(path: &Path, module: &naga::Module, what: &str) -> Result<Shader, FrontError> {
    let info = validator().validate(module).map_err(|e| {
        FrontError::Validation(SourceDiagnostic::new(
            path.to_owned(),
            "",
            vec![Message::new(format!(
                "the {what} module is not valid: {}",
                chain(&e)
            ))],
        ))
    })?;
    let wgsl = write_wgsl(module, &info).map_err(|why| {
        FrontError::Unsupported(SourceDiagnostic::new(
            path.to_owned(),
            "",
            vec![Message::new(format!("unsupported: {why}"))],
        ))
    })?;
    // A chain too long to read again is the module's, not a bug: said without the written text.
    if crate::depth::check_chains(path, &wgsl).is_err() {
        return Err(FrontError::Unsupported(SourceDiagnostic::new(
            path.to_owned(),
            "",
            vec![Message::new(format!(
                "unsupported: the {what} module holds a chain of more than {} operations in one expression: split it into shorter ones",
                crate::depth::MAX_EXPRESSION_DEPTH
            ))],
        )));
    }
    parse_text(path, Lang::Wgsl, wgsl).map_err(|e| FrontError::Internal {
        what: format!(
            "naga's WGSL of the {what} module {} does not parse again: {e}",
            path.display()
        ),
    })
}

/// Parse WGSL text and validate the module. Errors carry naga's rendered diagnostic.
pub fn parse_shader(path: &Path, source: String) -> Result<Shader, FrontError> {
    parse_text(path, Lang::Wgsl, source)
}

/// Compile GLSL fragment-shader text with glslang ([`crate::glslang`]) and validate the module;
/// where glslang is not installed, naga's GLSL front end reads it.
pub fn parse_glsl(path: &Path, source: String) -> Result<Shader, FrontError> {
    parse_glsl_with(path, source, &ShaderInput::default())
}

/// [`parse_glsl`] with `input`'s defs as macros and its include folders searched; a def that no
/// word of the shader or of the files it includes names is a warning.
pub fn parse_glsl_with(
    path: &Path,
    source: String,
    input: &ShaderInput,
) -> Result<Shader, FrontError> {
    let read = crate::glslang::words_read(path, &source, &input.include_dirs);
    let warnings = crate::input::unread_defs(path, input, &read);
    let shader = match crate::glslang::parse(path, source.clone(), input) {
        Ok(shader) => shader,
        Err(crate::glslang::GlslangError::Front(e)) => return Err(e),
        Err(crate::glslang::GlslangError::Missing) => parse_naga_glsl(path, source, input)?,
    };
    Ok(Shader { warnings, ..shader })
}

/// naga's GLSL front end, where glslang is missing: `input`'s defs as its macros, no includes.
fn parse_naga_glsl(path: &Path, source: String, input: &ShaderInput) -> Result<Shader, FrontError> {
    let macros = crate::glslang::macros(input);
    parse_text_defined(path, Lang::Glsl, source, &macros).map_err(|e| match e {
        FrontError::Parse(mut d) => {
            for m in &mut d.messages {
                m.notes.push(missing_glslang_note(&m.text));
            }
            FrontError::Parse(d)
        }
        e => e,
    })
}

/// What a naga GLSL parse error needs, said when glslang is missing.
fn missing_glslang_note(text: &str) -> String {
    let feature = if text.contains("variable qualifier") {
        "combined image samplers (sampler2D, samplerCube, ...) and layout(offset = N) need glslang"
    } else {
        "naga's GLSL front end reads less GLSL than glslang"
    };
    format!(
        "{feature}: `{}` was not found (install glslang-tools: scripts/ensure-tools.sh), so naga's GLSL front end read this file",
        crate::glslang::glslang_program()
    )
}

/// Parse a SPIR-V binary (naga's SPIR-V front end), validate it, and make its WGSL the source
/// text (see the module docs).
pub fn parse_spirv(path: &Path, bytes: &[u8]) -> Result<Shader, FrontError> {
    let options = naga::front::spv::Options {
        adjust_coordinate_space: false,
        strict_capabilities: false,
        block_ctx_dump_prefix: None,
    };
    let module = naga::front::spv::parse_u8_slice(bytes, &options).map_err(|e| {
        FrontError::Parse(SourceDiagnostic::new(
            path.to_owned(),
            "",
            vec![Message::new(format!("invalid SPIR-V: {e}"))],
        ))
    })?;
    // Spans of a SPIR-V module are byte offsets into the binary: report errors without them.
    let shader = reparse_as_wgsl(path, &module, "SPIR-V")?;
    Ok(Shader {
        lang: Lang::SpirV,
        ..shader
    })
}

/// An error and its sources, `: `-separated.
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(inner) = source {
        s.push_str(": ");
        s.push_str(&inner.to_string());
        source = inner.source();
    }
    s
}

/// `module` as WGSL text ([`crate::write_wgsl`], the one writer), for the languages that are
/// not WGSL.
fn write_wgsl(module: &naga::Module, info: &ModuleInfo) -> Result<String, String> {
    crate::write_wgsl(module, info)
        .map_err(|e| format!("naga cannot write this module as WGSL ({e})"))
}

pub(crate) fn parse_text(path: &Path, lang: Lang, source: String) -> Result<Shader, FrontError> {
    parse_text_defined(path, lang, source, &[])
}

/// [`parse_text`], GLSL with these macros defined.
fn parse_text_defined(
    path: &Path,
    lang: Lang,
    source: String,
    macros: &[(String, String)],
) -> Result<Shader, FrontError> {
    // naga lowers expressions recursively: a chain too long for the stack is refused first.
    crate::depth::check_chains(path, &source)?;
    let path_str = path.display().to_string();
    let mut glsl_options = naga::front::glsl::Options::from(naga::ShaderStage::Fragment);
    glsl_options.defines.extend(macros.iter().cloned());
    let module = match lang {
        Lang::Glsl => naga::front::glsl::Frontend::default()
            .parse(&glsl_options, &source)
            .map_err(|e| {
                FrontError::Parse(SourceDiagnostic::new(
                    path.to_owned(),
                    &source,
                    diagnostic::from_glsl(&e),
                ))
            })?,
        _ => naga::front::wgsl::parse_str(&source).map_err(|e| {
            FrontError::Parse(SourceDiagnostic::new(
                path.to_owned(),
                &source,
                diagnostic::from_wgsl(&e, &source),
            ))
        })?,
    };
    let mut module = module;
    let (warnings, filled_in) = match lang {
        Lang::Wgsl => crate::fill_in::fill_in(path, &mut module),
        _ => (Vec::new(), false),
    };
    let info = validator().validate(&module).map_err(|e| {
        // naga gives some errors (a whole entry point's) no span: name the place ourselves.
        let at = (!e.spans().any(|(span, _)| span.to_range().is_some()))
            .then(|| unspanned_location(&e, &module, &source, &path_str));
        FrontError::Validation(SourceDiagnostic::new(
            path.to_owned(),
            &source,
            diagnostic::from_validation(&e, at),
        ))
    })?;
    Ok(Shader {
        path: path.to_owned(),
        lang,
        source,
        module,
        info,
        split_samplers: Vec::new(),
        warnings,
        hidden_entries: Vec::new(),
        wgsl_form: false,
        filled_in,
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
            format!("{path}:{line}:{col}")
        }
        None => path.to_owned(),
    }
}

#[cfg(all(test, not(feature = "compose")))]
mod absent_compose_tests {
    use std::path::Path;

    use super::{FrontError, parse_composed};

    #[test]
    fn absent_compose_refuses_an_import_at_its_line() {
        let source = "// a material\n  #import bevy_pbr::forward_io::VertexOutput\n@fragment\nfn main() {}\n";
        let Err(FrontError::Unsupported(d)) = parse_composed(Path::new("m.wgsl"), source) else {
            panic!("expected a refusal");
        };
        let text = d.render();
        assert!(text.contains("`compose` feature"), "{text}");
        assert!(d.location().starts_with("m.wgsl:2"), "{}", d.location());
    }
}
