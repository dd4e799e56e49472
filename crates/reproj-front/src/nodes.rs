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

use std::collections::{HashMap, HashSet};

use naga::{Block, Expression, Handle, Statement, TypeInner};
use serde::{Deserialize, Serialize};

pub use crate::cost::DEFAULT_TRIP_COUNT;
use crate::cost::{op_cost, trip_count};
use crate::graph::{Reach, dominators};
use crate::ir;
use crate::normalize::Normalized;
use crate::parse::Shader;

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

/// Where an expression is evaluated.
#[derive(Debug, Clone, Copy, Default)]
struct Place {
    in_loop: bool,
    non_uniform: bool,
    /// Product of the enclosing loops' trip counts.
    weight: f64,
}

struct StoreInfo {
    value: Handle<Expression>,
    pointer: Handle<Expression>,
    control: Vec<Handle<Expression>>,
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

/// Dependency edges of each expression: `(dependency, discontinuous)`, its operands and, for a
/// load, every store to its local with the pointer and the control that guards it.
fn dependencies(
    fun: &naga::Function,
    info: &naga::valid::FunctionInfo,
    types: &naga::UniqueArena<naga::Type>,
    stores: &HashMap<Handle<naga::LocalVariable>, Vec<StoreInfo>>,
) -> Vec<Vec<(Handle<Expression>, bool)>> {
    let n = fun.expressions.len();
    let mut deps: Vec<Vec<(Handle<Expression>, bool)>> = vec![Vec::new(); n];
    let is_float = |h: Handle<Expression>| {
        matches!(
            info[h].ty.inner_with(types).scalar_kind(),
            Some(naga::ScalarKind::Float)
        )
    };
    for (h, e) in fun.expressions.iter() {
        let ops = ir::operands(e);
        let disc = ir::discontinuous_edges(e, is_float(h));
        deps[h.index()].extend(ops.into_iter().zip(disc));
        if let Expression::Load { pointer } = *e
            && let Some(v) = ir::root_local(&fun.expressions, pointer)
        {
            for s in stores.get(&v).into_iter().flatten() {
                deps[h.index()].push((s.value, false));
                deps[h.index()].push((s.pointer, true));
                deps[h.index()].extend(s.control.iter().map(|c| (*c, true)));
            }
        }
    }
    deps
}

/// The costs of every expression's subtree, from one reachability graph over the dependency
/// edges (see `crate::graph`). The weights are whole numbers, so sums in any order are exact and
/// equal the old per-node ones.
struct Costs {
    reach: Reach,
    /// Prefix sums over `reach`'s positions of every expression's weight.
    all_weight: Vec<f64>,
    /// The same, of the weight of what the output needs.
    needed_weight: Vec<f64>,
    /// What only each expression leads to from the output and the kill conditions.
    dominated: Vec<f64>,
    /// Whether the output (or a kill condition) needs each expression.
    total_closure: Vec<bool>,
    /// The cost of everything the output needs.
    total_cost: f64,
}

impl Costs {
    /// What each expression reaches, and what only it leads to from the output and the kill
    /// conditions (a virtual vertex `n` stands for them).
    fn new(
        fun: &naga::Function,
        info: &naga::valid::FunctionInfo,
        types: &naga::UniqueArena<naga::Type>,
        root: Handle<Expression>,
        walked: &Walk,
        deps: &[Vec<(Handle<Expression>, bool)>],
    ) -> Costs {
        let n = fun.expressions.len();
        let weight: Vec<f64> = fun
            .expressions
            .iter()
            .map(|(h, e)| {
                let mult = walked.places.get(&h).map_or(1.0, |p| p.weight);
                op_cost(e, info[h].ty.inner_with(types)) * mult
            })
            .collect();
        let outputs = n as u32;
        let mut succ: Vec<Vec<u32>> = deps
            .iter()
            .map(|d| d.iter().map(|&(h, _)| h.index() as u32).collect())
            .collect();
        succ.push(
            std::iter::once(root)
                .chain(walked.kills.iter().copied())
                .map(|h| h.index() as u32)
                .collect(),
        );
        let reach = Reach::new(&succ, &[outputs]);
        let mut total_closure = vec![false; n + 1];
        for &(s, e) in reach.runs(outputs) {
            for &v in &reach.by_position()[s as usize..e as usize] {
                total_closure[v as usize] = true;
            }
        }
        total_closure.truncate(n);
        let total_cost: f64 = (0..n)
            .filter(|&i| total_closure[i])
            .map(|i| weight[i])
            .sum();
        // Prefix sums over positions: of the weight, and of the weight of what the output needs.
        let prefix = |keep: &dyn Fn(usize) -> bool| -> Vec<f64> {
            let mut sums = Vec::with_capacity(n + 2);
            sums.push(0.0);
            let mut acc = 0.0;
            for &v in reach.by_position() {
                let v = v as usize;
                if v < n && keep(v) {
                    acc += weight[v];
                }
                sums.push(acc);
            }
            sums
        };
        let all_weight = prefix(&|_| true);
        let needed_weight = prefix(&|v| total_closure[v]);
        let mut dominated = dominators(&succ, outputs).subtree_sums(&{
            let mut w = weight.clone();
            w.push(0.0);
            w
        });
        dominated.truncate(n);
        Costs {
            reach,
            all_weight,
            needed_weight,
            dominated,
            total_closure,
            total_cost,
        }
    }

