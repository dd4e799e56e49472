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

use std::collections::{HashMap, HashSet};

use naga::{Block, Expression, Function, Handle, LocalVariable, Span, Statement};

use crate::ir;
use crate::parse::FrontError;

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

impl Out<'_, '_> {
    fn normalize(&self) -> bool {
        self.mode == Mode::Normalize
    }

    fn flush(&mut self) {
        if let Some((stmt, span)) = self.emitter.finish(&self.fun.expressions) {
            self.blocks.last_mut().unwrap().push(stmt, span);
        }
    }

    fn push_stmt(&mut self, stmt: Statement, span: Span) {
        self.flush();
        self.blocks.last_mut().unwrap().push(stmt, span);
        self.emitter.start(&self.fun.expressions);
    }

    fn enter(&mut self) {
        self.flush();
        self.blocks.push(Block::new());
        self.cse.push(HashMap::new());
        self.depth += 1;
        self.emitter.start(&self.fun.expressions);
    }

    fn exit(&mut self) -> Block {
        self.flush();
        self.cse.pop();
        self.depth -= 1;
        let b = self.blocks.pop().unwrap();
        self.emitter.start(&self.fun.expressions);
        b
    }

    /// Append an expression, sharing an identical earlier one when that is safe.
    fn append(&mut self, expr: Expression, span: Span) -> Handle<Expression> {
        let pre = expr.needs_pre_emit();
        let shareable = self.normalize()
            && !matches!(
                expr,
                Expression::Load { .. }
                    | Expression::CallResult(_)
                    | Expression::AtomicResult { .. }
                    | Expression::WorkGroupUniformLoadResult { .. }
                    | Expression::SubgroupBallotResult
                    | Expression::SubgroupOperationResult { .. }
                    | Expression::RayQueryProceedResult
            );
        let key = shareable.then(|| format!("{expr:?}"));
        if let Some(k) = &key {
            if pre {
                if let Some(&h) = self.pre_cse.get(k) {
                    return h;
                }
            } else {
                for scope in self.cse.iter().rev() {
                    if let Some(&h) = scope.get(k) {
                        return h;
                    }
                }
            }
        }
        let h = if pre {
            self.flush();
            let h = self.fun.expressions.append(expr, span);
            self.emitter.start(&self.fun.expressions);
            h
        } else {
            self.fun.expressions.append(expr, span)
        };
        if let Some(k) = key {
            if pre {
                self.pre_cse.insert(k, h);
            } else {
                self.cse.last_mut().unwrap().insert(k, h);
            }
        }
        h
    }

    fn is_live_expr(&self, h: Handle<Expression>) -> bool {
        self.opts.live.is_none_or(|l| l.exprs.contains(&h))
    }

    fn init_locals(&mut self, ctx: &mut Ctx, fun: &Function) -> Result<(), FrontError> {
        if !self.normalize() {
            // Copy mode keeps constant initializers as they are.
            for (h, var) in fun.local_variables.iter() {
                if let Some(init) = var.init {
                    let v = self.translate(ctx, init)?;
                    let nv = self.local(ctx, h);
                    self.fun.local_variables.get_mut(nv).init = Some(v);
                }
            }
            return Ok(());
        }
        for (h, var) in fun.local_variables.iter() {
            let nv = self.local(ctx, h);
            let span = fun.local_variables.get_span(h);
            let value = match var.init {
                Some(init) => self.translate(ctx, init)?,
                None => self.append(Expression::ZeroValue(var.ty), span),
            };
            let ptr = self.append(Expression::LocalVariable(nv), span);
            self.store(ptr, value, span);
        }
        Ok(())
    }

    /// Normalizing: every module-scope `var<private>` becomes a local of the entry point, stored
    /// its initial value first. Private variables live for one invocation and the normalized entry
    /// point is the only function left, so this keeps the meaning; it lets the load forwarding see
    /// through the pattern naga's GLSL and SPIR-V front ends produce (inputs copied into private
    /// globals, the real `main` called from a wrapper entry point, the output read back).
    fn init_privates(&mut self) {
        for (g, var) in self.module.global_variables.iter() {
            if var.space != naga::AddressSpace::Private {
                continue;
            }
            let span = self.module.global_variables.get_span(g);
            let local = self.fun.local_variables.append(
                LocalVariable {
                    name: var.name.clone(),
                    ty: var.ty,
                    init: None,
                },
                span,
            );
            self.privates.insert(g, local);
            let value = match var.init {
                Some(init) => self.global_expression(init),
                None => self.append(Expression::ZeroValue(var.ty), span),
            };
            let ptr = self.append(Expression::LocalVariable(local), span);
            self.store(ptr, value, span);
        }
    }

