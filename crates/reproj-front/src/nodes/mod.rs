//! Candidate nodes: enumeration, culling, cost and overlap.
//!
//! A *node* is a float-valued expression (f32/f16 scalar, vector or matrix) of the normalized
//! entry point. Each gets a stable id (its rank in the normalized function's expression arena,
//! which is evaluation order), its source span and text, its type, a static cost estimate of its
//! subtree and its *overlap*: the part of that cost the rest of the shader still needs when the node
//! is read from a cache. A node is cacheable, or culled with exactly one [`CullReason`].
//!
//! Dependencies go through memory too: a `Load` of a local variable depends on every `Store` to
//! it (and on the conditions that control those stores), so a value read after a loop has the loop
//! as its subtree.

//!
//! Enumeration is in phases, a file each: `walk.rs` (where each expression is evaluated and the
//! dependency edges, through memory too), `costs.rs` (each subtree's cost and overlap over one
//! reachability graph), `cull.rs` (continuity, derivatives and the one [`CullReason`]) and
//! `source.rs` (a node's line, column, text and WGSL type).

mod costs;
mod cull;
mod source;
mod walk;

use std::collections::HashSet;

use naga::{Expression, Handle};
use serde::{Deserialize, Serialize};

pub use crate::cost::DEFAULT_TRIP_COUNT;
use crate::ir;
use crate::normalize::Normalized;
use crate::shader::Shader;
use costs::Costs;
use cull::{Flags, continuous_from, cull_reason, feeds_derivatives, payload_components};
use source::{LineIndex, node_type, place_leaves, source_position, span_text};
use walk::{Walk, dependencies};

/// Why a node cannot be cached. Serialized in kebab-case (`in-loop`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CullReason {
    /// Evaluated inside a loop body: a different value each iteration.
    InLoop,
    /// Evaluated inside a branch whose condition is not uniform.
    NonUniformBranch,
    /// Reaches the output only through comparisons, `select` conditions, `step`, rounding,
    /// `fract`, `sign`, `%`, integer or boolean conversions, or branch conditions.
    Discontinuous,
    /// Feeds `dpdx`/`dpdy`/`fwidth`, or the coordinates of a `textureSample` with an implicit
    /// level of detail: both need the neighbouring pixels' values.
    Derivative,
    /// Not an f32 scalar or vector of at most 4 components.
    PayloadType,
    /// A literal, constant, input, builtin or uniform read: cheaper than a cache lookup.
    Trivial,
}

impl CullReason {
    /// Every reason, in declaration order.
    pub const ALL: [CullReason; 6] = [
        CullReason::InLoop,
        CullReason::NonUniformBranch,
        CullReason::Discontinuous,
        CullReason::Derivative,
        CullReason::PayloadType,
        CullReason::Trivial,
    ];

    /// What a shader whose work is mostly culled for this reason could change.
    pub fn hint(self) -> &'static str {
        match self {
            CullReason::InLoop => {
                "the work is inside loops: a value read after the loop (a variable it accumulates) can be cached"
            }
            CullReason::NonUniformBranch => {
                "the work is inside branches on per-pixel values: compute both sides and `select`, or branch on a uniform"
            }
            CullReason::Discontinuous => {
                "the work reaches the color only through comparisons, rounding or conversions, which reprojection would blur"
            }
            CullReason::Derivative => {
                "the work feeds derivatives or implicit-LOD texture samples, which need neighbouring pixels"
            }
            CullReason::PayloadType => {
                "the values are not f32/f16 data of at most 4 components, so no cache texture holds them"
            }
            CullReason::Trivial => {
                "every expression is cheaper than a cache lookup: there is nothing worth caching"
            }
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            CullReason::InLoop => "in-loop",
            CullReason::NonUniformBranch => "non-uniform-branch",
            CullReason::Discontinuous => "discontinuous",
            CullReason::Derivative => "derivative",
            CullReason::PayloadType => "payload-type",
            CullReason::Trivial => "trivial",
        }
    }
}

impl std::fmt::Display for CullReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One candidate node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub id: u32,
    pub cacheable: bool,
    pub reason: Option<CullReason>,
    #[serde(rename = "type")]
    pub ty: String,
    /// Number of f32 values of the payload (0 when it is not f32 data).
    pub components: u32,
    /// Static cost of the node's subtree (see `docs/COST.md`).
    pub cost: f64,
    /// Part of `cost` the rest of the shader still computes when this node is cached.
    pub overlap: f64,
    /// 1-based source position; 0 when the expression has no source span (generated).
    pub line: u32,
    pub col: u32,
    pub text: String,
    /// Where the helper this expression came from was called in the entry point, if inlined.
    pub call_line: Option<u32>,
    pub call_col: Option<u32>,
    /// True for the output color.
    pub root: bool,
    /// The expression in the normalized function (not serialized).
    #[serde(skip)]
    pub handle: Option<Handle<Expression>>,
}

