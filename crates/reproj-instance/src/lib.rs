//! The reproj instancer.
//!
//! Turns a shader and one cacheable node into a *variant*: the fragment modules of one
//! [`Strategy`] and a manifest that tells a host how to run them (see `docs/PASSES.md`). The paper's
//! three passes (reproject, recompute, shade): pass 1 is the lookup library (`lookup.wgsl`) plus a
//! small entry; passes 2 and 3 are the normalized shader rebuilt in order — sliced after the node,
//! or with the node read from the cache. The fused and two-pass strategies put the same pieces in
//! one module as functions ([`strategy`]). Every module is stripped of dead code, validated,
//! compacted, validated again and written as WGSL that survives a round trip.

use std::path::Path;

use naga::{Handle, Module};
use reproj_front::rebuild::{CacheRead, CacheSource, Rewrite, Slot, StopAfter, rebuild_live};
use reproj_front::{Node, NodeTable, Normalized, Shader, validator};

pub mod backends;
pub mod import;
pub mod manifest;
mod simplify;
mod strategy;

pub mod contract;

pub use manifest::*;
pub use simplify::{Replacement, Simplified, SimplifyOptions, probe, simplify};

/// The lookup library; `REPROJ_GROUP`, `REPROJ_PREV_CLIP` and `REPROJ_RECONSTRUCT` are substituted.
const LOOKUP_LIBRARY: &str = include_str!("lookup.wgsl");
/// The three-pass strategy's pass-1 entry, appended to the library.
const REPROJECT_ENTRY: &str = include_str!("reproject.wgsl");

pub use contract::MAX_BIND_GROUPS;
use contract::ReprojParams;
use std::mem::offset_of;

/// Which node to cache.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeSelector {
    Id(u32),
    Root,
}

impl std::str::FromStr for NodeSelector {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "root" {
            Ok(NodeSelector::Root)
        } else {
            s.parse().map(NodeSelector::Id).map_err(|_| {
                format!("`{s}` is not a node id (a number from `reproj nodes`) or `root`")
            })
        }
    }
}

/// Which payload format a variant uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CacheFormatChoice {
    /// The narrowest 32-bit float format that holds the node (exact).
    #[default]
    Narrowest32,
    /// The narrowest 16-bit float format that holds the node (the paper's precision).
    Narrowest16,
    /// This format (it must hold the node's components).
    Exact(CacheFormat),
}

impl CacheFormatChoice {
    /// The format for a node of `components` floats.
    pub fn resolve(self, components: u32) -> CacheFormat {
        match self {
            CacheFormatChoice::Narrowest32 => CacheFormat::narrowest(components, false),
            CacheFormatChoice::Narrowest16 => CacheFormat::narrowest(components, true),
            CacheFormatChoice::Exact(f) => f,
        }
    }
}

/// Options of [`instance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InstanceOptions {
    pub strategy: Strategy,
    pub reconstruct: Reconstruct,
    pub cache_format: CacheFormatChoice,
    /// Default refresh period written to the manifest (the modules take it at run time).
    pub delta_n: u32,
    /// Refresh block size k (1, or even so blocks align with 2×2 quads).
    pub block: u32,
    /// Relative depth tolerance of the hit test.
    pub depth_epsilon: f32,
    /// Bind group of the added bindings (`None`: the lowest one the shader does not use).
    pub group: Option<u32>,
    /// How the first pass that writes the frame color starts it.
    pub frame_load: FrameLoad,
}

/// How the variant's first frame-color write starts the frame target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrameLoad {
    /// Clear it to the host's clear color, as a standalone pass of the original shader would.
    #[default]
    Clear,
    /// Keep what the engine drew before (its other passes, a sky): the variant's passes only
    /// write the pixels of their geometry.
    Load,
}

impl Default for InstanceOptions {
    fn default() -> Self {
        InstanceOptions {
            strategy: Strategy::ThreePass,
            reconstruct: Reconstruct::Bilinear,
            cache_format: CacheFormatChoice::Narrowest32,
            delta_n: 8,
            block: 4,
            depth_epsilon: 0.01,
            group: None,
            frame_load: FrameLoad::Clear,
        }
    }
}

/// One generated pass.
#[derive(Debug, Clone)]
pub struct PassModule {
    pub kind: PassKind,
    pub module: Module,
    pub info: naga::valid::ModuleInfo,
    /// WGSL text: a fixed point of parse → validate → write.
    pub wgsl: String,
}

/// A cached variant: its passes (in draw order) and the manifest.
#[derive(Debug, Clone)]
pub struct Variant {
    pub manifest: Manifest,
    pub passes: Vec<PassModule>,
}

