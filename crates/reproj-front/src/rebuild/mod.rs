//! Rebuilding a function in order, with a handle map.
//!
//! naga requires every expression to be emitted before it is used, so reproj never edits a function
//! in place: it walks the source function's statements in order and appends translated expressions
//! and statements to a new [`naga::Function`]. One walker serves every rewrite:
//!
//! - the front end's normalization ([`Mode::Normalize`]): inline calls, turn module-scope
//!   `var<private>` globals into locals, forward local loads in straight-line code, share identical
//!   pure expressions;
//! - plain copies ([`Mode::Copy`]) that keep only live code ([`crate::liveness`]), replace one
//!   expression by another, or stop after one expression and return it (the instancer's passes),
//!   or replace expressions by constants (code simplification, `reproj compare`).
//!
//! This file holds the rewrites and the walker's state; `walk.rs` walks statements (control flow,
//! loop-carried kills, inlined calls), `expr.rs` appends and translates expressions, `inserts.rs`
//! makes what a rewrite puts in place of a source expression.

use std::collections::{HashMap, HashSet};

use naga::{Block, Expression, Function, Handle, LocalVariable, Span, Statement};

use crate::ir;
use crate::shader::FrontError;

/// Whether calls are inlined and expressions shared (internal: chosen by the [`Rewrite`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Inline calls, forward loads, share identical pure expressions.
    Normalize,
    /// Copy as is (calls are an error: run on normalized functions).
    Copy,
}

/// What one [`rebuild`] does to the function it copies.
#[derive(Debug, Clone)]
pub enum Rewrite<'a> {
    /// Inline every call, turn module-scope `var<private>` globals into locals, forward loads in
    /// straight-line code, share identical pure expressions (the front end's normalization).
    Normalize,
    /// Copy only the live expressions and statements (of a call-free function).
    KeepLive(&'a crate::liveness::Liveness),
    /// Copy, reading one expression from the cache instead of computing it.
    CacheRead(CacheRead),
    /// Copy up to one expression and return it (the recompute slice).
    StopAfter(StopAfter),
    /// Copy, with each listed expression replaced by a constant (code simplification).
    Constants(&'a [Constant]),
}

/// Replacement of one source expression of the top-level function by a constant `f32` scalar or
/// `vecN<f32>`: the first `components` of `value`.
#[derive(Debug, Clone)]
pub struct Constant {
    /// The expression to replace (source handle).
    pub target: Handle<Expression>,
    pub value: [f32; 4],
    /// 1 (an `f32`) to 4.
    pub components: u32,
    /// The `vecN<f32>` type of the expression (`None` for a scalar).
    pub vector: Option<Handle<naga::Type>>,
}

/// One cached expression's place in the payload: `components` floats from `offset`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slot {
    /// The expression (source handle).
    pub target: Handle<Expression>,
    pub offset: u32,
    pub components: u32,
}

impl Slot {
    /// Pack expressions of the given float counts one after the other from offset 0.
    pub fn pack(nodes: &[(Handle<Expression>, u32)]) -> Vec<Slot> {
        let mut offset = 0;
        nodes
            .iter()
            .map(|&(target, components)| {
                let slot = Slot {
                    target,
                    offset,
                    components,
                };
                offset += components;
                slot
            })
            .collect()
    }
}

/// Replacement of source expressions by their slots of the cached payload.
#[derive(Debug, Clone)]
pub struct CacheRead {
    /// The expressions to replace; their floats fit in the payload's four.
    pub slots: Vec<Slot>,
    pub source: CacheSource,
}

/// Where [`CacheRead`] finds the payload (a `vec4<f32>`).
#[derive(Debug, Clone, Copy)]
pub enum CacheSource {
    /// `textureLoad(image, vec2<i32>(position.xy), 0)`: the current cache at this fragment's pixel.
    Texture {
        image: Handle<naga::GlobalVariable>,
        /// The `@builtin(position)` value: entry argument index and, if the argument is a struct,
        /// the member index.
        position: (u32, Option<u32>),
    },
    /// A function argument of the rebuilt function (the fused strategy passes the payload in).
    Argument(u32),
}

