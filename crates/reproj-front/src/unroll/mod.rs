//! Loop unrolling of constant-trip loops.
//!
//! A loop whose value is read after it (an accumulated sum) is one node to the node table: the
//! per-iteration values inside it are culled as `in-loop`. Unrolling a loop with a constant trip
//! count turns each iteration into straight-line code, so that load forwarding (a second
//! normalization, see [`crate::normalize`]) makes every partial sum and per-iteration value its own
//! node. The pass copies a call-free (normalized) function in order with a handle map, as
//! [`crate::rebuild`] does, and expands the loops it recognises; it leaves every other loop alone.
//!
//! Recognised shape (what `for (var i = 0; i < N; i++)` becomes in naga's WGSL and GLSL front
//! ends): `loop { if i < N {} else { break; } body; continuing { i = i + step; } }` (or `if !(i <
//! N) { break; }`), where `i` is an `i32`/`u32` local holding a literal when the loop starts, `N`
//! and `step` are literals or module constants, the condition is `<`, `<=`, `>`, `>=` or `!=`, and the body neither
//! writes `i` nor holds a `break`, `continue` or `return` of its own (those of nested loops and
//! switches are theirs). Inside each copy the counter reads as a literal.

use std::collections::HashMap;

use naga::{
    BinaryOperator, Block, Expression, Function, Handle, Literal, LocalVariable, Span, Statement,
    UnaryOperator,
};

use crate::ir;

mod shape;

use shape::{escapes, flip, stored_locals, trips};

/// Options of [`unroll`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnrollOptions {
    /// Unroll loops of at most this many iterations (nested loops multiply); 0 unrolls nothing.
    pub max_trip: u32,
}

impl UnrollOptions {
    /// No unrolling.
    pub const OFF: UnrollOptions = UnrollOptions { max_trip: 0 };
}

impl Default for UnrollOptions {
    fn default() -> Self {
        Self::OFF
    }
}

/// The unrolled function and where its expressions came from.
#[derive(Debug)]
pub struct Unrolled {
    pub function: Function,
    /// Loops expanded (a nested loop counts once per copy of its parent).
    pub loops: usize,
    /// For each expression of `function`, the source expression it copies (`None`: added).
    pub origin: Vec<Option<Handle<Expression>>>,
}

/// Expand every constant-trip loop of at most `options.max_trip` iterations of the call-free
/// function `fun` of `module` into straight-line copies of its body; other loops are copied as they are.
/// The result is valid when `fun` is; it still needs load forwarding to become a DAG.
pub fn unroll(module: &naga::Module, fun: &Function, options: &UnrollOptions) -> Unrolled {
    let mut w = Walker {
        module,
        src: fun,
        options: *options,
        out: Function {
            name: fun.name.clone(),
            arguments: fun.arguments.clone(),
            result: fun.result.clone(),
            local_variables: fun.local_variables.clone(),
            expressions: naga::Arena::new(),
            named_expressions: Default::default(),
            body: Block::new(),
            diagnostic_filter_leaf: fun.diagnostic_filter_leaf,
        },
        origin: Vec::new(),
        map: vec![None; fun.expressions.len()],
        emitter: naga::proc::Emitter::default(),
        blocks: vec![Block::new()],
        counters: HashMap::new(),
        known: HashMap::new(),
        loops: 0,
    };
    w.emitter.start(&w.out.expressions);
    w.walk_block(&fun.body);
    w.flush();
    w.out.body = w.blocks.pop().unwrap_or_default();
    for (&h, name) in &fun.named_expressions {
        if let Some(n) = w.map[h.index()]
            && !w.out.expressions[n].needs_pre_emit()
        {
            w.out
                .named_expressions
                .entry(n)
                .or_insert_with(|| name.clone());
        }
    }
    Unrolled {
        function: w.out,
        loops: w.loops,
        origin: w.origin,
    }
}