/// What can go wrong while instancing.
#[derive(Debug, thiserror::Error)]
pub enum InstanceError {
    #[error(
        "no node {id}: {shader} has node ids {min}..={max} (see `reproj nodes {shader} --all`)"
    )]
    UnknownNode {
        id: u32,
        shader: String,
        min: u32,
        max: u32,
    },
    #[error("node {id} (`{text}`, line {line}) cannot be cached: it is culled as {reason}")]
    Culled {
        id: u32,
        text: String,
        line: u32,
        reason: reproj_front::CullReason,
    },
    #[error(
        "the shader already uses every bind group slot (groups {used:?}); the variant needs a free group below {MAX_BIND_GROUPS}"
    )]
    NoFreeGroup { used: Vec<u32> },
    #[error(
        "bind group {group} cannot hold the variant's bindings: the shader uses groups {used:?} and a group must be below {MAX_BIND_GROUPS}"
    )]
    GroupTaken { group: u32, used: Vec<u32> },
    #[error("the block size k must be 1 or even (to align with 2×2 quads), got {0}")]
    BadBlock(u32),
    #[error("the refresh period must be at least 1")]
    BadDeltaN,
    #[error(
        "nodes {ids} hold {components} floats together: a payload holds 4 (cache nodes of fewer components together)"
    )]
    PayloadTooWide { ids: String, components: u32 },
    #[error("node {id} is listed twice")]
    RepeatedNode { id: String },
    #[error("the {format} cache holds {channels} float(s) but node {id} has {components}")]
    FormatTooNarrow {
        format: &'static str,
        channels: u32,
        id: String,
        components: u32,
    },
    #[error(transparent)]
    Write(#[from] reproj_io::WriteError),
    /// A naga backend could not write a pass in another language.
    #[error("cannot write {file}: {what}")]
    Backend { file: String, what: String },
    #[error(transparent)]
    Front(#[from] reproj_front::FrontError),
    /// A node cannot be replaced by a constant (code simplification).
    #[error("node {id} (`{text}`) cannot be replaced by a constant: {why}")]
    NotReplaceable { id: u32, text: String, why: String },
    /// A bug in reproj: a simplified shader did not validate or round-trip.
    #[error("internal error in a simplified shader: {what}")]
    InternalSimplified { what: String },
    /// A bug in reproj: a generated module did not validate or round-trip.
    #[error("internal error in the {pass:?} pass: {what}")]
    Internal { pass: PassKind, what: String },
}

impl InstanceError {
    /// True when the error comes from the user's input or the machine (exit code 2), false for a
    /// bug in reproj.
    pub fn is_user_error(&self) -> bool {
        match self {
            InstanceError::Internal { .. } | InstanceError::InternalSimplified { .. } => false,
            InstanceError::Front(f) => f.is_user_error(),
            _ => true,
        }
    }

    /// The source diagnostic of a front-end error about a place in the shader.
    pub fn diagnostic(&self) -> Option<&reproj_front::SourceDiagnostic> {
        match self {
            InstanceError::Front(f) => f.diagnostic(),
            _ => None,
        }
    }
}

/// Build the variant of `shader` that caches `node`.
pub fn instance(
    shader: &Shader,
    norm: &Normalized,
    table: &NodeTable,
    node: NodeSelector,
    opts: &InstanceOptions,
) -> Result<Variant, InstanceError> {
    instance_nodes(shader, norm, table, &[node], opts)
}

/// Build the variant of `shader` that caches `nodes` together: their floats packed one after the
/// other, in the order given, in one payload texture (at most 4 floats in all).
pub fn instance_nodes(
    shader: &Shader,
    norm: &Normalized,
    table: &NodeTable,
    nodes: &[NodeSelector],
    opts: &InstanceOptions,
) -> Result<Variant, InstanceError> {
    if opts.block != 1 && !opts.block.is_multiple_of(2) || opts.block == 0 {
        return Err(InstanceError::BadBlock(opts.block));
    }
    if opts.delta_n == 0 {
        return Err(InstanceError::BadDeltaN);
    }
    let picked = nodes
        .iter()
        .map(|&n| pick(table, n))
        .collect::<Result<Vec<&Node>, _>>()?;
    for (i, n) in picked.iter().enumerate() {
        if picked[..i].iter().any(|m| m.id == n.id) {
            return Err(InstanceError::RepeatedNode { id: node_id(n) });
        }
    }
    let components: u32 = picked.iter().map(|n| n.components).sum();
    if components > 4 {
        return Err(InstanceError::PayloadTooWide {
            ids: picked
                .iter()
                .map(|n| node_id(n))
                .collect::<Vec<_>>()
                .join(", "),
            components,
        });
    }
    let slots = Slot::pack(
        &picked
            .iter()
            .map(|n| {
                let target = n.handle.expect("nodes from enumerate carry their handle");
                (target, n.components)
            })
            .collect::<Vec<_>>(),
    );
    let group = match opts.group {
        None => free_group(&shader.module)?,
        Some(g) => {
            let used = used_groups(&shader.module);
            if g >= MAX_BIND_GROUPS || used.contains(&g) {
                return Err(InstanceError::GroupTaken { group: g, used });
            }
            g
        }
    };
    let prev_clip_location = prev_clip_location(&norm.module);
    let cache_format = opts.cache_format.resolve(components);
    if cache_format.channels() < components {
        return Err(InstanceError::FormatTooNarrow {
            format: cache_format.name(),
            channels: cache_format.channels(),
            id: picked
                .iter()
                .map(|n| node_id(n))
                .collect::<Vec<_>>()
                .join("+"),
            components,
        });
    }
    let library = library_text(group, prev_clip_location, opts.reconstruct);
    let passes = match opts.strategy {
        Strategy::ThreePass => vec![
            reproject_pass(&library)?,
            recompute_pass(norm, &slots)?,
            shade_pass(norm, &slots, group)?,
        ],
        Strategy::Fused | Strategy::TwoPass => {
            strategy_passes(norm, &slots, &library, opts.strategy, prev_clip_location)?
        }
    };
    let manifest = build_manifest(
        shader,
        norm,
        &picked,
        opts,
        cache_format,
        group,
        prev_clip_location,
        &passes,
    );
    Ok(Variant { manifest, passes })
}

/// A node's id as the CLI and the manifest spell it.
fn node_id(node: &Node) -> String {
    if node.root {
        "root".into()
    } else {
        node.id.to_string()
    }
}

fn pick(table: &NodeTable, sel: NodeSelector) -> Result<&Node, InstanceError> {
    let node = match sel {
        NodeSelector::Root => table.root(),
        NodeSelector::Id(id) => table.get(id).ok_or_else(|| InstanceError::UnknownNode {
            id,
            shader: table.shader.clone(),
            min: table.nodes.first().map_or(0, |n| n.id),
            max: table.nodes.last().map_or(0, |n| n.id),
        })?,
    };
    match node.reason {
        Some(reason) => Err(InstanceError::Culled {
            id: node.id,
            text: node.text.clone(),
            line: node.line,
            reason,
        }),
        None => Ok(node),
    }
}

/// The bind groups the shader uses, ascending.
fn used_groups(module: &Module) -> Vec<u32> {
    let mut used: Vec<u32> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| g.binding.as_ref().map(|b| b.group))
        .collect();
    used.sort_unstable();
    used.dedup();
    used
}