/// Stop once every slot's expression is computed and return them packed in a zero-padded
/// `vec4<f32>` (the recompute pass). With several slots, each must be computed outside branches.
#[derive(Debug, Clone)]
pub struct StopAfter {
    pub slots: Vec<Slot>,
    pub vec4: Handle<naga::Type>,
}

/// The rewrite as flags the walker tests.
#[derive(Debug, Clone, Default)]
struct Opts<'a> {
    live: Option<&'a crate::liveness::Liveness>,
    cache_read: Option<CacheRead>,
    stop_after: Option<StopAfter>,
    constants: &'a [Constant],
}

/// The rebuilt function and its side tables.
#[derive(Debug)]
pub struct Rebuilt {
    pub function: Function,
    /// Value of the last top-level `return` of the function, if any.
    pub root: Option<Handle<Expression>>,
    /// For expressions that came from an inlined helper: the span of the outermost call.
    pub call_site: HashMap<Handle<Expression>, Span>,
    /// Source handle → new handle, for the top-level function only.
    pub map: Vec<Option<Handle<Expression>>>,
}

/// `rewrite`, then [`Rewrite::KeepLive`] on the result: the rewritten function with its dead code
/// removed. The side tables map from `fun` to the final function.
pub fn rebuild_live(
    module: &naga::Module,
    fun: &Function,
    rewrite: &Rewrite,
) -> Result<Rebuilt, FrontError> {
    let first = rebuild(module, fun, rewrite)?;
    let live = crate::liveness::liveness(&first.function);
    let second = rebuild(module, &first.function, &Rewrite::KeepLive(&live))?;
    let through = |h: Handle<Expression>| second.map.get(h.index()).copied().flatten();
    let mut call_site = HashMap::new();
    for (old, span) in &first.call_site {
        if let Some(new) = through(*old) {
            call_site.entry(new).or_insert(*span);
        }
    }
    Ok(Rebuilt {
        function: second.function,
        root: second.root,
        call_site,
        map: first.map.iter().map(|m| m.and_then(through)).collect(),
    })
}

/// Rebuild the function `fun` of `module` in order under `rewrite`.
pub fn rebuild(
    module: &naga::Module,
    fun: &Function,
    rewrite: &Rewrite,
) -> Result<Rebuilt, FrontError> {
    let (mode, opts) = match rewrite {
        Rewrite::Normalize => (Mode::Normalize, Opts::default()),
        Rewrite::KeepLive(live) => (
            Mode::Copy,
            Opts {
                live: Some(live),
                ..Default::default()
            },
        ),
        Rewrite::CacheRead(c) => (
            Mode::Copy,
            Opts {
                cache_read: Some(c.clone()),
                ..Default::default()
            },
        ),
        Rewrite::StopAfter(s) => (
            Mode::Copy,
            Opts {
                stop_after: Some(s.clone()),
                ..Default::default()
            },
        ),
        Rewrite::Constants(c) => (
            Mode::Copy,
            Opts {
                constants: c,
                ..Default::default()
            },
        ),
    };
    let opts = &opts;
    let mut out = Out {
        module,
        mode,
        opts,
        fun: Function {
            name: fun.name.clone(),
            arguments: fun.arguments.clone(),
            result: fun.result.clone(),
            local_variables: naga::Arena::new(),
            expressions: naga::Arena::new(),
            named_expressions: Default::default(),
            body: Block::new(),
            diagnostic_filter_leaf: fun.diagnostic_filter_leaf,
        },
        emitter: naga::proc::Emitter::default(),
        blocks: vec![Block::new()],
        cse: vec![HashMap::new()],
        pre_cse: HashMap::new(),
        env: HashMap::new(),
        privates: HashMap::new(),
        stored_log: Vec::new(),
        call_site: HashMap::new(),
        root: None,
        stmt_index: 0,
        stopped: false,
        stop_values: opts
            .stop_after
            .as_ref()
            .map_or(Vec::new(), |s| vec![None; s.slots.len()]),
        depth: 0,
        calls: 0,
    };
    if let Some(stop) = &opts.stop_after {
        out.fun.result = Some(naga::FunctionResult {
            ty: stop.vec4,
            binding: Some(naga::Binding::Location {
                location: 0,
                interpolation: None,
                sampling: None,
                blend_src: None,
                per_primitive: false,
            }),
        });
    }
    out.emitter.start(&out.fun.expressions);
    let mut ctx = Ctx::new(fun, true, None, Vec::new());
    // Locals of the top-level function: created up front when normalizing (their initial values
    // become stores), on first use when copying (so dead variables disappear).
    ctx.locals = vec![None; fun.local_variables.len()];
    if mode == Mode::Normalize {
        for (h, _) in fun.local_variables.iter() {
            out.local(&mut ctx, h);
        }
    }
    if mode == Mode::Normalize {
        out.init_privates();
    }
    out.init_locals(&mut ctx, fun)?;
    out.walk_block(&mut ctx, &fun.body)?;
    if let (true, Some(stop), None) = (out.stopped, &opts.stop_after, out.root) {
        // The node was inside a branch: the other paths return zero.
        let z = out.append(Expression::ZeroValue(stop.vec4), Span::UNDEFINED);
        out.push_stmt(Statement::Return { value: Some(z) }, Span::UNDEFINED);
    }
    out.flush();
    let body = out.blocks.pop().unwrap();
    out.fun.body = body;
    Ok(Rebuilt {
        function: out.fun,
        root: out.root,
        call_site: out.call_site,
        map: ctx.map,
    })
}