    /// A module-scope constant expression (a private global's initializer) copied into the function.
    fn global_expression(&mut self, h: Handle<Expression>) -> Handle<Expression> {
        let exprs = &self.module.global_expressions;
        let span = exprs.get_span(h);
        let mut e = exprs[h].clone();
        let mapped: Vec<_> = ir::operands(&e)
            .into_iter()
            .map(|o| self.global_expression(o))
            .collect();
        let mut it = mapped.into_iter();
        ir::map_operands(&mut e, &mut |_| it.next().unwrap());
        self.append(e, span)
    }

    /// The new local variable for a source local, created on first use.
    fn local(&mut self, ctx: &mut Ctx, v: Handle<LocalVariable>) -> Handle<LocalVariable> {
        if let Some(nv) = ctx.locals[v.index()] {
            return nv;
        }
        let var = &ctx.fun.local_variables[v];
        let nv = self.fun.local_variables.append(
            LocalVariable {
                name: var.name.clone(),
                ty: var.ty,
                init: None,
            },
            ctx.fun.local_variables.get_span(v),
        );
        ctx.locals[v.index()] = Some(nv);
        nv
    }

    fn store(&mut self, pointer: Handle<Expression>, value: Handle<Expression>, span: Span) {
        if let Some(v) = ir::root_local(&self.fun.expressions, pointer) {
            self.stored_log.push(v);
            if matches!(self.fun.expressions[pointer], Expression::LocalVariable(_)) {
                self.env.insert(v, value);
            } else {
                self.env.remove(&v);
            }
        }
        self.push_stmt(Statement::Store { pointer, value }, span);
    }

    /// The value a load through `ptr` reads, when it is known in straight-line code.
    fn forward(&mut self, ptr: Handle<Expression>, span: Span) -> Option<Handle<Expression>> {
        match self.fun.expressions[ptr] {
            Expression::LocalVariable(v) => self.env.get(&v).copied(),
            Expression::AccessIndex { base, index } => {
                let value = self.forward(base, span)?;
                Some(self.append(Expression::AccessIndex { base: value, index }, span))
            }
            _ => None,
        }
    }

    fn translate(
        &mut self,
        ctx: &mut Ctx,
        h: Handle<Expression>,
    ) -> Result<Handle<Expression>, FrontError> {
        if let Some(m) = ctx.map[h.index()] {
            return Ok(m);
        }
        let span = ctx.fun.expressions.get_span(h);
        if let Some(cr) = &self.opts.cache_read
            && ctx.is_top
            && let Some(slot) = cr.slots.iter().find(|s| s.target == h)
        {
            let (slot, source) = (*slot, cr.source);
            let m = self.cache_read(slot, source, span);
            ctx.map[h.index()] = Some(m);
            return Ok(m);
        }
        if ctx.is_top
            && let Some(c) = self.opts.constants.iter().find(|c| c.target == h)
        {
            let m = self.constant(c, span);
            ctx.map[h.index()] = Some(m);
            return Ok(m);
        }
        let src = &ctx.fun.expressions[h];
        let new = match *src {
            Expression::FunctionArgument(i) if !ctx.is_top => ctx.args[i as usize],
            Expression::LocalVariable(v) => {
                let nv = self.local(ctx, v);
                self.append(Expression::LocalVariable(nv), span)
            }
            Expression::GlobalVariable(g) if self.privates.contains_key(&g) => {
                self.append(Expression::LocalVariable(self.privates[&g]), span)
            }
            Expression::CallResult(_) => {
                return Err(unsupported(span, "a call result used before its call"));
            }
            Expression::Load { pointer } if self.normalize() => {
                let p = self.translate(ctx, pointer)?;
                match self.forward(p, span) {
                    Some(v) => v,
                    None => self.append(Expression::Load { pointer: p }, span),
                }
            }
            _ => {
                let mut e = src.clone();
                let ops = ir::operands(&e);
                let mut mapped = Vec::with_capacity(ops.len());
                for o in ops {
                    mapped.push(self.translate(ctx, o)?);
                }
                let mut it = mapped.into_iter();
                ir::map_operands(&mut e, &mut |_| it.next().unwrap());
                self.append(e, span)
            }
        };
        ctx.map[h.index()] = Some(new);
        if let Some(cs) = ctx.call_site {
            self.call_site.entry(new).or_insert(cs);
        }
        if let Some(name) = ctx.fun.named_expressions.get(&h)
            && !self.fun.expressions[new].needs_pre_emit()
            && !self.fun.named_expressions.contains_key(&new)
        {
            self.fun.named_expressions.insert(new, name.clone());
        }
        Ok(new)
    }