/// A recognised loop: its counter, the values the counter takes, where the guard sits.
struct Plan {
    counter: Handle<LocalVariable>,
    values: Vec<Literal>,
    end: Literal,
    /// Index of the guard `if` in the loop body (statements before it are `Emit`s).
    guard: usize,
}

struct Walker<'f> {
    module: &'f naga::Module,
    src: &'f Function,
    options: UnrollOptions,
    out: Function,
    origin: Vec<Option<Handle<Expression>>>,
    map: Vec<Option<Handle<Expression>>>,
    emitter: naga::proc::Emitter,
    blocks: Vec<Block>,
    /// Counters of the loops being expanded, with their value in the current copy.
    counters: HashMap<Handle<LocalVariable>, Literal>,
    /// Locals known to hold a literal at this point of straight-line code (output side values).
    known: HashMap<Handle<LocalVariable>, Literal>,
    loops: usize,
}

impl Walker<'_> {
    fn flush(&mut self) {
        if let Some((stmt, span)) = self.emitter.finish(&self.out.expressions) {
            self.blocks.last_mut().unwrap().push(stmt, span);
        }
    }

    fn push_stmt(&mut self, stmt: Statement, span: Span) {
        self.flush();
        self.blocks.last_mut().unwrap().push(stmt, span);
        self.emitter.start(&self.out.expressions);
    }

    fn nested(&mut self, block: &Block) -> Block {
        self.flush();
        self.blocks.push(Block::new());
        self.emitter.start(&self.out.expressions);
        let known = self.known.clone();
        self.walk_block(block);
        self.known = known;
        self.flush();
        let b = self.blocks.pop().unwrap();
        self.emitter.start(&self.out.expressions);
        b
    }

    fn append(
        &mut self,
        expr: Expression,
        span: Span,
        origin: Option<Handle<Expression>>,
    ) -> Handle<Expression> {
        let h = if expr.needs_pre_emit() {
            self.flush();
            let h = self.out.expressions.append(expr, span);
            self.emitter.start(&self.out.expressions);
            h
        } else {
            self.out.expressions.append(expr, span)
        };
        self.origin.push(origin);
        h
    }

    fn translate(&mut self, h: Handle<Expression>) -> Handle<Expression> {
        if let Some(m) = self.map[h.index()] {
            return m;
        }
        let span = self.src.expressions.get_span(h);
        let counter = match self.src.expressions[h] {
            Expression::Load { pointer } => match self.src.expressions[pointer] {
                Expression::LocalVariable(v) => self.counters.get(&v).copied(),
                _ => None,
            },
            _ => None,
        };
        let new = match counter {
            Some(value) => self.append(Expression::Literal(value), span, Some(h)),
            None => {
                let mut e = self.src.expressions[h].clone();
                let mapped: Vec<_> = ir::operands(&e)
                    .into_iter()
                    .map(|o| self.translate(o))
                    .collect();
                let mut it = mapped.into_iter();
                ir::map_operands(&mut e, &mut |_| it.next().unwrap());
                self.append(e, span, Some(h))
            }
        };
        self.map[h.index()] = Some(new);
        new
    }

    fn walk_block(&mut self, block: &Block) {
        for (stmt, span) in block.span_iter() {
            self.walk_stmt(stmt, *span);
        }
    }

    fn walk_stmt(&mut self, stmt: &Statement, span: Span) {
        match stmt {
            Statement::Emit(range) => {
                for h in range.clone() {
                    self.translate(h);
                }
            }
            Statement::Block(b) => {
                let nb = self.nested(b);
                self.forget_stored(b);
                self.push_stmt(Statement::Block(nb), span);
            }
            Statement::If {
                condition,
                accept,
                reject,
            } => {
                let c = self.translate(*condition);
                let a = self.nested(accept);
                let r = self.nested(reject);
                self.forget_stored(accept);
                self.forget_stored(reject);
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
                let s = self.translate(*selector);
                let cases = cases
                    .iter()
                    .map(|c| naga::SwitchCase {
                        value: c.value,
                        body: self.nested(&c.body),
                        fall_through: c.fall_through,
                    })
                    .collect();
                for c in match stmt {
                    Statement::Switch { cases, .. } => cases.iter(),
                    _ => unreachable!(),
                } {
                    self.forget_stored(&c.body);
                }
                self.push_stmt(Statement::Switch { selector: s, cases }, span);
            }
            Statement::Loop {
                body,
                continuing,
                break_if,
            } => match self.plan(body, continuing, *break_if) {
                Some(plan) => self.expand(&plan, body, continuing, span),
                None => {
                    // Values stored in the loop differ between iterations.
                    self.forget_stored(body);
                    self.forget_stored(continuing);
                    let b = self.nested(body);
                    self.flush();
                    self.blocks.push(Block::new());
                    self.emitter.start(&self.out.expressions);
                    let known = self.known.clone();
                    self.walk_block(continuing);
                    // `break_if` is evaluated at the end of the continuing block.
                    let bi = break_if.map(|h| self.translate(h));
                    self.known = known;
                    self.flush();
                    let c = self.blocks.pop().unwrap();
                    self.emitter.start(&self.out.expressions);
                    self.push_stmt(
                        Statement::Loop {
                            body: b,
                            continuing: c,
                            break_if: bi,
                        },
                        span,
                    );
                }
            },
            Statement::Store { pointer, value } => {
                let p = self.translate(*pointer);
                let v = self.translate(*value);
                match (&self.out.expressions[p], &self.out.expressions[v]) {
                    (Expression::LocalVariable(l), Expression::Literal(lit)) => {
                        self.known.insert(*l, *lit);
                    }
                    _ => {
                        if let Some(l) = ir::root_local(&self.out.expressions, p) {
                            self.known.remove(&l);
                        }
                    }
                }
                self.push_stmt(
                    Statement::Store {
                        pointer: p,
                        value: v,
                    },
                    span,
                );
            }
            Statement::Return { value } => {
                let v = value.map(|h| self.translate(h));
                self.push_stmt(Statement::Return { value: v }, span);
            }
            Statement::ImageStore {
                image,
                coordinate,
                array_index,
                value,
            } => {
                let s = Statement::ImageStore {
                    image: self.translate(*image),
                    coordinate: self.translate(*coordinate),
                    array_index: array_index.map(|a| self.translate(a)),
                    value: self.translate(*value),
                };
                self.push_stmt(s, span);
            }
            // Break, continue, kill; a normalized function has nothing else.
            other => self.push_stmt(other.clone(), span),
        }
    }

    /// Locals stored anywhere in `block` no longer hold a known literal after it.
    fn forget_stored(&mut self, block: &Block) {
        let mut stored = Vec::new();
        stored_locals(self.src, block, &mut stored);
        for v in stored {
            self.known.remove(&v);
        }
    }

    /// The loop as a constant-trip loop to expand, or `None` to copy it.
    fn plan(
        &self,
        body: &Block,
        continuing: &Block,
        break_if: Option<Handle<Expression>>,
    ) -> Option<Plan> {
        if self.options.max_trip == 0 || break_if.is_some() {
            return None;
        }
        let exprs = &self.src.expressions;
        let guard = body.iter().position(|s| !matches!(s, Statement::Emit(_)))?;
        let Statement::If {
            condition,
            accept,
            reject,
        } = &body[guard]
        else {
            return None;
        };
        let is_break = |b: &Block| b.len() == 1 && matches!(b[0], Statement::Break);
        // The condition under which the loop goes on.
        let (go_on, negated) = match (accept.is_empty(), reject.is_empty()) {
            (true, false) if is_break(reject) => (*condition, false),
            (false, true) if is_break(accept) => match exprs[*condition] {
                Expression::Unary {
                    op: UnaryOperator::LogicalNot,
                    expr,
                } => (expr, false),
                _ => (*condition, true),
            },
            _ => return None,
        };
        if negated {
            return None;
        }
        let counter_of = |h: Handle<Expression>| match exprs[h] {
            Expression::Load { pointer } => match exprs[pointer] {
                Expression::LocalVariable(v) => Some(v),
                _ => None,
            },
            _ => None,
        };
        let literal = |h: Handle<Expression>| {
            let value = match exprs[h] {
                Expression::Literal(l) => l,
                // A module-scope `const` (naga keeps the name in function expressions).
                Expression::Constant(c) => {
                    let init = self.module.constants[c].init;
                    match self.module.global_expressions[init] {
                        Expression::Literal(l) => l,
                        _ => return None,
                    }
                }
                _ => return None,
            };
            matches!(value, Literal::I32(_) | Literal::U32(_)).then_some(value)
        };
        let Expression::Binary { op, left, right } = exprs[go_on] else {
            return None;
        };
        let (counter, op, bound) = match (counter_of(left), literal(right)) {
            (Some(c), Some(b)) => (c, op, b),
            _ => (counter_of(right)?, flip(op)?, literal(left)?),
        };
        if self.counters.contains_key(&counter) {
            return None;
        }
        // The update: the continuing block's only store, `counter = counter ± step`.
        let mut step = None;
        for s in continuing.iter() {
            match s {
                Statement::Emit(_) => {}
                Statement::Store { pointer, value }
                    if step.is_none()
                        && matches!(exprs[*pointer], Expression::LocalVariable(v) if v == counter) =>
                {
                    let Expression::Binary { op, left, right } = exprs[*value] else {
                        return None;
                    };
                    step = match (op, counter_of(left) == Some(counter), literal(right)) {
                        (BinaryOperator::Add, true, Some(s)) => Some((s, false)),
                        (BinaryOperator::Subtract, true, Some(s)) => Some((s, true)),
                        (BinaryOperator::Add, false, _) if counter_of(right) == Some(counter) => {
                            Some((literal(left)?, false))
                        }
                        _ => return None,
                    };
                }
                _ => return None,
            }
        }
        let (step, down) = step?;
        let rest = Block::from_vec(body.iter().skip(guard + 1).cloned().collect());
        if escapes(&rest) {
            return None;
        }
        let mut stored = Vec::new();
        stored_locals(self.src, &rest, &mut stored);
        if stored.contains(&counter) {
            return None;
        }
        let start = *self.known.get(&counter)?;
        let (values, end) = trips(start, op, bound, step, down, self.options.max_trip)?;
        Some(Plan {
            counter,
            values,
            end,
            guard,
        })
    }

    fn expand(&mut self, plan: &Plan, body: &Block, continuing: &Block, span: Span) {
        self.loops += 1;
        let saved = self.map.clone();
        for &value in &plan.values {
            self.map.clone_from(&saved);
            self.counters.insert(plan.counter, value);
            for (stmt, s) in body.span_iter().skip(plan.guard + 1) {
                match stmt {
                    // The body block of a `for`: splice it, so its stores forward.
                    Statement::Block(b) => self.walk_block(b),
                    _ => self.walk_stmt(stmt, *s),
                }
            }
            for (stmt, s) in continuing.span_iter() {
                match stmt {
                    Statement::Store { .. } => {}
                    _ => self.walk_stmt(stmt, *s),
                }
            }
        }
        self.counters.remove(&plan.counter);
        self.map = saved;
        let ptr = self.append(Expression::LocalVariable(plan.counter), span, None);
        let end = self.append(Expression::Literal(plan.end), span, None);
        self.known.insert(plan.counter, plan.end);
        self.push_stmt(
            Statement::Store {
                pointer: ptr,
                value: end,
            },
            span,
        );
    }
}
