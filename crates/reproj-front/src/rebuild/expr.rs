//! The rebuilt function's expressions: appending (with sharing when normalizing), translating
//! a source expression through the handle map, locals and forwarded stores.

use super::*;

impl Out<'_, '_> {
    pub(super) fn normalize(&self) -> bool {
        self.mode == Mode::Normalize
    }

    pub(super) fn flush(&mut self) {
        if let Some((stmt, span)) = self.emitter.finish(&self.fun.expressions) {
            self.blocks.last_mut().unwrap().push(stmt, span);
        }
    }

    pub(super) fn push_stmt(&mut self, stmt: Statement, span: Span) {
        self.flush();
        self.blocks.last_mut().unwrap().push(stmt, span);
        self.emitter.start(&self.fun.expressions);
    }

    pub(super) fn enter(&mut self) {
        self.flush();
        self.blocks.push(Block::new());
        self.cse.push(HashMap::new());
        self.depth += 1;
        self.emitter.start(&self.fun.expressions);
    }

    pub(super) fn exit(&mut self) -> Block {
        self.flush();
        self.cse.pop();
        self.depth -= 1;
        let b = self.blocks.pop().unwrap();
        self.emitter.start(&self.fun.expressions);
        b
    }

    /// Append an expression, sharing an identical earlier one when that is safe.
    pub(super) fn append(&mut self, expr: Expression, span: Span) -> Handle<Expression> {
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

    pub(super) fn is_live_expr(&self, h: Handle<Expression>) -> bool {
        self.opts.live.is_none_or(|l| l.exprs.contains(&h))
    }

    pub(super) fn init_locals(&mut self, ctx: &mut Ctx, fun: &Function) -> Result<(), FrontError> {
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
    pub(super) fn init_privates(&mut self) {
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
    pub(super) fn global_expression(&mut self, h: Handle<Expression>) -> Handle<Expression> {
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
    pub(super) fn local(
        &mut self,
        ctx: &mut Ctx,
        v: Handle<LocalVariable>,
    ) -> Handle<LocalVariable> {
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

    pub(super) fn store(
        &mut self,
        pointer: Handle<Expression>,
        value: Handle<Expression>,
        span: Span,
    ) {
        if let Some(v) = ir::root_local(&self.fun.expressions, pointer) {
            self.stored_log.push(v);
            if matches!(self.fun.expressions[pointer], Expression::LocalVariable(_)) {
                self.env.insert(v, value);
            } else if let Some(whole) = self.member_store(pointer, value, span) {
                self.env.insert(v, whole);
            } else {
                self.env.remove(&v);
            }
        }
        self.push_stmt(Statement::Store { pointer, value }, span);
    }

    /// Normalizing, a store to a member of a struct local whose value is known (`out.albedo = a;`,
    /// the G-buffer pattern, at any depth of struct members): the struct's new value, composed
    /// of the stored member and the known others, so the loads after it forward like those of a
    /// whole store. `None` (forget the variable) for any other partial store.
    fn member_store(
        &mut self,
        pointer: Handle<Expression>,
        value: Handle<Expression>,
        span: Span,
    ) -> Option<Handle<Expression>> {
        if !self.normalize() {
            return None;
        }
        let mut path = Vec::new();
        let mut p = pointer;
        let var = loop {
            match self.fun.expressions[p] {
                Expression::AccessIndex { base, index } => {
                    path.push(index);
                    p = base;
                }
                Expression::LocalVariable(v) => break v,
                _ => return None,
            }
        };
        path.reverse();
        let old = *self.env.get(&var)?;
        let ty = self.fun.local_variables[var].ty;
        self.with_member(old, ty, &path, value, span)
    }

    /// `whole` (of type `ty`: a struct, or a vector for the last step) with the member or
    /// component at `path` replaced by `value`.
    fn with_member(
        &mut self,
        whole: Handle<Expression>,
        ty: Handle<naga::Type>,
        path: &[u32],
        value: Handle<Expression>,
        span: Span,
    ) -> Option<Handle<Expression>> {
        let Some((&at, rest)) = path.split_first() else {
            return Some(value);
        };
        // Each part's type: a member's type, or none for a vector's scalar component.
        let (parts, scalar): (Vec<Option<Handle<naga::Type>>>, _) =
            match &self.module.types[ty].inner {
                naga::TypeInner::Struct { members, .. } => {
                    (members.iter().map(|m| Some(m.ty)).collect(), None)
                }
                naga::TypeInner::Vector { size, scalar } if rest.is_empty() => {
                    (vec![None; *size as usize], Some(*scalar))
                }
                _ => return None,
            };
        let mut components = Vec::with_capacity(parts.len());
        for (k, part_ty) in parts.into_iter().enumerate() {
            let k = k as u32;
            let part = if k == at && rest.is_empty() {
                value
            } else {
                let part = self.member_of(whole, k, part_ty, scalar, span)?;
                if k == at {
                    self.with_member(part, part_ty?, rest, value, span)?
                } else {
                    part
                }
            };
            components.push(part);
        }
        Some(self.append(Expression::Compose { ty, components }, span))
    }

    /// Part `k` of the struct or vector value `whole` (a member of type `ty`, or a component of
    /// type `scalar`): the part itself when `whole` was composed of its parts or is zero.
    fn member_of(
        &mut self,
        whole: Handle<Expression>,
        k: u32,
        ty: Option<Handle<naga::Type>>,
        scalar: Option<naga::Scalar>,
        span: Span,
    ) -> Option<Handle<Expression>> {
        let whole_ty_parts = |this: &Self, t: Handle<naga::Type>| match &this.module.types[t].inner
        {
            naga::TypeInner::Struct { members, .. } => members.len(),
            naga::TypeInner::Vector { size, .. } => *size as usize,
            _ => 0,
        };
        Some(match &self.fun.expressions[whole] {
            Expression::Compose { ty: t, components }
                if components.len() == whole_ty_parts(self, *t) =>
            {
                components[k as usize]
            }
            Expression::ZeroValue(_) => match (ty, scalar) {
                (Some(ty), _) => self.append(Expression::ZeroValue(ty), span),
                (None, Some(scalar)) => {
                    self.append(Expression::Literal(naga::Literal::zero(scalar)?), span)
                }
                (None, None) => return None,
            },
            _ => self.append(
                Expression::AccessIndex {
                    base: whole,
                    index: k,
                },
                span,
            ),
        })
    }

    /// The value a load through `ptr` reads, when it is known in straight-line code.
    pub(super) fn forward(
        &mut self,
        ptr: Handle<Expression>,
        span: Span,
    ) -> Option<Handle<Expression>> {
        match self.fun.expressions[ptr] {
            Expression::LocalVariable(v) => self.env.get(&v).copied(),
            Expression::AccessIndex { base, index } => {
                let value = self.forward(base, span)?;
                // A member of a struct composed member by member is that member's value.
                if let Expression::Compose { ty, components } = &self.fun.expressions[value]
                    && matches!(self.module.types[*ty].inner, naga::TypeInner::Struct { .. })
                {
                    return Some(components[index as usize]);
                }
                Some(self.append(Expression::AccessIndex { base: value, index }, span))
            }
            _ => None,
        }
    }

    pub(super) fn translate(
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
}