    fn cache_read(&mut self, slot: Slot, source: CacheSource, span: Span) -> Handle<Expression> {
        use naga::{Expression as E, SwizzleComponent as S};
        let texel = match source {
            CacheSource::Texture { image, position } => self.texture_read(image, position, span),
            CacheSource::Argument(i) => self.append(E::FunctionArgument(i), span),
        };
        let at = |i: u32| [S::X, S::Y, S::Z, S::W][((slot.offset + i) % 4) as usize];
        let size = match slot.components {
            1 => {
                return self.append(
                    E::AccessIndex {
                        base: texel,
                        index: slot.offset,
                    },
                    span,
                );
            }
            4 if slot.offset == 0 => return texel,
            2 => naga::VectorSize::Bi,
            3 => naga::VectorSize::Tri,
            _ => naga::VectorSize::Quad,
        };
        self.append(
            E::Swizzle {
                size,
                vector: texel,
                pattern: [at(0), at(1), at(2), at(3)],
            },
            span,
        )
    }

    fn constant(&mut self, c: &Constant, span: Span) -> Handle<Expression> {
        let n = c.components.clamp(1, 4) as usize;
        let literals: Vec<_> = c.value[..n]
            .iter()
            .map(|&v| self.append(Expression::Literal(naga::Literal::F32(v)), span))
            .collect();
        match c.vector {
            Some(ty) if n > 1 => self.append(
                Expression::Compose {
                    ty,
                    components: literals,
                },
                span,
            ),
            _ => literals[0],
        }
    }

    fn texture_read(
        &mut self,
        image: Handle<naga::GlobalVariable>,
        position: (u32, Option<u32>),
        span: Span,
    ) -> Handle<Expression> {
        use naga::{Expression as E, SwizzleComponent as S};
        let image = self.append(E::GlobalVariable(image), span);
        let arg = self.append(E::FunctionArgument(position.0), span);
        let pos = match position.1 {
            Some(m) => self.append(
                E::AccessIndex {
                    base: arg,
                    index: m,
                },
                span,
            ),
            None => arg,
        };
        let xy = self.append(
            E::Swizzle {
                size: naga::VectorSize::Bi,
                vector: pos,
                pattern: [S::X, S::Y, S::X, S::X],
            },
            span,
        );
        let coord = self.append(
            E::As {
                expr: xy,
                kind: naga::ScalarKind::Sint,
                convert: Some(4),
            },
            span,
        );
        let level = self.append(E::Literal(naga::Literal::I32(0)), span);
        self.append(
            E::ImageLoad {
                image,
                coordinate: coord,
                array_index: None,
                sample: None,
                level: Some(level),
            },
            span,
        )
    }

    fn payload_return(&mut self, stop: &StopAfter, values: &[Handle<Expression>], span: Span) {
        let used: u32 = stop.slots.iter().map(|s| s.components).sum();
        let v = match (values, used) {
            (&[value], 4) => value,
            _ => {
                let mut comps = values.to_vec();
                for _ in used..4 {
                    comps.push(self.append(Expression::Literal(naga::Literal::F32(0.0)), span));
                }
                self.append(
                    Expression::Compose {
                        ty: stop.vec4,
                        components: comps,
                    },
                    span,
                )
            }
        };
        if self.depth == 0 {
            self.root = Some(v);
        }
        self.push_stmt(Statement::Return { value: Some(v) }, span);
    }

