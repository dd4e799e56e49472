//! WGSL with `#import`s and `#ifdef`s (Bevy's and naga_oil's preprocessor): composed into one
//! module first.
//!
//! Bevy materials start with `#import bevy_pbr::forward_io::VertexOutput` and friends, which no
//! WGSL parser reads. naga_oil (Bevy's composer) resolves them — when it has the modules. reproj
//! looks for them in `.wgsl` files that declare `#define_import_path NAME`, in the shader's folder
//! (and its subfolders), in the import paths given ([`ShaderInput::import_paths`]) and in the
//! folders listed in `REPROJ_WGSL_IMPORTS` (`:`-separated; point it at a checkout of the engine's
//! shader sources, e.g. Bevy's `crates/`); an asset-path import (`#import "shaders/x.wgsl"`) is
//! the file at that path under the first of those folders that has it, registered under the
//! quoted path, as naga_oil names such a module. It adds the modules the shader needs in import
//! order, and composes with the shader defs given ([`ShaderInput::defs`]; naga_oil builds each
//! module with them too). The composed module is written back as WGSL and parsed
//! again, as SPIR-V input is ([`crate::parse`]): spans and node lines then point into that text,
//! whose imported names carry naga_oil's decoration. A module not found is refused at its
//! `#import` line, naming the module and where it was looked for. Feature `compose` (default);
//! without it such a shader is refused at its first `#` line ([`crate::parse::parse_composed`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, ComposerError, ComposerErrorInner, NagaModuleDescriptor,
    ShaderDefValue, ShaderLanguage, ShaderType, get_preprocessor_data,
};

use crate::diagnostic::{Message, SourceDiagnostic};
use crate::directives::HiddenEntry;
use crate::input::{DefValue, InputWarning, ShaderInput};
use crate::shader::FrontError;

/// The environment variable listing further folders of importable modules.
pub const IMPORTS_VAR: &str = "REPROJ_WGSL_IMPORTS";

/// Folders below a search root that are read, at most (a root is not meant to be a whole disk).
const MAX_FILES: usize = 20_000;

pub use crate::directives::needs_composing;

/// A module file found in the search folders.
#[derive(Debug)]
struct Found {
    path: PathBuf,
    source: String,
    imports: Vec<String>,
    /// Registered under its asset path (`"shaders/x.wgsl"`, quotes included, as naga_oil names
    /// a quoted import), not under its `#define_import_path`.
    asset: bool,
}

/// The folders searched for the modules `shader` imports: its own folder, then `import_paths`,
/// then those of [`IMPORTS_VAR`].
fn search_roots(shader: &Path, import_paths: &[PathBuf]) -> Vec<PathBuf> {
    let mut roots = vec![
        shader
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_owned),
    ];
    roots.extend(import_paths.iter().cloned());
    if let Some(list) = std::env::var_os(IMPORTS_VAR) {
        roots.extend(std::env::split_paths(&list).filter(|p| !p.as_os_str().is_empty()));
    }
    roots
}

/// Every `.wgsl` file under `roots` that declares `#define_import_path`, by module name (the
/// first found wins).
fn find_modules(roots: &[PathBuf], shader: &Path) -> BTreeMap<String, Found> {
    let mut modules = BTreeMap::new();
    let mut seen = 0;
    for root in roots {
        let mut dirs = vec![root.clone()];
        while let Some(dir) = dirs.pop() {
            let Ok(entries) = std::fs::read_dir(&dir) else {
                continue;
            };
            let mut entries: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
            entries.sort();
            for path in entries {
                seen += 1;
                if seen > MAX_FILES {
                    return modules;
                }
                if path.is_dir() {
                    dirs.push(path);
                    continue;
                }
                if path.extension().is_none_or(|x| x != "wgsl") || path == shader {
                    continue;
                }
                // Only regular files within the limit: a pipe named `x.wgsl` must not block.
                let Ok(source) = reproj_io::read_input_string(&path, reproj_io::InputKind::Shader)
                else {
                    continue;
                };
                if !source.contains("#define_import_path") {
                    continue;
                }
                let source = crate::enables::enable_binding_arrays(&source).into_owned();
                let (name, imports, _) = get_preprocessor_data(&source);
                if let Some(name) = name {
                    let imports = imports.into_iter().map(|i| i.import).collect();
                    modules.entry(name).or_insert(Found {
                        path,
                        source,
                        imports,
                        asset: false,
                    });
                }
            }
        }
    }
    modules
}