/// The lowest bind group index the shader does not use.
pub fn free_group(module: &Module) -> Result<u32, InstanceError> {
    let used = used_groups(module);
    (0..MAX_BIND_GROUPS)
        .find(|g| !used.contains(g))
        .ok_or(InstanceError::NoFreeGroup { used })
}

/// One past the highest `@location` the entry point reads.
fn prev_clip_location(module: &Module) -> u32 {
    let fun = &module.entry_points[0].function;
    let mut max: Option<u32> = None;
    let mut see = |b: &Option<naga::Binding>| {
        if let Some(naga::Binding::Location { location, .. }) = b {
            max = Some(max.map_or(*location, |m: u32| m.max(*location)));
        }
    };
    for arg in &fun.arguments {
        see(&arg.binding);
        if let naga::TypeInner::Struct { members, .. } = &module.types[arg.ty].inner {
            for m in members {
                see(&m.binding);
            }
        }
    }
    max.map_or(0, |m| m + 1)
}

/// The lookup library's WGSL for this group, input location and reconstruction.
fn library_text(group: u32, location: u32, reconstruct: Reconstruct) -> String {
    let fetch = match reconstruct {
        Reconstruct::Bilinear => {
            "textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, uv, 0.0)"
        }
        Reconstruct::Nearest => {
            "textureLoad(reproj_prev_payload, vec2<i32>(min(uv * size, size - vec2<f32>(1.0))), 0)"
        }
    };
    LOOKUP_LIBRARY
        .replace("REPROJ_GROUP", &group.to_string())
        .replace("REPROJ_PREV_CLIP", &location.to_string())
        .replace("REPROJ_RECONSTRUCT", fetch)
}

fn parse_library(text: &str, pass: PassKind) -> Result<Module, InstanceError> {
    naga::front::wgsl::parse_str(text).map_err(|e| InstanceError::Internal {
        pass,
        what: e.emit_to_string(text),
    })
}

fn reproject_pass(library: &str) -> Result<PassModule, InstanceError> {
    let text = format!("{library}{REPROJECT_ENTRY}");
    finish(
        PassKind::Reproject,
        parse_library(&text, PassKind::Reproject)?,
    )
}

/// The passes of the fused and two-pass strategies (see [`strategy`]).
fn strategy_passes(
    norm: &Normalized,
    slots: &[Slot],
    library: &str,
    which: Strategy,
    prev_clip_location: u32,
) -> Result<Vec<PassModule>, InstanceError> {
    let kinds = strategy::entries(which);
    let first = strategy::pass_kind(kinds[0]);
    let mut base = norm.module.clone();
    let (recompute, vec4) = recompute_slice(norm, &mut base, slots, first)?;
    let entry = norm.function().clone();
    let payload_arg = entry.arguments.len() as u32;
    let mut shade = rebuild_entry(
        norm,
        &base,
        &Rewrite::CacheRead(CacheRead {
            slots: slots.to_vec(),
            source: CacheSource::Argument(payload_arg),
        }),
        first,
    )?;
    shade.arguments = entry.arguments.clone();
    shade.arguments.push(naga::FunctionArgument {
        name: Some("reproj_payload".into()),
        ty: vec4,
        binding: None,
    });
    let result = entry
        .result
        .clone()
        .ok_or_else(|| InstanceError::Internal {
            pass: first,
            what: "the entry point returns nothing".into(),
        })?;
    let recompute = base.functions.append(
        strategy::as_function(recompute, "reproj_recompute"),
        naga::Span::UNDEFINED,
    );
    let shade = base.functions.append(
        strategy::as_function(shade, "reproj_shade"),
        naga::Span::UNDEFINED,
    );
    let output = strategy::output_struct(&mut base, &result, Some(vec4));
    let original_ep = base.entry_points[0].clone();
    let mut passes = Vec::new();
    for &kind in kinds {
        let pass = strategy::pass_kind(kind);
        let mut module = base.clone();
        module.entry_points.clear();
        let fetch = if strategy::needs_fetch(kind) {
            let lib = parse_library(library, pass)?;
            let imported = import::import_module(&mut module, &lib)
                .map_err(|what| InstanceError::Internal { pass, what })?;
            imported.functions.get("reproj_fetch").copied()
        } else {
            None
        };
        let parts = strategy::Parts {
            vec4,
            recompute: Some(recompute),
            shade,
            fetch,
            output,
        };
        let function = strategy::build_entry(&module, &entry, &parts, kind, prev_clip_location)?;
        if kind == strategy::EntryKind::Fused {
            allow_quad_uniform_derivatives(&mut module);
        }
        module.entry_points.insert(
            0,
            naga::EntryPoint {
                function,
                ..original_ep.clone()
            },
        );
        passes.push(finish(pass, module)?);
    }
    Ok(passes)
}

/// The slice of the entry point that computes the node and returns it as a `vec4<f32>`
/// (zero-padded), with that `vec4<f32>` type, added to `module` if it was missing.
fn recompute_slice(
    norm: &Normalized,
    module: &mut Module,
    slots: &[Slot],
    pass: PassKind,
) -> Result<(naga::Function, Handle<naga::Type>), InstanceError> {
    let vec4 = vec_type(module, naga::VectorSize::Quad, naga::Scalar::F32);
    let fun = rebuild_entry(
        norm,
        module,
        &Rewrite::StopAfter(StopAfter {
            slots: slots.to_vec(),
            vec4,
        }),
        pass,
    )?;
    Ok((fun, vec4))
}