    /// Local variables stored anywhere in `block` (source side), for loop-carried kills.
    fn stored_in(&self, ctx: &Ctx, block: &Block, out: &mut HashSet<Handle<LocalVariable>>) {
        let src_root = |mut p: Handle<Expression>| -> Option<Handle<LocalVariable>> {
            loop {
                match ctx.fun.expressions[p] {
                    Expression::LocalVariable(v) => return ctx.locals[v.index()],
                    Expression::GlobalVariable(g) => return self.privates.get(&g).copied(),
                    Expression::FunctionArgument(i) if !ctx.is_top => {
                        return ir::root_local(&self.fun.expressions, ctx.args[i as usize]);
                    }
                    Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => {
                        p = base
                    }
                    _ => return None,
                }
            }
        };
        for stmt in block.iter() {
            match stmt {
                Statement::Store { pointer, .. } => out.extend(src_root(*pointer)),
                Statement::Call { arguments, .. } => {
                    for a in arguments {
                        out.extend(src_root(*a));
                    }
                }
                Statement::Block(b) => self.stored_in(ctx, b, out),
                Statement::If { accept, reject, .. } => {
                    self.stored_in(ctx, accept, out);
                    self.stored_in(ctx, reject, out);
                }
                Statement::Switch { cases, .. } => {
                    for c in cases {
                        self.stored_in(ctx, &c.body, out);
                    }
                }
                Statement::Loop {
                    body, continuing, ..
                } => {
                    self.stored_in(ctx, body, out);
                    self.stored_in(ctx, continuing, out);
                }
                _ => {}
            }
        }
    }

    fn walk_block(&mut self, ctx: &mut Ctx, block: &Block) -> Result<(), FrontError> {
        for (stmt, span) in block.span_iter() {
            let index = self.stmt_index;
            self.stmt_index += 1;
            if self.stopped {
                self.skip(stmt);
                continue;
            }
            let live = (ctx.is_top && !matches!(stmt, Statement::Emit(_)))
                .then(|| self.opts.live.is_none_or(|l| l.stmts.contains(&index)));
            if live == Some(false) {
                self.skip(stmt);
                continue;
            }
            self.walk_stmt(ctx, stmt, *span)?;
        }
        Ok(())
    }

