//! Code simplification (Pellacini 2005, the paper's § 5.4 comparison): the shader with some nodes
//! replaced by constants, and the probe that measures a node's value so the constant can be its
//! session mean.
//!
//! Both are the normalized entry point rebuilt in order ([`reproj_front::rebuild`]): the probe is
//! the recompute slice (the node's value as the color output, zero-padded to a `vec4<f32>`), the
//! simplified shader the whole function under [`Rewrite::Constants`] with its dead code removed,
//! so the subtree of a replaced node disappears unless the rest of the shader still uses it.
//! Every module is validated, compacted, validated again and written as round-trip WGSL (a few
//! trips allowed: naga folds the constants on parsing, which can cascade).

use naga::Module;
use reproj_front::rebuild::{Constant, Rewrite, Slot, rebuild_live};
use reproj_front::{Node, NodeTable, Normalized};

use crate::{InstanceError, NodeSelector, PassKind, finish_module, pick, recompute_pass, vec_type};

/// One node replaced by a constant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Replacement {
    /// The node's id (from [`reproj_front::enumerate`]).
    pub node: u32,
    /// Its constant value; components past the node's are ignored.
    pub value: [f32; 4],
}

/// Options of [`simplify`]: which nodes become which constants.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimplifyOptions {
    /// The replacements; a node listed twice takes its first value.
    pub replace: Vec<Replacement>,
}

/// A single-entry fragment module: a simplified shader or a node's probe.
#[derive(Debug, Clone)]
pub struct Simplified {
    pub module: Module,
    pub info: naga::valid::ModuleInfo,
    /// WGSL text: a fixed point of parse → validate → write.
    pub wgsl: String,
}

/// The shader of `norm` with every node of `opts.replace` replaced by its constant. Only
/// cacheable nodes of `f32` or `vecN<f32>` type can be replaced (a culled node may sit in a loop
/// or depend discontinuously on its inputs; its value has no single mean).
pub fn simplify(
    norm: &Normalized,
    table: &NodeTable,
    opts: &SimplifyOptions,
) -> Result<Simplified, InstanceError> {
    let mut module = norm.module.clone();
    let mut constants = Vec::with_capacity(opts.replace.len());
    for r in &opts.replace {
        let node = replaceable(norm, table, r.node)?;
        let target = node
            .handle
            .expect("nodes from enumerate carry their handle");
        if constants.iter().any(|c: &Constant| c.target == target) {
            continue;
        }
        let vector = match node.components {
            1 => None,
            n => Some(vec_type(&mut module, vector_size(n), naga::Scalar::F32)),
        };
        constants.push(Constant {
            target,
            value: r.value,
            components: node.components,
            vector,
        });
    }
    let internal = |what: String| InstanceError::InternalSimplified { what };
    let fun = rebuild_live(&module, norm.function(), &Rewrite::Constants(&constants))
        .map_err(|e| internal(e.to_string()))?
        .function;
    module.entry_points[0].function = fun;
    let (module, info, wgsl) = finish_module(module, internal)?;
    Ok(Simplified { module, info, wgsl })
}

/// The probe of node `id`: the shader sliced after the node, returning its value as the color
/// (`vec4<f32>`, zero-padded) at `@location(0)`. Rendered over a session, its frames hold the
/// node's value at every covered pixel.
pub fn probe(norm: &Normalized, table: &NodeTable, id: u32) -> Result<Simplified, InstanceError> {
    let node = replaceable(norm, table, id)?;
    let target = node
        .handle
        .expect("nodes from enumerate carry their handle");
    let pass = recompute_pass(norm, &Slot::pack(&[(target, node.components)]))?;
    debug_assert_eq!(pass.kind, PassKind::Recompute);
    Ok(Simplified {
        module: pass.module,
        info: pass.info,
        wgsl: pass.wgsl,
    })
}

/// Node `id` when it is cacheable and of type `f32` or `vecN<f32>`.
fn replaceable<'t>(
    norm: &Normalized,
    table: &'t NodeTable,
    id: u32,
) -> Result<&'t Node, InstanceError> {
    let node = pick(table, NodeSelector::Id(id))?;
    let handle = node
        .handle
        .expect("nodes from enumerate carry their handle");
    let inner = norm.function_info()[handle]
        .ty
        .inner_with(&norm.module.types);
    let float = naga::Scalar::F32;
    let ok = match *inner {
        naga::TypeInner::Scalar(s) => s == float,
        naga::TypeInner::Vector { scalar, .. } => scalar == float,
        _ => false,
    };
    if !ok || !(1..=4).contains(&node.components) {
        return Err(InstanceError::NotReplaceable {
            id,
            text: node.text.clone(),
            why: format!("its type is {}, not f32 or vecN<f32>", node.ty),
        });
    }
    Ok(node)
}

fn vector_size(n: u32) -> naga::VectorSize {
    match n {
        2 => naga::VectorSize::Bi,
        3 => naga::VectorSize::Tri,
        _ => naga::VectorSize::Quad,
    }
}