/// The normalized entry point rewritten by `rewrite`, with its dead code removed.
fn rebuild_entry(
    norm: &Normalized,
    module: &Module,
    rewrite: &Rewrite,
    pass: PassKind,
) -> Result<naga::Function, InstanceError> {
    rebuild_live(module, norm.function(), rewrite)
        .map(|r| r.function)
        .map_err(|e| InstanceError::Internal {
            pass,
            what: e.to_string(),
        })
}

fn vec_type(
    module: &mut Module,
    size: naga::VectorSize,
    scalar: naga::Scalar,
) -> Handle<naga::Type> {
    module.types.insert(
        naga::Type {
            name: None,
            inner: naga::TypeInner::Vector { size, scalar },
        },
        naga::Span::UNDEFINED,
    )
}

fn recompute_pass(norm: &Normalized, slots: &[Slot]) -> Result<PassModule, InstanceError> {
    let mut module = norm.module.clone();
    let (fun, _) = recompute_slice(norm, &mut module, slots, PassKind::Recompute)?;
    module.entry_points[0].function = fun;
    finish(PassKind::Recompute, module)
}

fn shade_pass(norm: &Normalized, slots: &[Slot], group: u32) -> Result<PassModule, InstanceError> {
    let mut module = norm.module.clone();
    let vec4f = vec_type(&mut module, naga::VectorSize::Quad, naga::Scalar::F32);
    let image_ty = module.types.insert(
        naga::Type {
            name: None,
            inner: naga::TypeInner::Image {
                dim: naga::ImageDimension::D2,
                arrayed: false,
                class: naga::ImageClass::Sampled {
                    kind: naga::ScalarKind::Float,
                    multi: false,
                },
            },
        },
        naga::Span::UNDEFINED,
    );
    let image = module.global_variables.append(
        naga::GlobalVariable {
            name: Some(contract::CUR_PAYLOAD.into()),
            space: naga::AddressSpace::Handle,
            binding: Some(naga::ResourceBinding {
                group,
                binding: contract::CUR_PAYLOAD_BINDING,
            }),
            ty: image_ty,
            init: None,
            memory_decorations: Default::default(),
        },
        naga::Span::UNDEFINED,
    );
    let position = find_or_add_position(&mut module, vec4f);
    let fun = rebuild_entry(
        norm,
        &module,
        &Rewrite::CacheRead(CacheRead {
            slots: slots.to_vec(),
            source: CacheSource::Texture { image, position },
        }),
        PassKind::Shade,
    )?;
    // The shader's entry, reading the node from the cache, becomes `reproj_shade`; a small entry
    // calls it and adds the depth copy to its outputs (see [`strategy`]).
    let entry = naga::Function {
        arguments: module.entry_points[0].function.arguments.clone(),
        ..fun
    };
    let result = entry
        .result
        .clone()
        .ok_or_else(|| InstanceError::Internal {
            pass: PassKind::Shade,
            what: "the entry point returns nothing".into(),
        })?;
    let shade = module.functions.append(
        strategy::as_function(entry.clone(), "reproj_shade"),
        naga::Span::UNDEFINED,
    );
    let output = strategy::output_struct(&mut module, &result, None);
    let parts = strategy::Parts {
        vec4: vec4f,
        recompute: None,
        shade,
        fetch: None,
        output,
    };
    let function = strategy::build_entry(&module, &entry, &parts, strategy::EntryKind::Shade, 0)?;
    module.entry_points[0].function = function;
    finish(PassKind::Shade, module)
}

/// The `@builtin(position)` among entry arguments: argument index and, for a struct, member index.
pub(crate) fn find_position(
    module: &Module,
    arguments: &[naga::FunctionArgument],
) -> Option<(u32, Option<u32>)> {
    let is_pos = |b: &Option<naga::Binding>| {
        matches!(
            b,
            Some(naga::Binding::BuiltIn(naga::BuiltIn::Position { .. }))
        )
    };
    for (i, arg) in arguments.iter().enumerate() {
        if is_pos(&arg.binding) {
            return Some((i as u32, None));
        }
        if let naga::TypeInner::Struct { members, .. } = &module.types[arg.ty].inner
            && let Some(m) = members.iter().position(|m| is_pos(&m.binding))
        {
            return Some((i as u32, Some(m as u32)));
        }
    }
    None
}

/// The entry point's `@builtin(position)`, added as a new argument when the shader has none.
fn find_or_add_position(module: &mut Module, vec4f: Handle<naga::Type>) -> (u32, Option<u32>) {
    if let Some(p) = find_position(module, &module.entry_points[0].function.arguments) {
        return p;
    }
    let fun = &mut module.entry_points[0].function;
    fun.arguments.push(naga::FunctionArgument {
        name: Some("reproj_frag_coord".into()),
        ty: vec4f,
        binding: Some(naga::Binding::BuiltIn(naga::BuiltIn::Position {
            invariant: false,
        })),
    });
    (fun.arguments.len() as u32 - 1, None)
}

/// Write WGSL. Names naga's writer invented on an earlier trip (`_e12`, `_e12_1`, ...) are dropped
/// first, so that the writer invents them again the same way and the text reaches a fixed point.
/// The module's global `diagnostic(...)` directives, which naga's writer leaves out, are written
/// first.
pub fn write_wgsl(module: &Module, info: &naga::valid::ModuleInfo) -> Result<String, String> {
    fn generated(name: &str) -> bool {
        name.strip_prefix("_e").is_some_and(|rest| {
            !rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit() || b == b'_')
        })
    }
    let mut module = module.clone();
    let strip = |f: &mut naga::Function| f.named_expressions.retain(|_, name| !generated(name));
    for (_, f) in module.functions.iter_mut() {
        strip(f);
    }
    for ep in &mut module.entry_points {
        strip(&mut ep.function);
    }
    let text =
        naga::back::wgsl::write_string(&module, info, naga::back::wgsl::WriterFlags::empty())
            .map_err(|e| e.to_string())?;
    Ok(diagnostic_directives(&module) + &text)
}