struct Ctx<'f> {
    fun: &'f Function,
    map: Vec<Option<Handle<Expression>>>,
    locals: Vec<Option<Handle<LocalVariable>>>,
    /// Values of the arguments of an inlined call.
    args: Vec<Handle<Expression>>,
    is_top: bool,
    call_site: Option<Span>,
    /// Return value of an inlined call.
    ret: Option<Handle<Expression>>,
}

impl<'f> Ctx<'f> {
    fn new(
        fun: &'f Function,
        is_top: bool,
        call_site: Option<Span>,
        args: Vec<Handle<Expression>>,
    ) -> Self {
        Ctx {
            fun,
            map: vec![None; fun.expressions.len()],
            locals: Vec::new(),
            args,
            is_top,
            call_site,
            ret: None,
        }
    }
}

struct Out<'m, 'o> {
    module: &'m naga::Module,
    mode: Mode,
    opts: &'o Opts<'o>,
    fun: Function,
    emitter: naga::proc::Emitter,
    blocks: Vec<Block>,
    cse: Vec<HashMap<String, Handle<Expression>>>,
    pre_cse: HashMap<String, Handle<Expression>>,
    env: HashMap<Handle<LocalVariable>, Handle<Expression>>,
    /// Module-scope `var<private>` globals and the locals that replace them when normalizing.
    privates: HashMap<Handle<naga::GlobalVariable>, Handle<LocalVariable>>,
    stored_log: Vec<Handle<LocalVariable>>,
    call_site: HashMap<Handle<Expression>, Span>,
    root: Option<Handle<Expression>>,
    stmt_index: usize,
    stopped: bool,
    /// The values of [`StopAfter`]'s slots computed so far.
    stop_values: Vec<Option<Handle<Expression>>>,
    depth: usize,
    /// Depth of inlined calls (with `depth`, bounded by [`MAX_NESTING`]).
    calls: usize,
}

/// Most nested blocks plus inlined helper calls the walker follows. It recurses on both (about
/// 12 KiB of stack per level in a debug build): a chain of 300 helpers overflowed a 2 MiB thread.
const MAX_NESTING: usize = 64;

fn unsupported(span: Span, what: impl Into<String>) -> FrontError {
    FrontError::UnsupportedAt {
        span,
        what: what.into(),
    }
}

mod expr;
mod inserts;
mod walk;
