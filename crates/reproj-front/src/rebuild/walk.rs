//! The statement walker: blocks in order, control flow, loop-carried kills and inlined calls.

use super::*;

impl Out<'_, '_> {
    /// Local variables stored anywhere in `block` (source side), for loop-carried kills.
    pub(super) fn stored_in(
        &self,
        ctx: &Ctx,
        block: &Block,
        out: &mut HashSet<Handle<LocalVariable>>,
    ) {
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

    pub(super) fn walk_block(&mut self, ctx: &mut Ctx, block: &Block) -> Result<(), FrontError> {
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
    pub(super) fn skip(&mut self, stmt: &Statement) {
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

    pub(super) fn nested(&mut self, ctx: &mut Ctx, block: &Block) -> Result<Block, FrontError> {
        self.enter();
        self.walk_block(ctx, block)?;
        Ok(self.exit())
    }

    /// Rebuild one statement: a dispatch on its kind, one method per kind.
    pub(super) fn walk_stmt(
        &mut self,
        ctx: &mut Ctx,
        stmt: &Statement,
        span: Span,
    ) -> Result<(), FrontError> {
        if self.depth + self.calls > MAX_NESTING {
            return Err(unsupported(
                span,
                format!("more than {MAX_NESTING} nested blocks and helper calls"),
            ));
        }
        match stmt {
            Statement::Emit(range) => self.emit(ctx, range.clone(), span),
            Statement::Block(b) => self.block_stmt(ctx, b, span),
            Statement::If {
                condition,
                accept,
                reject,
            } => self.if_stmt(ctx, *condition, accept, reject, span),
            Statement::Switch { selector, cases } => self.switch_stmt(ctx, *selector, cases, span),
            Statement::Loop {
                body,
                continuing,
                break_if,
            } => self.loop_stmt(ctx, body, continuing, *break_if, span),
            Statement::Break | Statement::Continue | Statement::Kill => {
                self.push_stmt(stmt.clone(), span);
                Ok(())
            }
            Statement::Return { value } => self.return_stmt(ctx, *value, span),
            Statement::Store { pointer, value } => {
                let p = self.translate(ctx, *pointer)?;
                let v = self.translate(ctx, *value)?;
                self.store(p, v, span);
                Ok(())
            }
            Statement::ImageStore {
                image,
                coordinate,
                array_index,
                value,
            } => self.image_store(ctx, [*image, *coordinate, *value], *array_index, span),
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
                self.inline_call(ctx, *function, arguments, *result, span)
            }
            other => Err(unsupported_statement(other, span)),
        }
    }

    /// The expressions of an `Emit`, translated in order (dead ones skipped at the top level);
    /// where `StopAfter` caches the last of its nodes, the payload is returned and the walk stops.
    fn emit(
        &mut self,
        ctx: &mut Ctx,
        range: naga::Range<Expression>,
        span: Span,
    ) -> Result<(), FrontError> {
        for h in range {
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
                if let Some(values) = self.stop_values.iter().copied().collect::<Option<Vec<_>>>() {
                    let stop = stop.clone();
                    self.payload_return(&stop, &values, span);
                    self.stopped = true;
                    return Ok(());
                }
            }
        }
        Ok(())
    }

    /// A nested block. Values stored inside the block were emitted in its scope: they are not
    /// forwarded past it (naga's validator does not catch an expression used out of scope).
    fn block_stmt(&mut self, ctx: &mut Ctx, b: &Block, span: Span) -> Result<(), FrontError> {
        let mark = self.stored_log.len();
        let nb = self.nested(ctx, b)?;
        self.kill_since(mark);
        self.push_stmt(Statement::Block(nb), span);
        Ok(())
    }

    /// An `if`: each branch walked from the values known before it; none stored in either is
    /// forwarded past it.
    fn if_stmt(
        &mut self,
        ctx: &mut Ctx,
        condition: Handle<Expression>,
        accept: &Block,
        reject: &Block,
        span: Span,
    ) -> Result<(), FrontError> {
        let c = self.translate(ctx, condition)?;
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
        Ok(())
    }

    /// A `switch`: each case walked from the values known before it, a case that falls through
    /// written with the bodies it falls into.
    fn switch_stmt(
        &mut self,
        ctx: &mut Ctx,
        selector: Handle<Expression>,
        cases: &[naga::SwitchCase],
        span: Span,
    ) -> Result<(), FrontError> {
        let s = self.translate(ctx, selector)?;
        let mark = self.stored_log.len();
        let before = self.env.clone();
        let mut new_cases = Vec::with_capacity(cases.len());
        for (i, case) in cases.iter().enumerate() {
            self.env = before.clone();
            let (body, fall_through) = if case.fall_through && !case.body.is_empty() {
                (self.fall_through_case(ctx, &cases[i..])?, false)
            } else {
                (self.nested(ctx, &case.body)?, case.fall_through)
            };
            new_cases.push(naga::SwitchCase {
                value: case.value,
                body,
                fall_through,
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
        Ok(())
    }

    /// A `loop`: what it stores is forgotten before it (carried from one iteration to the next),
    /// and what it stores inside is not forwarded past it.
    fn loop_stmt(
        &mut self,
        ctx: &mut Ctx,
        body: &Block,
        continuing: &Block,
        break_if: Option<Handle<Expression>>,
        span: Span,
    ) -> Result<(), FrontError> {
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
            Some(h) => Some(self.translate(ctx, h)?),
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
        Ok(())
    }

    /// A struct result that is not built by a constructor where it is returned (a local filled
    /// in branches: `if … { out.color = a; } else { out.color = b; } return out;`, Bevy's
    /// `pbr.wgsl`), returned as one built member by member (`Out(out.color, …)`) when
    /// normalizing, so that its `@location(0)` member is an expression of its own: the root.
    fn struct_by_members(
        &mut self,
        ctx: &Ctx,
        value: Handle<Expression>,
        span: Span,
    ) -> Handle<Expression> {
        if !self.normalize() || self.depth != 0 {
            return value;
        }
        let Some(result) = ctx.fun.result.as_ref() else {
            return value;
        };
        let naga::TypeInner::Struct { members, .. } = &self.module.types[result.ty].inner else {
            return value;
        };
        if matches!(self.fun.expressions[value], Expression::Compose { .. }) {
            return value;
        }
        let components = (0..members.len() as u32)
            .map(|index| self.append(Expression::AccessIndex { base: value, index }, span))
            .collect();
        self.append(
            Expression::Compose {
                ty: result.ty,
                components,
            },
            span,
        )
    }

    /// A `return`: at the top level the function's result (zero in the recompute pass, before
    /// the cached node), in an inlined helper the value of the call.
    fn return_stmt(
        &mut self,
        ctx: &mut Ctx,
        value: Option<Handle<Expression>>,
        span: Span,
    ) -> Result<(), FrontError> {
        if ctx.is_top {
            let v = match (value, &self.opts.stop_after) {
                // A return before the cached node in the recompute pass: its value is not
                // the payload; return zero.
                (_, Some(stop)) => Some(self.append(Expression::ZeroValue(stop.vec4), span)),
                (Some(v), None) => {
                    let v = self.translate(ctx, v)?;
                    Some(self.struct_by_members(ctx, v, span))
                }
                (None, None) => None,
            };
            if self.depth == 0 {
                self.root = v;
            }
            self.push_stmt(Statement::Return { value: v }, span);
        } else {
            ctx.ret = match value {
                Some(v) => Some(self.translate(ctx, v)?),
                None => None,
            };
        }
        Ok(())
    }

    /// An image store, its operands translated in order: `[image, coordinate, value]` and the
    /// array index (translated before the value).
    fn image_store(
        &mut self,
        ctx: &mut Ctx,
        [image, coordinate, value]: [Handle<Expression>; 3],
        array_index: Option<Handle<Expression>>,
        span: Span,
    ) -> Result<(), FrontError> {
        let image = self.translate(ctx, image)?;
        let coordinate = self.translate(ctx, coordinate)?;
        let array_index = match array_index {
            Some(a) => Some(self.translate(ctx, a)?),
            None => None,
        };
        let value = self.translate(ctx, value)?;
        self.push_stmt(
            Statement::ImageStore {
                image,
                coordinate,
                array_index,
                value,
            },
            span,
        );
        Ok(())
    }

    /// A case whose body falls through into the next (C-style `switch` from GLSL or SPIR-V; WGSL
    /// has none, and naga's WGSL writer cannot write one): its body followed by the bodies it falls
    /// into, up to the first case that does not fall through, as one block. The bodies after the
    /// first are walked again for their own cases, so their translations made here (scoped to
    /// this case) are forgotten afterwards, and their statements are not counted twice.
    fn fall_through_case(
        &mut self,
        ctx: &mut Ctx,
        cases: &[naga::SwitchCase],
    ) -> Result<Block, FrontError> {
        self.enter();
        self.walk_block(ctx, &cases[0].body)?;
        let (map, stmt_index) = (ctx.map.clone(), self.stmt_index);
        for case in &cases[1..] {
            self.walk_block(ctx, &case.body)?;
            if !case.fall_through {
                break;
            }
        }
        (ctx.map, self.stmt_index) = (map, stmt_index);
        Ok(self.exit())
    }

    pub(super) fn kill_since(&mut self, mark: usize) {
        for v in &self.stored_log[mark..] {
            self.env.remove(v);
        }
    }

    pub(super) fn inline_call(
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

/// The error for a statement a fragment shader reproj rebuilds cannot hold, named by its kind.
fn unsupported_statement(other: &Statement, span: Span) -> FrontError {
    let what = format!("the statement {:?}", std::mem::discriminant(other));
    let name = match other {
        Statement::ControlBarrier(_) | Statement::MemoryBarrier(_) => "a barrier",
        Statement::Atomic { .. } | Statement::ImageAtomic { .. } => "an atomic operation",
        Statement::WorkGroupUniformLoad { .. } => "workgroupUniformLoad",
        Statement::RayQuery { .. } | Statement::RayPipelineFunction(_) => "ray queries",
        Statement::SubgroupBallot { .. }
        | Statement::SubgroupGather { .. }
        | Statement::SubgroupCollectiveOperation { .. } => "subgroup operations",
        _ => what.as_str(),
    };
    unsupported(span, format!("{name} in a fragment shader"))
}