/// The module's global diagnostic filters as WGSL directives, outermost first.
fn diagnostic_directives(module: &Module) -> String {
    use naga::diagnostic_filter::{
        FilterableTriggeringRule as R, Severity, StandardFilterableTriggeringRule as S,
    };
    let mut lines = Vec::new();
    let mut node = module.diagnostic_filter_leaf;
    while let Some(h) = node {
        let n = &module.diagnostic_filters[h];
        let severity = match n.inner.new_severity {
            Severity::Off => "off",
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Error => "error",
        };
        let rule = match &n.inner.triggering_rule {
            R::Standard(S::DerivativeUniformity) => "derivative_uniformity".to_string(),
            R::Unknown(name) => name.to_string(),
            R::User(parts) => format!("{}.{}", parts[0], parts[1]),
        };
        lines.push(format!("diagnostic({severity}, {rule});\n"));
        node = n.parent;
    }
    lines.reverse();
    if lines.is_empty() {
        String::new()
    } else {
        lines.concat() + "\n"
    }
}

/// Turn WGSL's `derivative_uniformity` diagnostic off for the whole module (see the fused entry in
/// [`strategy`]: its recompute branch is uniform over each 2×2 quad, which the analysis cannot see).
fn allow_quad_uniform_derivatives(module: &mut Module) {
    use naga::diagnostic_filter::{
        DiagnosticFilter, DiagnosticFilterNode, FilterableTriggeringRule, Severity,
        StandardFilterableTriggeringRule,
    };
    let node = DiagnosticFilterNode {
        inner: DiagnosticFilter {
            new_severity: Severity::Off,
            triggering_rule: FilterableTriggeringRule::Standard(
                StandardFilterableTriggeringRule::DerivativeUniformity,
            ),
        },
        parent: module.diagnostic_filter_leaf,
    };
    module.diagnostic_filter_leaf = Some(
        module
            .diagnostic_filters
            .append(node, naga::Span::UNDEFINED),
    );
}

/// Validate, compact, validate again, write WGSL and run it to a fixed point of the round trip.
fn finish(pass: PassKind, module: Module) -> Result<PassModule, InstanceError> {
    let (module, info, wgsl) =
        finish_module(module, 2, |what| InstanceError::Internal { pass, what })?;
    Ok(PassModule {
        kind: pass,
        module,
        info,
        wgsl,
    })
}

/// Validate, compact, validate again and write `module` as WGSL that is a fixed point of parse →
/// validate → write within `rounds` trips; `internal` makes the error of a step that fails (a bug
/// in reproj).
pub(crate) fn finish_module(
    mut module: Module,
    rounds: usize,
    internal: impl Fn(String) -> InstanceError,
) -> Result<(Module, naga::valid::ModuleInfo, String), InstanceError> {
    validator().validate(&module).map_err(|e| {
        internal(format!(
            "does not validate before compaction: {}",
            e.as_inner()
        ))
    })?;
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    let info = validator().validate(&module).map_err(|e| {
        internal(format!(
            "does not validate after compaction: {}",
            e.as_inner()
        ))
    })?;
    let mut text = write_wgsl(&module, &info).map_err(&internal)?;
    // The text may change (names, literal spellings; constants naga folds on parsing) and must
    // then stop changing.
    for round in 0..rounds {
        let reparsed = naga::front::wgsl::parse_str(&text).map_err(|e| {
            internal(format!(
                "written WGSL does not parse: {}",
                e.emit_to_string(&text)
            ))
        })?;
        let reinfo = validator().validate(&reparsed).map_err(|e| {
            internal(format!(
                "written WGSL does not validate: {}",
                e.emit_to_string(&text)
            ))
        })?;
        let again = write_wgsl(&reparsed, &reinfo).map_err(&internal)?;
        if again == text {
            return Ok((reparsed, reinfo, text));
        }
        if round + 1 == rounds {
            return Err(internal(
                "the WGSL round trip does not reach a fixed point".into(),
            ));
        }
        text = again;
    }
    unreachable!()
}

/// File name of a pass's WGSL beside the manifest.
pub fn pass_file(kind: PassKind) -> &'static str {
    match kind {
        PassKind::Reproject => "pass1_reproject.wgsl",
        PassKind::Recompute => "pass2_recompute.wgsl",
        PassKind::Shade => "pass3_shade.wgsl",
        PassKind::Fused => "pass1_fused.wgsl",
        PassKind::ShadeHits => "pass1_shade_hits.wgsl",
        PassKind::ShadeMisses => "pass2_shade_misses.wgsl",
    }
}

/// WGSL spelling of a type (naga's own printer; structs by name).
fn type_name(module: &Module, ty: Handle<naga::Type>) -> String {
    use naga::common::wgsl::TypeContext;
    module.to_ctx().type_to_string(ty)
}