    /// The cost of `h`'s subtree, and its overlap: the part of the subtree the rest still needs,
    /// all of it but what only `h` leads to (when the output needs `h`), or what the output
    /// needs (when it does not).
    fn of(&self, h: Handle<Expression>, is_root: bool) -> (f64, f64) {
        let v = h.index() as u32;
        let cost = self.reach.sum(v, &self.all_weight);
        let overlap = if is_root {
            0.0
        } else if self.total_closure[h.index()] {
            cost - self.dominated[h.index()]
        } else {
            self.reach.sum(v, &self.needed_weight)
        };
        (cost, overlap)
    }
}

/// Per expression: continuous from the root, and feeding a derivative.
struct Flags {
    continuous: Vec<bool>,
    feeds_derivative: Vec<bool>,
}

/// The expressions the root depends on through continuous edges only.
fn continuous_from(
    root: Handle<Expression>,
    deps: &[Vec<(Handle<Expression>, bool)>],
) -> Vec<bool> {
    let mut continuous = vec![false; deps.len()];
    let mut stack = vec![root];
    while let Some(h) = stack.pop() {
        if continuous[h.index()] {
            continue;
        }
        continuous[h.index()] = true;
        for &(d, disc) in &deps[h.index()] {
            if !disc && !continuous[d.index()] {
                stack.push(d);
            }
        }
    }
    continuous
}

/// What feeds explicit derivatives, and the coordinates of samples whose level of detail the
/// hardware derives from them (`textureSample`, `textureSampleBias`): in the shade pass a cached
/// value comes from a texel per pixel, and helper lanes at silhouettes read the background.
fn feeds_derivatives(fun: &naga::Function, deps: &[Vec<(Handle<Expression>, bool)>]) -> Vec<bool> {
    let mut feeds_derivative = vec![false; deps.len()];
    let mut stack: Vec<Handle<Expression>> = fun
        .expressions
        .iter()
        .filter_map(|(_, e)| match *e {
            Expression::Derivative { expr, .. } => Some(expr),
            Expression::ImageSample {
                coordinate,
                level: naga::SampleLevel::Auto | naga::SampleLevel::Bias(_),
                ..
            } => Some(coordinate),
            _ => None,
        })
        .collect();
    while let Some(h) = stack.pop() {
        if !std::mem::replace(&mut feeds_derivative[h.index()], true) {
            stack.extend(deps[h.index()].iter().map(|&(d, _)| d));
        }
    }
    feeds_derivative
}

/// The f32 components of a payload of this type: 1 to 4, or 0 when it cannot be one.
fn payload_components(inner: &TypeInner) -> u32 {
    match inner {
        TypeInner::Scalar(s) if s.width == 4 && s.kind == naga::ScalarKind::Float => 1,
        TypeInner::Vector { size, scalar }
            if scalar.width == 4 && scalar.kind == naga::ScalarKind::Float =>
        {
            *size as u32
        }
        _ => 0,
    }
}

/// Why the expression `h` cannot be cached, the first reason in this order; `None` when it can.
fn cull_reason(
    components: u32,
    cost: f64,
    place: Place,
    flags: &Flags,
    h: Handle<Expression>,
) -> Option<CullReason> {
    // Weights are never negative.
    let trivial = cost == 0.0;
    if components == 0 {
        Some(CullReason::PayloadType)
    } else if trivial {
        Some(CullReason::Trivial)
    } else if place.in_loop {
        Some(CullReason::InLoop)
    } else if place.non_uniform {
        Some(CullReason::NonUniformBranch)
    } else if flags.feeds_derivative[h.index()] {
        Some(CullReason::Derivative)
    } else if !flags.continuous[h.index()] {
        Some(CullReason::Discontinuous)
    } else {
        None
    }
}

/// Line, column and source text of the expression `h`, from its span or, where the front end
/// left none, from the variable it loads or its operands.
fn source_position(
    shader: &Shader,
    lines: &LineIndex,
    fun: &naga::Function,
    h: Handle<Expression>,
    e: &Expression,
) -> (u32, u32, String) {
    let span = fun.expressions.get_span(h);
    match (span.is_defined(), e) {
        // Loads made by the front end (`x += ...`, a read after a loop) have no span: name the
        // variable instead.
        (false, Expression::Load { pointer }) => match ir::root_local(&fun.expressions, *pointer) {
            Some(v) => {
                let (l, c, _) = span_text(shader, lines, fun.local_variables.get_span(v));
                (
                    l,
                    c,
                    fun.local_variables[v].name.clone().unwrap_or_default(),
                )
            }
            None => (0, 0, String::new()),
        },
        (false, _) => operand_span(shader, &fun.expressions, e)
            .map_or((0, 0, String::new()), |s| span_text(shader, lines, s)),
        _ => span_text(shader, lines, span),
    }
}

/// A span for an expression the front end left without one (naga's GLSL reader gives built-in
/// calls none): the union of its operands' spans, widened to the call around them when the text
/// before the first operand is `name(`, so that `mix(a, b, t)` reads as written.
fn operand_span(
    shader: &Shader,
    exprs: &naga::Arena<Expression>,
    e: &Expression,
) -> Option<naga::Span> {
    let text = |s: &naga::Span| s.to_range().and_then(|r| shader.source.get(r));
    // Operands spanned where they are used (a constant's span is its declaration, elsewhere).
    let one_expression = |s: &naga::Span| text(s).is_some_and(|t| !t.contains([';', '{', '}']));
    let spans: Vec<naga::Span> = ir::operands(e)
        .into_iter()
        .map(|o| exprs.get_span(o))
        .filter(|s| s.is_defined() && one_expression(s))
        .collect();
    let union = spans.iter().copied().reduce(|mut a, b| {
        a.subsume(b);
        a
    })?;
    let span = if one_expression(&union) {
        union
    } else {
        // Operands far apart: the last one, nearest the use.
        *spans
            .iter()
            .max_by_key(|s| s.to_range().map_or(0, |r| r.start))?
    };
    let range = span.to_range()?;
    let before = shader.source.get(..range.start)?.trim_end();
    let Some(open) = before.strip_suffix('(') else {
        return Some(span);
    };
    let name_len = open
        .bytes()
        .rev()
        .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_')
        .count();
    if name_len == 0 {
        return Some(span);
    }
    // The name alone: `span_text` extends a call's name to its closing parenthesis.
    let start = open.len() - name_len;
    Some(naga::Span::new(start as u32, open.len() as u32))
}

/// The start of every line of a text, to turn byte offsets into lines without rescanning the
/// text (naga's `Span::location` counts the lines before the span every time).
struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    fn new(text: &str) -> LineIndex {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        LineIndex { starts }
    }

