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
mod error;
pub mod import;
mod layout;
mod library;
mod options;
pub use library::classify_wgsl;
use library::{PrevClip, library_text, parse_library, reproject_text};
pub mod manifest;
mod simplify;
mod strategy;
mod wgsl;
mod write;

pub mod contract;

pub use error::InstanceError;
pub use layout::{
    ATTACHMENT_FRAME, ROLE_CUR_DEPTH, ROLE_CUR_DEPTH_COPY, ROLE_CUR_PAYLOAD, ROLE_PREV_DEPTH_COPY,
    ROLE_PREV_PAYLOAD, SAMPLER_LINEAR, payload_clear,
};
use layout::{ManifestInput, build_manifest};
pub use manifest::*;
pub use options::{CacheFormatChoice, DepthLoad, FrameLoad, InstanceOptions, NodeSelector};
pub use reproj_front::write_wgsl;
pub use simplify::{Replacement, Simplified, SimplifyOptions, probe, simplify};
pub use wgsl::pass_file;
use wgsl::{allow_quad_uniform_derivatives, finish, finish_module};
pub use write::{VARIANT_FILES, variant_files, write_variant, write_variant_in};

pub use contract::MAX_BIND_GROUPS;
use contract::ReprojParams;
use std::mem::offset_of;

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
    let place = added_place(&shader.module, opts.group)?;
    let prev_clip = match opts.reprojection {
        Reprojection::Vertex => PrevClip::Location(prev_clip_location(&norm.module)),
        Reprojection::MotionVectors => PrevClip::Motion,
    };
    let (cache_format, depth_channel) = payload_layout(opts, components);
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
    let library = library_text(place, prev_clip, opts.reconstruct, depth_channel);
    let passes = match opts.strategy {
        Strategy::ThreePass => vec![
            reproject_pass(&library, prev_clip)?,
            recompute_pass(norm, &slots)?,
            shade_pass(norm, &slots, place)?,
        ],
        Strategy::Fused | Strategy::TwoPass => strategy_passes(
            norm,
            &slots,
            &library,
            opts.strategy,
            prev_clip,
            depth_channel,
        )?,
    };
    let manifest = build_manifest(&ManifestInput {
        shader,
        norm,
        nodes: &picked,
        opts,
        cache_format,
        depth_channel,
        place,
        prev_clip_location: prev_clip.location(),
        passes: &passes,
    });
    Ok(Variant { manifest, passes })
}

/// The payload's format, and where the previous frame's depth is kept: in the payload's first
/// free channel where the entries that write the cache also write the frame (fused, two-pass),
/// the payload is a filtered 32-bit float format and has a channel to spare, so the lookup reads
/// depth and payload in one filtered fetch and no depth copy target is written; else (`None`) in
/// the depth copy, read with four loads. `f32` widens the payload by that channel; an exact
/// format packs only where it has one free (`r32float` for a one-float node keeps the depth copy).
/// Four loads cost a CPU rasterizer more than the shading they save
/// (docs/notebook/pass-layouts.md, "The depth in the payload").
fn payload_layout(opts: &InstanceOptions, components: u32) -> (CacheFormat, Option<u32>) {
    let packs = opts.strategy != Strategy::ThreePass && opts.reconstruct.filters();
    match opts.cache_format {
        CacheFormatChoice::Narrowest32 if packs && components < 4 => (
            CacheFormat::narrowest(components + 1, false),
            Some(components),
        ),
        CacheFormatChoice::Exact(f) if packs && !f.is_half() && f.channels() > components => {
            (f, Some(components))
        }
        choice => (choice.resolve(components), None),
    }
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

/// Where the variant's bindings go: `chosen` (`--group`) or else the lowest group the shader
/// leaves free; where that group is the shader's own (chosen, or every group taken: then its
/// highest), past the shader's bindings in it ([`contract::AddedPlace`]).
pub fn added_place(
    module: &Module,
    chosen: Option<u32>,
) -> Result<contract::AddedPlace, InstanceError> {
    let used = used_groups(module);
    let group = match chosen {
        Some(g) if g >= MAX_BIND_GROUPS => {
            return Err(InstanceError::GroupTaken { group: g, used });
        }
        Some(g) => g,
        None => match (0..MAX_BIND_GROUPS).find(|g| !used.contains(g)) {
            Some(g) => g,
            None => *used.last().expect("every group is used"),
        },
    };
    let base = module
        .global_variables
        .iter()
        .filter_map(|(_, v)| v.binding.as_ref())
        .filter(|b| b.group == group)
        .map(|b| b.binding + 1)
        .max()
        .unwrap_or(0);
    if base
        .checked_add(contract::MOTION_BINDING)
        .is_none_or(|top| top > MAX_BINDING)
    {
        return Err(InstanceError::GroupTaken { group, used });
    }
    Ok(contract::AddedPlace { group, base })
}

/// The highest binding number WebGPU's `maxBindingsPerBindGroup` (1000) allows.
const MAX_BINDING: u32 = 999;

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

fn reproject_pass(library: &str, prev_clip: PrevClip) -> Result<PassModule, InstanceError> {
    let text = reproject_text(library, prev_clip);
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
    prev_clip: PrevClip,
    depth_channel: Option<u32>,
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
    let output = strategy::output_struct(&mut base, &result, Some(vec4), depth_channel.is_none());
    let original_ep = base.entry_points[0].clone();
    let mut passes = Vec::new();
    for &kind in kinds {
        let pass = strategy::pass_kind(kind);
        let mut module = base.clone();
        module.entry_points.clear();
        let (fetch, motion_clip) = if strategy::needs_fetch(kind) {
            let lib = parse_library(library, pass)?;
            let imported = import::import_module(&mut module, &lib)
                .map_err(|what| InstanceError::Internal { pass, what })?;
            (
                imported.functions.get("reproj_fetch").copied(),
                imported.functions.get(contract::MOTION_CLIP).copied(),
            )
        } else {
            (None, None)
        };
        let parts = strategy::Parts {
            vec4,
            recompute: Some(recompute),
            shade,
            fetch,
            motion_clip,
            output,
            depth_channel,
        };
        let function = strategy::build_entry(&module, &entry, &parts, kind, prev_clip)?;
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

fn shade_pass(
    norm: &Normalized,
    slots: &[Slot],
    place: contract::AddedPlace,
) -> Result<PassModule, InstanceError> {
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
                group: place.group,
                binding: place.binding(contract::CUR_PAYLOAD_BINDING),
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
    let output = strategy::output_struct(&mut module, &result, None, true);
    let parts = strategy::Parts {
        vec4: vec4f,
        recompute: None,
        shade,
        fetch: None,
        motion_clip: None,
        output,
        depth_channel: None,
    };
    let function = strategy::build_entry(
        &module,
        &entry,
        &parts,
        strategy::EntryKind::Shade,
        PrevClip::Location(0),
    )?;
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