/// The bind group layout entry of a global variable, from its type.
fn layout_entry(module: &Module, g: &naga::GlobalVariable, filterable: bool) -> LayoutEntry {
    use naga::TypeInner as T;
    let inner = &module.types[g.ty].inner;
    match (g.space, inner) {
        (naga::AddressSpace::Uniform, _) => LayoutEntry::Buffer {
            buffer_type: "uniform".into(),
            min_binding_size: u64::from(inner.size(module.to_ctx())),
        },
        (naga::AddressSpace::Storage { access }, _) => LayoutEntry::Buffer {
            buffer_type: if access.contains(naga::StorageAccess::STORE) {
                "storage"
            } else {
                "read-only-storage"
            }
            .into(),
            min_binding_size: u64::from(inner.size(module.to_ctx())),
        },
        (_, T::Sampler { comparison }) => LayoutEntry::Sampler {
            sampler_type: if *comparison {
                "comparison"
            } else if filterable {
                "filtering"
            } else {
                "non-filtering"
            }
            .into(),
        },
        (
            _,
            T::Image {
                dim,
                arrayed,
                class,
            },
        ) => {
            let view_dimension = match (dim, arrayed) {
                (naga::ImageDimension::D1, _) => "1d",
                (naga::ImageDimension::D2, false) => "2d",
                (naga::ImageDimension::D2, true) => "2d-array",
                (naga::ImageDimension::D3, _) => "3d",
                (naga::ImageDimension::Cube, false) => "cube",
                (naga::ImageDimension::Cube, true) => "cube-array",
            }
            .to_string();
            match class {
                naga::ImageClass::Sampled { kind, multi } => LayoutEntry::Texture {
                    sample_type: match kind {
                        naga::ScalarKind::Sint => "sint",
                        naga::ScalarKind::Uint => "uint",
                        _ if filterable => "float",
                        _ => "unfilterable-float",
                    }
                    .into(),
                    view_dimension,
                    multisampled: *multi,
                },
                naga::ImageClass::Depth { multi } => LayoutEntry::Texture {
                    sample_type: "depth".into(),
                    view_dimension,
                    multisampled: *multi,
                },
                naga::ImageClass::Storage { format, access } => LayoutEntry::StorageTexture {
                    format: format!("{format:?}").to_lowercase(),
                    access: if access
                        .contains(naga::StorageAccess::LOAD | naga::StorageAccess::STORE)
                    {
                        "read-write"
                    } else if access.contains(naga::StorageAccess::STORE) {
                        "write-only"
                    } else {
                        "read-only"
                    }
                    .into(),
                    view_dimension,
                },
                naga::ImageClass::External => LayoutEntry::Texture {
                    sample_type: "float".into(),
                    view_dimension,
                    multisampled: false,
                },
            }
        }
        _ => LayoutEntry::Buffer {
            buffer_type: "uniform".into(),
            min_binding_size: u64::from(inner.size(module.to_ctx())),
        },
    }
}

/// The bindings of a pass module: the shader's own (bound as for the original) and the
/// instancer's, each with its layout entry and the resource it takes.
fn bindings(module: &Module, group: u32, reconstruct: Reconstruct) -> Vec<Binding> {
    let mut out: Vec<Binding> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            let b = g.binding.as_ref()?;
            let name = g.name.clone().unwrap_or_default();
            let space = match g.space {
                naga::AddressSpace::Uniform => "uniform ",
                naga::AddressSpace::Storage { .. } => "storage ",
                _ => "",
            };
            let added = b.group == group;
            let (resource, filterable) = if !added {
                (BindingResource::Own, true)
            } else {
                match name.as_str() {
                    contract::PARAMS => (BindingResource::Params, false),
                    contract::PREV_PAYLOAD => (
                        BindingResource::Texture {
                            role: ROLE_PREV_PAYLOAD.into(),
                        },
                        reconstruct == Reconstruct::Bilinear,
                    ),
                    contract::CUR_PAYLOAD => (
                        BindingResource::Texture {
                            role: ROLE_CUR_PAYLOAD.into(),
                        },
                        false,
                    ),
                    contract::PREV_DEPTH => (
                        BindingResource::Texture {
                            role: ROLE_PREV_DEPTH_COPY.into(),
                        },
                        false,
                    ),
                    contract::LINEAR_SAMPLER => (
                        BindingResource::Sampler {
                            name: SAMPLER_LINEAR.into(),
                        },
                        true,
                    ),
                    other => unreachable!("the lookup library declares no binding `{other}`"),
                }
            };
            Some(Binding {
                group: b.group,
                binding: b.binding,
                name,
                ty: format!("{space}{}", type_name(module, g.ty)),
                added,
                layout: layout_entry(module, g, filterable),
                resource,
            })
        })
        .collect();
    out.sort_by_key(|b| (b.group, b.binding));
    out
}

/// Texture roles of the [`FramePlan`].
pub const ROLE_CUR_PAYLOAD: &str = "cur_payload";
pub const ROLE_PREV_PAYLOAD: &str = "prev_payload";
pub const ROLE_CUR_DEPTH: &str = "cur_depth";
/// The depth attachment (one texture: the depth buffer is not kept from one frame to the next).
pub const ROLE_CUR_DEPTH_COPY: &str = "cur_depth_copy";
/// The previous frame's depth, as the passes that wrote its color copied it (r32float).
pub const ROLE_PREV_DEPTH_COPY: &str = "prev_depth_copy";
/// The frame target's attachment name.
pub const ATTACHMENT_FRAME: &str = "frame";
/// Sampler names.
pub const SAMPLER_LINEAR: &str = "linear";

/// The WGSL of the vertex contract's helper.
const VERTEX_CONTRACT_WGSL: &str = "\
// reproj: the vertex's clip-space position in the previous frame. Write the result to the vertex
// output at @location(prev_clip_location); the clip position itself must be @invariant.
fn reproj_prev_clip(prev_view_proj: mat4x4<f32>, prev_model: mat4x4<f32>, position: vec3<f32>) -> vec4<f32> {
    return prev_view_proj * (prev_model * vec4<f32>(position, 1.0));
}
";