/// Add the asset-path modules (`#import "shaders/x.wgsl"`) that `imports` and the modules found
/// so far name, and those they name in turn: each the first file at that path under a root
/// (Bevy resolves them against its asset folder; here the shader's folder and the import paths).
fn find_asset_modules(
    imports: &[String],
    roots: &[PathBuf],
    modules: &mut BTreeMap<String, Found>,
) {
    let mut todo: Vec<String> = imports
        .iter()
        .chain(modules.values().flat_map(|m| &m.imports))
        .filter(|i| i.starts_with('"'))
        .cloned()
        .collect();
    while let Some(name) = todo.pop() {
        if modules.contains_key(&name) {
            continue;
        }
        let rel = name.trim_matches('"');
        let Some((path, source)) = roots.iter().find_map(|root| {
            let path = root.join(rel);
            reproj_io::read_input_string(&path, reproj_io::InputKind::Shader)
                .ok()
                .map(|s| (path, crate::enables::enable_binding_arrays(&s).into_owned()))
        }) else {
            continue;
        };
        let (_, imports, _) = get_preprocessor_data(&source);
        let imports: Vec<String> = imports.into_iter().map(|i| i.import).collect();
        todo.extend(imports.iter().filter(|i| i.starts_with('"')).cloned());
        modules.insert(
            name,
            Found {
                path,
                source,
                imports,
                asset: true,
            },
        );
    }
}

/// The module an import names: the longest known module name that is the import or a prefix of
/// it at a `::` (`bevy_pbr::forward_io::VertexOutput` imports from `bevy_pbr::forward_io`).
fn module_of<'a>(import: &str, modules: &'a BTreeMap<String, Found>) -> Option<&'a str> {
    modules
        .keys()
        .filter(|m| {
            import == m.as_str()
                || import
                    .strip_prefix(m.as_str())
                    .is_some_and(|rest| rest.starts_with("::"))
        })
        .max_by_key(|m| m.len())
        .map(String::as_str)
}

/// Why a module could not be added.
enum AddError {
    /// naga_oil refused it.
    Composer(Box<ComposerError>),
    /// The modules import each other: the chain, from the first module to the one it came back to.
    Cycle(Vec<String>),
}

/// Add `name` and, first, everything it imports. `chain` is the modules being added around it:
/// meeting one of them again is an import cycle, refused as such (naga_oil would report the
/// module half-added as "not found"). Its defs are not fixed here: naga_oil builds each module
/// with the defs of the shader that imports it ([`NagaModuleDescriptor`]).
fn add_module(
    composer: &mut Composer,
    modules: &BTreeMap<String, Found>,
    name: &str,
    chain: &mut Vec<String>,
) -> Result<(), AddError> {
    if composer.contains_module(name) {
        return Ok(());
    }
    if let Some(at) = chain.iter().position(|m| m == name) {
        let mut cycle = chain[at..].to_vec();
        cycle.push(name.to_owned());
        return Err(AddError::Cycle(cycle));
    }
    chain.push(name.to_owned());
    let found = &modules[name];
    for import in &found.imports {
        if let Some(dep) = module_of(import, modules) {
            add_module(composer, modules, dep, chain)?;
        }
    }
    chain.pop();
    composer
        .add_composable_module(ComposableModuleDescriptor {
            source: &found.source,
            file_path: &found.path.display().to_string(),
            language: ShaderLanguage::Wgsl,
            as_name: found.asset.then(|| name.to_owned()),
            ..Default::default()
        })
        .map_err(|e| AddError::Composer(Box::new(e)))?;
    Ok(())
}

/// An import cycle as a diagnostic at the shader's `#import` of its first module.
fn cycle_error(path: &Path, source: &str, cycle: &[String]) -> FrontError {
    let mut m = Message::new(format!(
        "`#import` cycle: {} (modules that import each other cannot be composed)",
        cycle.join(" imports ")
    ));
    if let Some(first) = cycle.first()
        && let Some(at) = source.find(first.as_str())
    {
        m.labels
            .push((at..at + first.len(), "imported here".into()));
    }
    FrontError::Parse(SourceDiagnostic::new(path.to_owned(), source, vec![m]))
}

/// A composed shader and what composing it found out.
#[derive(Debug)]
pub struct Composed {
    pub module: naga::Module,
    /// The defs given by name that neither the shader nor an imported module reads.
    pub warnings: Vec<InputWarning>,
    /// The shader's `@fragment` entry points that the defs leave out.
    pub hidden: Vec<HiddenEntry>,
}

/// Compose `source` (the shader at `path`) with the modules it imports into one naga module,
/// the modules searched in the shader's folder and those of [`IMPORTS_VAR`].
pub fn compose(path: &Path, source: &str) -> Result<naga::Module, FrontError> {
    compose_with(path, source, &ShaderInput::default()).map(|c| c.module)
}

/// [`compose`] with `input`'s defs, its import paths searched after the shader's folder.
pub fn compose_with(
    path: &Path,
    source: &str,
    input: &ShaderInput,
) -> Result<Composed, FrontError> {
    compose_in(
        path,
        source,
        &search_roots(path, &input.import_paths),
        input,
    )
}