    /// 1-based line and byte column of `offset`, as `naga::Span::location` gives them.
    fn location(&self, offset: usize) -> (u32, u32) {
        let line = self.starts.partition_point(|&s| s <= offset);
        let start = self.starts[line - 1];
        (line as u32, (offset - start) as u32 + 1)
    }
}

fn span_text(shader: &Shader, lines: &LineIndex, span: naga::Span) -> (u32, u32, String) {
    if !span.is_defined() || span.to_range().is_none_or(|r| r.end > shader.source.len()) {
        return (0, 0, String::new());
    }
    let (line_number, line_position) = lines.location(span.to_range().unwrap().start);
    let mut range = span.to_range().unwrap();
    // Calls are spanned by their name only: extend to the closing parenthesis.
    let src = shader.source.as_bytes();
    let is_ident = shader.source[range.clone()]
        .bytes()
        .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'<' || b == b'>');
    if is_ident {
        let mut i = range.end;
        while i < src.len() && src[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < src.len() && src[i] == b'(' {
            let mut depth = 0usize;
            while i < src.len() {
                match src[i] {
                    b'(' => depth += 1,
                    b')' => {
                        depth -= 1;
                        if depth == 0 {
                            range.end = i + 1;
                            break;
                        }
                    }
                    _ => {}
                }
                i += 1;
            }
        }
    }
    let text = shader.source[range]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    (line_number, line_position, text)
}