#[allow(clippy::too_many_arguments)]
fn build_manifest(
    shader: &Shader,
    norm: &Normalized,
    nodes: &[&Node],
    opts: &InstanceOptions,
    cache_format: CacheFormat,
    group: u32,
    prev_clip_location: u32,
    passes: &[PassModule],
) -> Manifest {
    let clear_cache = || LoadOp::Clear {
        value: Some(vec![0.0; 4]),
    };
    let cache = |location: u32, load: LoadOp| ColorTarget {
        location,
        attachment: ROLE_CUR_PAYLOAD.into(),
        format: Some(cache_format.name().into()),
        load,
        store: true,
        blend: None,
    };
    let frame_first = || match opts.frame_load {
        FrameLoad::Clear => LoadOp::Clear { value: None },
        FrameLoad::Load => LoadOp::Load,
    };
    let frame = |load: LoadOp| ColorTarget {
        location: 0,
        attachment: ATTACHMENT_FRAME.into(),
        format: None,
        load,
        store: true,
        blend: None,
    };
    let clear_depth = || LoadOp::Clear {
        value: Some(vec![1.0]),
    };
    let depth = |compare: &str, write: bool, load: LoadOp| DepthState {
        attachment: ROLE_CUR_DEPTH.into(),
        format: "depth32float".into(),
        compare: compare.into(),
        write,
        load,
        store: true,
        stencil: None,
    };
    let depth_copy = |location: u32, load: LoadOp| ColorTarget {
        location,
        attachment: ROLE_CUR_DEPTH_COPY.into(),
        format: Some("r32float".into()),
        load,
        store: true,
        blend: None,
    };
    let clear_depth_copy = || LoadOp::Clear {
        value: Some(vec![1.0, 0.0, 0.0, 0.0]),
    };
    // The location of an output struct member (the cache and the depth copy follow the shader's
    // outputs).
    let location_of = |p: &PassModule, name: &str| {
        let ep = &p.module.entry_points[0];
        let ty = ep
            .function
            .result
            .as_ref()
            .map(|r| &p.module.types[r.ty].inner);
        match ty {
            Some(naga::TypeInner::Struct { members, .. }) => members
                .iter()
                .find(|m| m.name.as_deref() == Some(name))
                .and_then(|m| match m.binding {
                    Some(naga::Binding::Location { location, .. }) => Some(location),
                    _ => None,
                })
                .unwrap_or(1),
            _ => 1,
        }
    };
    let cache_at = |p: &PassModule| location_of(p, strategy::CACHE_MEMBER);
    let depth_at = |p: &PassModule| location_of(p, strategy::DEPTH_MEMBER);
    let pass = |p: &PassModule| {
        let (colors, depth) = match p.kind {
            PassKind::Reproject => (
                vec![cache(0, clear_cache())],
                depth("less", true, clear_depth()),
            ),
            PassKind::Recompute => (
                vec![cache(0, LoadOp::Load)],
                depth("less", true, LoadOp::Load),
            ),
            PassKind::Shade => (
                vec![
                    frame(frame_first()),
                    depth_copy(depth_at(p), clear_depth_copy()),
                ],
                depth("equal", false, LoadOp::Load),
            ),
            PassKind::Fused | PassKind::ShadeHits => (
                vec![
                    frame(frame_first()),
                    cache(cache_at(p), clear_cache()),
                    depth_copy(depth_at(p), clear_depth_copy()),
                ],
                depth("less", true, clear_depth()),
            ),
            PassKind::ShadeMisses => (
                vec![
                    frame(LoadOp::Load),
                    cache(cache_at(p), LoadOp::Load),
                    depth_copy(depth_at(p), LoadOp::Load),
                ],
                depth("less", true, LoadOp::Load),
            ),
        };
        Pass {
            kind: p.kind,
            file: pass_file(p.kind).into(),
            entry: p
                .module
                .entry_points
                .iter()
                .find(|e| e.name != contract::CLASSIFY_ENTRY)
                .map_or_else(String::new, |e| e.name.clone()),
            bindings: bindings(&p.module, group, opts.reconstruct),
            colors,
            depth,
        }
    };
    let draw = match opts.strategy {
        Strategy::ThreePass => "All three passes draw",
        Strategy::TwoPass => "Both passes draw",
        Strategy::Fused => "The pass draws",
    };
    let mut notes = vec![
        format!("{draw} the scene's geometry with the same vertex stage, whose clip position is @invariant."),
        format!(
            "The vertex stage also writes @location({prev_clip_location}) prev_clip: vec4<f32> = previous frame's view_proj * previous model * position (the manifest's vertex.wgsl)."
        ),
        "The passes that write the frame color also write the fragment's depth to the \"current depth copy\" target (r32float, cleared to 1.0): the depth the next frame's lookup reads. The depth buffer itself is not read, nor kept from one frame to the next.".into(),
        "Frame i binds the textures of frames.ping_pong[i % 2]: what it writes as cur_* it reads as prev_* next frame.".into(),
        "On the first frame, or after a cut, set delta_n = 1: every pixel is recomputed.".into(),
        "The first pass's module also has the debug entry point reproj_classify (rgba8unorm target, no discard, pass 1's depth state): green hit, red miss, blue refresh.".into(),
    ];
    if opts.frame_load == FrameLoad::Load {
        notes.push("The frame target is loaded, not cleared: clear it (or draw what lies behind) before the first pass.".into());
    }
    let texture = |name: &str, format: &str| TextureDesc {
        name: name.into(),
        format: format.into(),
        size: TextureSize::Frame,
        usage: vec![TextureUsage::RenderAttachment, TextureUsage::TextureBinding],
        mip_levels: 1,
        sample_count: 1,
    };
    let plan = |a: &str, b: &str| {
        [
            (ROLE_CUR_PAYLOAD, format!("payload_{a}")),
            (ROLE_PREV_PAYLOAD, format!("payload_{b}")),
            (ROLE_CUR_DEPTH_COPY, format!("depth_copy_{a}")),
            (ROLE_PREV_DEPTH_COPY, format!("depth_copy_{b}")),
            (ROLE_CUR_DEPTH, "depth".to_string()),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect()
    };
    let sampler = |name: &str, f: Filter| SamplerDesc {
        name: name.into(),
        mag_filter: f,
        min_filter: f,
        mipmap_filter: Filter::Nearest,
        address_mode: "clamp-to-edge".into(),
    };
    let field = |name: &str, offset: u32, ty: ScalarType, value: ParamValue| ParamField {
        name: name.into(),
        offset,
        ty,
        value,
    };
    let mut offset = 0;
    let infos: Vec<NodeInfo> = nodes
        .iter()
        .map(|node| {
            let info = NodeInfo {
                id: node_id(node),
                text: node.text.clone(),
                line: node.line,
                col: node.col,
                ty: node.ty.clone(),
                components: node.components,
                offset,
            };
            offset += node.components;
            info
        })
        .collect();
    if nodes.len() > 1 {
        notes.push(format!(
            "The payload holds {} nodes, each at its offset: {}.",
            nodes.len(),
            infos
                .iter()
                .map(|i| format!("node {} at {}", i.id, i.offset))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Manifest {
        schema: "reproj.manifest".into(),
        version: MANIFEST_VERSION,
        shader: shader.path.file_name().map_or_else(
            || shader.path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        ),
        entry: norm.entry.clone(),
        node: infos[0].clone(),
        also: infos[1..].to_vec(),
        strategy: opts.strategy,
        reconstruct: opts.reconstruct,
        cache_format,
        required_features: if !cache_format.is_half() && opts.reconstruct == Reconstruct::Bilinear {
            vec!["float32-filterable".into()]
        } else {
            Vec::new()
        },
        group,
        conventions: Conventions::default(),
        vertex: VertexContract {
            invariant_position: true,
            prev_clip_location,
            inputs: vec![
                VertexInput {
                    name: "prev_view_proj".into(),
                    ty: "mat4x4<f32>".into(),
                    meaning: "the previous frame's view-projection matrix (this frame's on the first frame)".into(),
                },
                VertexInput {
                    name: "prev_model".into(),
                    ty: "mat4x4<f32>".into(),
                    meaning: "the object's model matrix in the previous frame".into(),
                },
                VertexInput {
                    name: "position".into(),
                    ty: "vec3<f32>".into(),
                    meaning: "the vertex's object-space position".into(),
                },
            ],
            wgsl: VERTEX_CONTRACT_WGSL.into(),
        },
        params: Params {
            delta_n: opts.delta_n,
            block: opts.block,
            depth_epsilon: opts.depth_epsilon,
            size: contract::PARAMS_SIZE,
            fields: vec![
                field(
                    "delta_n",
                    offset_of!(ReprojParams, delta_n) as u32,
                    ScalarType::U32,
                    ParamValue::Steady {
                        value: f64::from(opts.delta_n),
                        first: 1.0,
                    },
                ),
                field(
                    "clock",
                    offset_of!(ReprojParams, clock) as u32,
                    ScalarType::U32,
                    ParamValue::FrameIndex,
                ),
                field(
                    "block",
                    offset_of!(ReprojParams, block) as u32,
                    ScalarType::U32,
                    ParamValue::Constant {
                        value: f64::from(opts.block),
                    },
                ),
                field(
                    "depth_epsilon",
                    offset_of!(ReprojParams, depth_epsilon) as u32,
                    ScalarType::F32,
                    ParamValue::Constant {
                        // The f32's shortest decimal (0.01, not 0.009999999776482582).
                        value: opts.depth_epsilon.to_string().parse().unwrap_or_default(),
                    },
                ),
            ],
        },
        textures: vec![
            texture("payload_0", cache_format.name()),
            texture("payload_1", cache_format.name()),
            texture("depth_copy_0", "r32float"),
            texture("depth_copy_1", "r32float"),
            TextureDesc {
                usage: vec![TextureUsage::RenderAttachment],
                ..texture("depth", "depth32float")
            },
        ],
        samplers: vec![sampler(SAMPLER_LINEAR, Filter::Linear)],
        frames: FramePlan {
            ping_pong: vec![plan("0", "1"), plan("1", "0")],
        },
        passes: passes.iter().map(pass).collect(),
        notes,
    }
}

/// The file extensions a variant directory holds: [`write_variant`] replaces a directory that
/// holds only these (and refuses any other), so a stale pass from another strategy or language
/// never lingers.
pub const VARIANT_FILES: &[&str] = &["wgsl", "json", "frag", "hlsl", "metal", "spv"];

/// Write the variant's WGSL files and `manifest.json` as the directory `dir`, whole: everything is
/// written into a staging directory beside it, which then replaces `dir`
/// ([`reproj_io::StagedDir`]), so a failure leaves `dir` as it was and a success leaves no file
/// of an earlier variant.
pub fn write_variant(variant: &Variant, dir: &Path) -> Result<(), InstanceError> {
    write_variant_in(variant, dir, &[])
}

/// [`write_variant`], and every pass also in each of `langs` ([`backends`]) beside its WGSL.
/// Every file is generated before any is written: a backend error writes nothing.
pub fn write_variant_in(
    variant: &Variant,
    dir: &Path,
    langs: &[backends::OutputLang],
) -> Result<(), InstanceError> {
    let files = variant_files(variant, langs)?;
    let staged = reproj_io::StagedDir::new(dir, reproj_io::Replace::OwnFiles(VARIANT_FILES))?;
    for (name, bytes) in files {
        staged.write(name, &bytes)?;
    }
    staged.commit()?;
    Ok(())
}

/// The files of a variant directory, by name: each pass's WGSL, each pass in each of `langs`,
/// and `manifest.json`.
pub fn variant_files(
    variant: &Variant,
    langs: &[backends::OutputLang],
) -> Result<Vec<(String, Vec<u8>)>, InstanceError> {
    let mut files: Vec<(String, Vec<u8>)> = variant
        .passes
        .iter()
        .map(|p| (pass_file(p.kind).to_owned(), p.wgsl.clone().into_bytes()))
        .collect();
    for &lang in langs {
        for p in &variant.passes {
            files.push((
                backends::pass_file_in(p, lang),
                backends::write_pass(p, lang)?,
            ));
        }
    }
    let mut manifest = serde_json::to_vec_pretty(&variant.manifest).expect("manifest serializes");
    manifest.push(b'\n');
    files.push(("manifest.json".to_owned(), manifest));
    Ok(files)
}