/// [`compose`], the modules searched in `roots` (and their subfolders) only.
pub fn compose_searching(
    path: &Path,
    source: &str,
    roots: &[PathBuf],
) -> Result<naga::Module, FrontError> {
    compose_in(path, source, roots, &ShaderInput::default()).map(|c| c.module)
}

/// Compose with the modules under `roots` and `input`'s defs (its import paths are in `roots`).
fn compose_in(
    path: &Path,
    source: &str,
    roots: &[PathBuf],
    input: &ShaderInput,
) -> Result<Composed, FrontError> {
    let source = &*crate::enables::enable_binding_arrays(source);
    let mut modules = find_modules(roots, path);
    let (_, imports, _) = get_preprocessor_data(source);
    let imports: Vec<String> = imports.into_iter().map(|i| i.import).collect();
    find_asset_modules(&imports, roots, &mut modules);
    let mut composer = Composer::default().with_capabilities(naga::valid::Capabilities::all());
    for import in &imports {
        let Some(module) = module_of(import, &modules) else {
            continue;
        };
        match add_module(&mut composer, &modules, module, &mut Vec::new()) {
            Ok(()) => {}
            Err(AddError::Composer(e)) => {
                return Err(composer_error(path, source, roots, &composer, &e));
            }
            Err(AddError::Cycle(cycle)) => return Err(cycle_error(path, source, &cycle)),
        }
    }
    let defs = input.all_defs();
    let module = composer
        .make_naga_module(NagaModuleDescriptor {
            source,
            file_path: &path.display().to_string(),
            shader_type: ShaderType::Wgsl,
            shader_defs: defs
                .iter()
                .map(|(n, v)| (n.clone(), naga_oil_value(*v)))
                .collect(),
            ..Default::default()
        })
        .map_err(|e| composer_error(path, source, roots, &composer, &e))?;
    let mut read = crate::directives::read_defs(source);
    for name in composer.module_sets.keys() {
        if let Some(found) = modules.get(name) {
            read.extend(crate::directives::read_defs(&found.source));
        }
    }
    Ok(Composed {
        module,
        warnings: crate::input::unread_defs(path, input, &read),
        hidden: crate::directives::hidden_fragments(source, &defs),
    })
}

/// naga_oil's spelling of a def's value.
fn naga_oil_value(v: DefValue) -> ShaderDefValue {
    match v {
        DefValue::Bool(b) => ShaderDefValue::Bool(b),
        DefValue::Int(i) => ShaderDefValue::Int(i),
        DefValue::UInt(u) => ShaderDefValue::UInt(u),
    }
}

/// naga_oil's error as a front-end diagnostic: a missing module at its `#import`, with where it
/// was looked for; anything else with naga_oil's own rendering as a note.
fn composer_error(
    path: &Path,
    source: &str,
    roots: &[PathBuf],
    composer: &Composer,
    e: &ComposerError,
) -> FrontError {
    let places = roots
        .iter()
        .map(|r| r.display().to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let message = match &e.inner {
        ComposerErrorInner::ImportNotFound(name, _) => {
            let mut m = Message::new(if name.starts_with('"') {
                format!(
                    "`#import {name}`: no module {name} was found (the file at that path under a searched folder)"
                )
            } else {
                format!(
                    "`#import {name}`: no module `{name}` was found (a .wgsl file declaring `#define_import_path` for it)"
                )
            });
            // The import's line in the shader itself, where it is there.
            if let Some(at) = source.find(name.as_str()) {
                m.labels.push((at..at + name.len(), "imported here".into()));
            }
            m.notes.push(format!(
                "searched: {places}; add the folder holding the module's source with `-I DIR` or to {IMPORTS_VAR} (`:`-separated), e.g. a checkout of the engine's shader sources (Bevy's modules are in its crates: bevy_pbr, bevy_render, ...)"
            ));
            m
        }
        ComposerErrorInner::UnknownShaderDef {
            shader_def_name: name,
            ..
        } => {
            let mut m = Message::new(format!(
                "`#if {name} …` compares shader def `{name}`, which is not defined: define it (`--def {name}=VALUE`)"
            ));
            // The comparison's line in the shader itself, where it is there (naga_oil's rendering
            // below says where it is in a module).
            if let Some(range) = crate::directives::comparison_of(source, name) {
                m.labels.push((range, "compared here".into()));
            }
            m.notes.push(e.emit_to_string(composer));
            m
        }
        _ => {
            let mut m = Message::new(format!(
                "composing the shader's imports failed: {}",
                e.inner
            ));
            m.notes.push(e.emit_to_string(composer));
            m
        }
    };
    FrontError::Parse(SourceDiagnostic::new(
        path.to_owned(),
        source,
        vec![message],
    ))
}