impl Node {
    /// Static saving of caching this node: its cost less what the rest of the shader still
    /// computes (its overlap). What `analyze` prunes candidates by and `nodes` lists.
    pub fn saving(&self) -> f64 {
        (self.cost - self.overlap).max(0.0)
    }
}

/// All candidate nodes of one entry point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodeTable {
    /// Always [`NODES_SCHEMA`] (absent before version 2: read as `reproj.nodes`).
    #[serde(default = "nodes_schema")]
    pub schema: String,
    /// Schema version of this JSON object.
    pub version: u32,
    pub shader: String,
    pub entry: String,
    /// Static cost of the whole shader.
    pub total_cost: f64,
    pub nodes: Vec<Node>,
}

/// Name of the [`NodeTable`] JSON schema (`reproj nodes --json`).
pub const NODES_SCHEMA: &str = "reproj.nodes";

/// Version of the [`NodeTable`] JSON schema (2: `schema` added).
pub const NODES_VERSION: u32 = 2;

fn nodes_schema() -> String {
    NODES_SCHEMA.into()
}

impl NodeTable {
    pub fn root(&self) -> &Node {
        self.nodes
            .iter()
            .find(|n| n.root)
            .expect("the root is always a node")
    }

    pub fn cacheable(&self) -> impl Iterator<Item = &Node> {
        self.nodes.iter().filter(|n| n.cacheable)
    }

    /// Look a node up by id.
    pub fn get(&self, id: u32) -> Option<&Node> {
        self.nodes.iter().find(|n| n.id == id)
    }
}

/// Enumerate, cull and cost the nodes of a normalized shader. Phases: where each expression is
/// evaluated ([`Walk`]), the dependency edges, the costs over the reachability graph, continuity
/// and what feeds derivatives, then one [`Node`] per float-valued expression.
pub fn enumerate(shader: &Shader, norm: &Normalized) -> NodeTable {
    let fun = norm.function();
    let info = norm.function_info();
    let types = &norm.module.types;
    let walked = Walk::function(fun, info);
    let deps = dependencies(fun, info, types, &walked.stores);
    let costs = Costs::new(fun, info, types, norm.root, &walked, &deps);
    let flags = Flags {
        continuous: continuous_from(norm.root, &deps),
        feeds_derivative: feeds_derivatives(fun, &deps),
    };
    let lines = LineIndex::new(&shader.source);
    let mut nodes = Vec::new();
    for (h, e) in fun.expressions.iter() {
        let inner = info[h].ty.inner_with(types);
        let Some(ty) = node_type(inner, types) else {
            continue;
        };
        let is_root = h == norm.root;
        let (cost, overlap) = costs.of(h, is_root);
        let components = payload_components(inner);
        let place = walked.places.get(&h).copied().unwrap_or_default();
        let reason = cull_reason(components, cost, place, &flags, h);
        let (line, col, text) = source_position(shader, &lines, fun, h, e);
        let call = norm.call_site.get(&h).map(|s| {
            let (l, c, _) = span_text(shader, &lines, *s);
            (l, c)
        });
        nodes.push(Node {
            id: nodes.len() as u32,
            cacheable: reason.is_none(),
            reason,
            ty,
            components,
            cost: cost + 0.0,
            overlap: overlap + 0.0,
            line,
            col,
            text,
            call_line: call.map(|c| c.0),
            call_col: call.map(|c| c.1),
            root: is_root,
            handle: Some(h),
        });
    }
    place_leaves(shader, &lines, &mut nodes, &norm.module, fun);
    NodeTable {
        schema: NODES_SCHEMA.into(),
        version: NODES_VERSION,
        shader: shader.path.file_name().map_or_else(
            || shader.path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        ),
        entry: norm.entry.clone(),
        total_cost: costs.total_cost,
        nodes,
    }
}

/// Set of expressions an expression depends on (for tests and the instancer).
pub fn subtree(fun: &naga::Function, h: Handle<Expression>) -> HashSet<Handle<Expression>> {
    let mut seen = HashSet::new();
    let mut stack = vec![h];
    while let Some(x) = stack.pop() {
        if seen.insert(x) {
            stack.extend(ir::operands(&fun.expressions[x]));
        }
    }
    seen
}