    /// Advance the statement counter over a statement that is not copied.
    fn skip(&mut self, stmt: &Statement) {
        let count = |b: &Block, s: &mut Self| {
            for st in b.iter() {
                s.stmt_index += 1;
                s.skip(st);
            }
        };
        match stmt {
            Statement::Block(b) => count(b, self),
            Statement::If { accept, reject, .. } => {
                count(accept, self);
                count(reject, self);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    count(&c.body, self);
                }
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                count(body, self);
                count(continuing, self);
            }
            _ => {}
        }
    }

    fn nested(&mut self, ctx: &mut Ctx, block: &Block) -> Result<Block, FrontError> {
        self.enter();
        self.walk_block(ctx, block)?;
        Ok(self.exit())
    }

    fn walk_stmt(&mut self, ctx: &mut Ctx, stmt: &Statement, span: Span) -> Result<(), FrontError> {
        if self.depth + self.calls > MAX_NESTING {
            return Err(unsupported(
                span,
                format!("more than {MAX_NESTING} nested blocks and helper calls"),
            ));
        }
        match stmt {
            Statement::Emit(range) => {
                for h in range.clone() {
                    if ctx.is_top && !self.is_live_expr(h) {
                        continue;
                    }
                    let m = self.translate(ctx, h)?;
                    if let Some(stop) = &self.opts.stop_after
                        && ctx.is_top
                        && let Some(i) = stop.slots.iter().position(|s| s.target == h)
                    {
                        if stop.slots.len() > 1 && self.depth > 0 {
                            return Err(unsupported(
                                span,
                                "nodes cached together must be computed outside branches",
                            ));
                        }
                        self.stop_values[i] = Some(m);
                        if let Some(values) =
                            self.stop_values.iter().copied().collect::<Option<Vec<_>>>()
                        {
                            let stop = stop.clone();
                            self.payload_return(&stop, &values, span);
                            self.stopped = true;
                            return Ok(());
                        }
                    }
                }
            }
            Statement::Block(b) => {
                // Values stored inside the block were emitted in its scope: do not forward them
                // past it (naga's validator does not catch an expression used out of scope).
                let mark = self.stored_log.len();
                let nb = self.nested(ctx, b)?;
                self.kill_since(mark);
                self.push_stmt(Statement::Block(nb), span);
            }
            Statement::If {
                condition,
                accept,
                reject,
            } => {
                let c = self.translate(ctx, *condition)?;
                let mark = self.stored_log.len();
                let before = self.env.clone();
                let a = self.nested(ctx, accept)?;
                self.env = before.clone();
                let r = self.nested(ctx, reject)?;
                self.env = before;
                self.kill_since(mark);
                self.push_stmt(
                    Statement::If {
                        condition: c,
                        accept: a,
                        reject: r,
                    },
                    span,
                );
            }
            Statement::Switch { selector, cases } => {
                let s = self.translate(ctx, *selector)?;
                let mark = self.stored_log.len();
                let before = self.env.clone();
                let mut new_cases = Vec::with_capacity(cases.len());
                for case in cases {
                    self.env = before.clone();
                    new_cases.push(naga::SwitchCase {
                        value: case.value,
                        body: self.nested(ctx, &case.body)?,
                        fall_through: case.fall_through,
                    });
                }
                self.env = before;
                self.kill_since(mark);
                self.push_stmt(
                    Statement::Switch {
                        selector: s,
                        cases: new_cases,
                    },
                    span,
                );
            }
            Statement::Loop {
                body,
                continuing,
                break_if,
            } => {
                let mut carried = HashSet::new();
                self.stored_in(ctx, body, &mut carried);
                self.stored_in(ctx, continuing, &mut carried);
                for v in &carried {
                    self.env.remove(v);
                }
                let mark = self.stored_log.len();
                let before = self.env.clone();
                let b = self.nested(ctx, body)?;
                self.enter();
                self.walk_block(ctx, continuing)?;
                let bi = match break_if {
                    Some(h) => Some(self.translate(ctx, *h)?),
                    None => None,
                };
                let c = self.exit();
                self.env = before;
                self.kill_since(mark);
                self.push_stmt(
                    Statement::Loop {
                        body: b,
                        continuing: c,
                        break_if: bi,
                    },
                    span,
                );
            }
            Statement::Break | Statement::Continue | Statement::Kill => {
                self.push_stmt(stmt.clone(), span)
            }
            Statement::Return { value } => {
                if ctx.is_top {
                    let v = match (value, &self.opts.stop_after) {
                        // A return before the cached node in the recompute pass: its value is not
                        // the payload; return zero.
                        (_, Some(stop)) => {
                            Some(self.append(Expression::ZeroValue(stop.vec4), span))
                        }
                        (Some(v), None) => Some(self.translate(ctx, *v)?),
                        (None, None) => None,
                    };
                    if self.depth == 0 {
                        self.root = v;
                    }
                    self.push_stmt(Statement::Return { value: v }, span);
                } else {
                    ctx.ret = match value {
                        Some(v) => Some(self.translate(ctx, *v)?),
                        None => None,
                    };
                }
            }
            Statement::Store { pointer, value } => {
                let p = self.translate(ctx, *pointer)?;
                let v = self.translate(ctx, *value)?;
                self.store(p, v, span);
            }
            Statement::ImageStore {
                image,
                coordinate,
                array_index,
                value,
            } => {
                let image = self.translate(ctx, *image)?;
                let coordinate = self.translate(ctx, *coordinate)?;
                let array_index = match array_index {
                    Some(a) => Some(self.translate(ctx, *a)?),
                    None => None,
                };
                let value = self.translate(ctx, *value)?;
                self.push_stmt(
                    Statement::ImageStore {
                        image,
                        coordinate,
                        array_index,
                        value,
                    },
                    span,
                );
            }
            Statement::Call {
                function,
                arguments,
                result,
            } => {
                if !self.normalize() {
                    return Err(unsupported(
                        span,
                        "a function call in a normalized function",
                    ));
                }
                self.inline_call(ctx, *function, arguments, *result, span)?;
            }
            other => {
                let what = format!("the statement {:?}", std::mem::discriminant(other));
                let name = match other {
                    Statement::ControlBarrier(_) | Statement::MemoryBarrier(_) => "a barrier",
                    Statement::Atomic { .. } | Statement::ImageAtomic { .. } => {
                        "an atomic operation"
                    }
                    Statement::WorkGroupUniformLoad { .. } => "workgroupUniformLoad",
                    Statement::RayQuery { .. } | Statement::RayPipelineFunction(_) => "ray queries",
                    Statement::SubgroupBallot { .. }
                    | Statement::SubgroupGather { .. }
                    | Statement::SubgroupCollectiveOperation { .. } => "subgroup operations",
                    _ => what.as_str(),
                };
                return Err(unsupported(span, format!("{name} in a fragment shader")));
            }
        }
        Ok(())
    }

    fn kill_since(&mut self, mark: usize) {
        for v in &self.stored_log[mark..] {
            self.env.remove(v);
        }
    }

    fn inline_call(
        &mut self,
        ctx: &mut Ctx,
        function: Handle<Function>,
        arguments: &[Handle<Expression>],
        result: Option<Handle<Expression>>,
        span: Span,
    ) -> Result<(), FrontError> {
        let callee = &self.module.functions[function];
        check_single_return(callee)?;
        let mut args = Vec::with_capacity(arguments.len());
        for a in arguments {
            args.push(self.translate(ctx, *a)?);
        }
        // A call with no span (the wrapper entry point naga's GLSL and SPIR-V front ends add
        // around `main`) is no call site: the calls inside `main` are.
        let site = ctx.call_site.or(span.is_defined().then_some(span));
        let mut cctx = Ctx::new(callee, false, site, args);
        cctx.locals = vec![None; callee.local_variables.len()];
        for (h, _) in callee.local_variables.iter() {
            self.local(&mut cctx, h);
        }
        // Statement indices only count the top-level function.
        let saved_index = self.stmt_index;
        self.calls += 1;
        self.init_locals(&mut cctx, callee)?;
        self.walk_block(&mut cctx, &callee.body)?;
        self.calls -= 1;
        self.stmt_index = saved_index;
        if let Some(r) = result {
            match cctx.ret {
                Some(v) => ctx.map[r.index()] = Some(v),
                None => {
                    return Err(unsupported(
                        span,
                        format!(
                            "fn {} returns no value on its last statement",
                            callee.name.as_deref().unwrap_or("?")
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A helper can be inlined when its only `return` is its last top-level statement.
fn check_single_return(fun: &Function) -> Result<(), FrontError> {
    fn find_return(block: &Block) -> Option<Span> {
        for (s, span) in block.span_iter() {
            let nested = match s {
                Statement::Return { .. } => return Some(*span),
                Statement::Block(b) => find_return(b),
                Statement::If { accept, reject, .. } => {
                    find_return(accept).or_else(|| find_return(reject))
                }
                Statement::Switch { cases, .. } => cases.iter().find_map(|c| find_return(&c.body)),
                Statement::Loop {
                    body, continuing, ..
                } => find_return(body).or_else(|| find_return(continuing)),
                _ => None,
            };
            if nested.is_some() {
                return nested;
            }
        }
        None
    }
    let n = fun.body.len();
    let stmts = fun.body.span_iter().enumerate();
    for (i, (s, span)) in stmts {
        let is_last_return = i + 1 == n && matches!(s, Statement::Return { .. });
        if is_last_return {
            break;
        }
        let early = match s {
            Statement::Return { .. } => Some(*span),
            Statement::Block(b) => find_return(b),
            Statement::If { accept, reject, .. } => {
                find_return(accept).or_else(|| find_return(reject))
            }
            Statement::Switch { cases, .. } => cases.iter().find_map(|c| find_return(&c.body)),
            Statement::Loop {
                body, continuing, ..
            } => find_return(body).or_else(|| find_return(continuing)),
            _ => None,
        };
        if let Some(span) = early {
            return Err(FrontError::UnsupportedAt {
                span,
                what: format!(
                    "early return in helper fn {} (helpers are inlined; end them with a single return)",
                    fun.name.as_deref().unwrap_or("?")
                ),
            });
        }
    }
    Ok(())
}