/// WGSL name of a node's type (naga's own printer), or `None` if expressions of this type are not
/// nodes (only f32/f16 scalars, vectors and matrices are).
fn node_type(inner: &TypeInner, types: &naga::UniqueArena<naga::Type>) -> Option<String> {
    use naga::common::wgsl::TypeContext;
    let float = |s: naga::Scalar| match (s.kind, s.width) {
        (naga::ScalarKind::Float, 2 | 4) => Some(s),
        (naga::ScalarKind::AbstractFloat, _) => Some(naga::Scalar::F32),
        _ => None,
    };
    let inner = match *inner {
        TypeInner::Scalar(s) => TypeInner::Scalar(float(s)?),
        TypeInner::Vector { size, scalar } => TypeInner::Vector {
            size,
            scalar: float(scalar)?,
        },
        TypeInner::Matrix {
            columns,
            rows,
            scalar,
        } => TypeInner::Matrix {
            columns,
            rows,
            scalar: float(scalar)?,
        },
        _ => return None,
    };
    let mut name = String::new();
    types.write_type_inner(&inner, &mut name).ok()?;
    Some(name)
}

/// Conditions that decide whether the loop keeps going: `break_if` and the conditions of `if`s
/// that break or continue.
fn loop_control(body: &Block, out: &mut Vec<Handle<Expression>>) {
    for stmt in body.iter() {
        match stmt {
            Statement::If {
                condition,
                accept,
                reject,
            } => {
                if accept
                    .iter()
                    .chain(reject.iter())
                    .any(|s| matches!(s, Statement::Break | Statement::Continue))
                {
                    out.push(*condition);
                }
                loop_control(accept, out);
                loop_control(reject, out);
            }
            Statement::Block(b) => loop_control(b, out),
            _ => {}
        }
    }
}

/// Where each expression of a function is evaluated, the stores to its locals (with the
/// conditions that guard them), and the conditions under which it discards.
struct Walk<'a> {
    fun: &'a naga::Function,
    info: &'a naga::valid::FunctionInfo,
    /// The conditions of the statements around the one being walked.
    control: Vec<Handle<Expression>>,
    places: HashMap<Handle<Expression>, Place>,
    stores: HashMap<Handle<naga::LocalVariable>, Vec<StoreInfo>>,
    /// The conditions around each `discard`.
    kills: Vec<Handle<Expression>>,
}

impl<'a> Walk<'a> {
    /// Walk the function's body.
    fn function(fun: &'a naga::Function, info: &'a naga::valid::FunctionInfo) -> Walk<'a> {
        let mut w = Walk {
            fun,
            info,
            control: Vec::new(),
            places: HashMap::new(),
            stores: HashMap::new(),
            kills: Vec::new(),
        };
        w.block(
            &fun.body,
            Place {
                weight: 1.0,
                ..Place::default()
            },
        );
        w
    }

    fn block(&mut self, block: &Block, place: Place) {
        for stmt in block.iter() {
            match stmt {
                Statement::Emit(range) => {
                    for h in range.clone() {
                        self.places.insert(h, place);
                    }
                }
                Statement::Store { pointer, value } => {
                    if let Some(v) = ir::root_local(&self.fun.expressions, *pointer) {
                        self.stores.entry(v).or_default().push(StoreInfo {
                            value: *value,
                            pointer: *pointer,
                            control: self.control.clone(),
                        });
                    }
                }
                Statement::Kill => self.kills.extend(self.control.iter().copied()),
                Statement::Block(b) => self.block(b, place),
                Statement::If {
                    condition,
                    accept,
                    reject,
                } => {
                    let inner = self.branch(place, *condition);
                    self.control.push(*condition);
                    self.block(accept, inner);
                    self.block(reject, inner);
                    self.control.pop();
                }
                Statement::Switch { selector, cases } => {
                    let inner = self.branch(place, *selector);
                    self.control.push(*selector);
                    for c in cases {
                        self.block(&c.body, inner);
                    }
                    self.control.pop();
                }
                Statement::Loop {
                    body,
                    continuing,
                    break_if,
                } => {
                    let inner = Place {
                        in_loop: true,
                        weight: place.weight * trip_count(self.fun, body),
                        ..place
                    };
                    let mut ctl = Vec::new();
                    loop_control(body, &mut ctl);
                    ctl.extend(*break_if);
                    let depth = self.control.len();
                    self.control.extend(ctl);
                    self.block(body, inner);
                    self.block(continuing, inner);
                    self.control.truncate(depth);
                }
                _ => {}
            }
        }
    }

    /// The place inside a branch on `condition`: non-uniform when the condition is.
    fn branch(&self, place: Place, condition: Handle<Expression>) -> Place {
        let nu = self.info[condition].uniformity.non_uniform_result.is_some();
        Place {
            non_uniform: place.non_uniform || nu,
            ..place
        }
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
