//! One exit per function: early `return`s become stores to a result variable, and the code after
//! them runs only on the paths that did not return.
//!
//! Why: normalization inlines every helper at its call and takes the entry point's output from
//! its final top-level `return`, so both need functions whose only `return` is their last
//! statement. Real shaders often return early: a `switch` (or `if`/`else`) that returns from each
//! case (a debug-view selector), `if (n_dot_l <= 0.0) { return ambient; }` in a lighting helper, a
//! `return` from inside a loop. Rewritten here, before normalization, such a function stores the
//! value in a local `result` and ends with `return result;`; the nodes inside the cases become
//! ordinary nodes (cacheable when the branch is uniform).
//!
//! How, per block, knowing whether each statement never, sometimes or always returns:
//!
//! - `return v` becomes `result = v; returned = true;` — followed by `break` when it sits inside a
//!   `switch` or loop of the function (one that is not already ending its case), so the
//!   construct is left at once; the rest of its block is unreachable and dropped;
//! - after an `if` whose one side always returns and the other never does, the rest of the block
//!   moves into the side that does not return (no flag needed);
//! - after any other statement that may return, the rest is guarded: `if !returned { rest }` at
//!   the function's level, `if returned { break; }` inside a loop or `switch` that the statement's
//!   own `break` did not leave;
//! - the function then ends with `return result;` (a `returned` flag nobody reads is removed).
//!
//! The expression arena is kept (new expressions are appended), so the handles of every source
//! expression, and the spans of every statement, stay as they were. Functions with a single final
//! `return` are not touched, so the shaders reproj read before keep their node ids.

use naga::{Block, Expression, Function, Handle, LocalVariable, Span, Statement};

/// Whether a statement (or block) returns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Flow {
    Never,
    Maybe,
    Always,
}

impl Flow {
    fn join(self, other: Flow) -> Flow {
        if self == other { self } else { Flow::Maybe }
    }
}

/// `module` with every function and entry point rewritten to one exit, or `None` when every
/// function already has one (its only `return` is its last top-level statement).
pub(crate) fn single_exit(module: &naga::Module) -> Option<naga::Module> {
    let needs = |f: &Function| has_early_return(f);
    if !module.functions.iter().any(|(_, f)| needs(f))
        && !module.entry_points.iter().any(|ep| needs(&ep.function))
    {
        return None;
    }
    let mut module = module.clone();
    let bool_ty = module.types.insert(
        naga::Type {
            name: None,
            inner: naga::TypeInner::Scalar(naga::Scalar::BOOL),
        },
        Span::UNDEFINED,
    );
    for (_, f) in module.functions.iter_mut() {
        if needs(f) {
            rewrite(f, bool_ty);
        }
    }
    for ep in &mut module.entry_points {
        if needs(&ep.function) {
            rewrite(&mut ep.function, bool_ty);
        }
    }
    Some(module)
}

/// True when `fun` has a `return` that is not its last top-level statement.
pub(crate) fn has_early_return(fun: &Function) -> bool {
    fn returns(s: &Statement) -> bool {
        match s {
            Statement::Return { .. } => true,
            Statement::Block(b) => b.iter().any(returns),
            Statement::If { accept, reject, .. } => {
                accept.iter().any(returns) || reject.iter().any(returns)
            }
            Statement::Switch { cases, .. } => cases.iter().any(|c| c.body.iter().any(returns)),
            Statement::Loop {
                body, continuing, ..
            } => body.iter().any(returns) || continuing.iter().any(returns),
            _ => false,
        }
    }
    let n = fun.body.len();
    fun.body
        .iter()
        .enumerate()
        .any(|(i, s)| returns(s) && !(i + 1 == n && matches!(s, Statement::Return { .. })))
}

/// Where a block sits, for what a `return` in it must do.
#[derive(Debug, Clone, Copy)]
struct Place {
    /// Inside a loop or a `switch` of this function: `break` leaves the innermost one.
    breakable: bool,
    /// The top level of a `switch` case that does not fall through: its end leaves the switch.
    case_top: bool,
}

/// Where a statement is lowered: its place, its span, and the statements after it in its block
/// (which a statement that may return takes over).
struct At<'r> {
    place: Place,
    span: Span,
    rest: &'r mut std::vec::IntoIter<(Statement, Span)>,
}

/// What lowering one statement leaves to its block.
enum Next {
    /// Go on with the next statement.
    Statement,
    /// The block ends here with this flow (the rest, if any, already lowered into it).
    End(Flow),
}

struct Exits<'f> {
    fun: &'f mut Function,
    /// Pointer to the `result` local (`None` for a function without a result).
    result: Option<Handle<Expression>>,
    /// Pointer to the `returned` flag.
    flag: Handle<Expression>,
    flag_read: bool,
    yes: Handle<Expression>,
    /// Span of the last `return` met, for the final one.
    last_return: Span,
}

fn rewrite(fun: &mut Function, bool_ty: Handle<naga::Type>) {
    let result = fun.result.as_ref().map(|r| {
        let v = fun.local_variables.append(
            LocalVariable {
                name: Some("result".into()),
                ty: r.ty,
                init: None,
            },
            Span::UNDEFINED,
        );
        fun.expressions
            .append(Expression::LocalVariable(v), Span::UNDEFINED)
    });
    let flag_var = fun.local_variables.append(
        LocalVariable {
            name: Some("returned".into()),
            ty: bool_ty,
            init: None,
        },
        Span::UNDEFINED,
    );
    let flag = fun
        .expressions
        .append(Expression::LocalVariable(flag_var), Span::UNDEFINED);
    let yes = fun.expressions.append(
        Expression::Literal(naga::Literal::Bool(true)),
        Span::UNDEFINED,
    );
    let body = std::mem::take(&mut fun.body);
    let mut ex = Exits {
        fun,
        result,
        flag,
        flag_read: false,
        yes,
        last_return: Span::UNDEFINED,
    };
    let top = Place {
        breakable: false,
        case_top: false,
    };
    let stmts: Vec<(Statement, Span)> = body.span_iter().map(|(s, sp)| (s.clone(), *sp)).collect();
    let (mut new_body, _) = ex.block(stmts, top);
    if let Some(ptr) = ex.result {
        let span = ex.last_return;
        let start = ex.fun.expressions.len();
        let value = ex
            .fun
            .expressions
            .append(Expression::Load { pointer: ptr }, span);
        new_body.push(Statement::Emit(ex.fun.expressions.range_from(start)), span);
        new_body.push(Statement::Return { value: Some(value) }, span);
    }
    if !ex.flag_read {
        strip_stores(&mut new_body, flag);
    }
    fun.body = new_body;
}

impl Exits<'_> {
    /// Lower a list of statements; returns the new block and whether it returns. A dispatch on
    /// the statements that return or hold returns, one method each; the others are kept.
    fn block(&mut self, stmts: Vec<(Statement, Span)>, place: Place) -> (Block, Flow) {
        let mut out = Block::new();
        let mut iter = stmts.into_iter();
        while let Some((stmt, span)) = iter.next() {
            let at = At {
                place,
                span,
                rest: &mut iter,
            };
            let next = match stmt {
                Statement::Return { value } => self.return_stmt(&mut out, value, at),
                Statement::If {
                    condition,
                    accept,
                    reject,
                } => self.if_stmt(&mut out, If(condition, accept, reject), at),
                Statement::Block(b) => self.block_stmt(&mut out, &b, at),
                Statement::Switch { selector, cases } => {
                    self.switch_stmt(&mut out, selector, cases, at)
                }
                Statement::Loop {
                    body,
                    continuing,
                    break_if,
                } => self.loop_stmt(&mut out, (body, continuing, break_if), at),
                other => {
                    out.push(other, span);
                    Next::Statement
                }
            };
            if let Next::End(flow) = next {
                return (out, flow);
            }
        }
        (out, Flow::Never)
    }

    /// The rest of the block after a statement that may have returned, lowered into `out`.
    fn end_after_maybe(&mut self, out: &mut Block, at: At, left_construct: bool) -> Next {
        let rest: Vec<_> = at.rest.collect();
        let done = std::mem::take(out);
        let (block, flow) = self.after_maybe(done, rest, at.place, left_construct, at.span);
        *out = block;
        Next::End(flow)
    }

    /// A `return`: the value stored to `result`, the flag set, and a `break` out of the loop or
    /// case around it.
    fn return_stmt(&mut self, out: &mut Block, value: Option<Handle<Expression>>, at: At) -> Next {
        let span = at.span;
        self.last_return = span;
        if let (Some(ptr), Some(v)) = (self.result, value) {
            out.push(
                Statement::Store {
                    pointer: ptr,
                    value: v,
                },
                span,
            );
        }
        out.push(
            Statement::Store {
                pointer: self.flag,
                value: self.yes,
            },
            span,
        );
        if at.place.breakable && !at.place.case_top {
            out.push(Statement::Break, span);
        }
        Next::End(Flow::Always)
    }

    /// An `if` whose branches may return: the rest of the block moves into the branch that does
    /// not, or is guarded when either may.
    fn if_stmt(&mut self, out: &mut Block, If(condition, accept, reject): If, at: At) -> Next {
        let (place, span) = (at.place, at.span);
        let inner = Place {
            case_top: false,
            ..place
        };
        let (a, fa) = self.block(stmts_of(&accept), inner);
        let (r, fr) = self.block(stmts_of(&reject), inner);
        if (fa, fr) == (Flow::Never, Flow::Never) {
            out.push(If(condition, a, r).into(), span);
            return Next::Statement;
        }
        match (fa, fr) {
            (Flow::Always, Flow::Always) => {
                out.push(If(condition, a, r).into(), span);
                Next::End(Flow::Always)
            }
            // One side returns, the other falls through: the rest goes there.
            (Flow::Always, Flow::Never) | (Flow::Never, Flow::Always) => {
                let rest: Vec<_> = at.rest.collect();
                let (mut rest, f) = self.block(rest, place);
                let (a, r) = if fa == Flow::Never {
                    (concat(a, &mut rest), r)
                } else {
                    (a, concat(r, &mut rest))
                };
                out.push(If(condition, a, r).into(), span);
                Next::End(if f == Flow::Always {
                    Flow::Always
                } else {
                    Flow::Maybe
                })
            }
            _ => {
                out.push(If(condition, a, r).into(), span);
                // Inside a loop or switch the returns have already broken out.
                self.end_after_maybe(out, at, false)
            }
        }
    }

    /// A nested block: the rest is guarded when it may have returned.
    fn block_stmt(&mut self, out: &mut Block, b: &Block, at: At) -> Next {
        let inner = Place {
            case_top: false,
            ..at.place
        };
        let (nb, f) = self.block(stmts_of(b), inner);
        out.push(Statement::Block(nb), at.span);
        match f {
            Flow::Never => Next::Statement,
            Flow::Always => Next::End(Flow::Always),
            Flow::Maybe => self.end_after_maybe(out, at, false),
        }
    }

    /// A `switch`: each case lowered (a `break` leaves it without returning, a case that falls
    /// through ends as the next one does), the rest guarded when a case may have returned.
    fn switch_stmt(
        &mut self,
        out: &mut Block,
        selector: Handle<Expression>,
        cases: Vec<naga::SwitchCase>,
        at: At,
    ) -> Next {
        let mut flows = Vec::with_capacity(cases.len());
        let mut new_cases = Vec::with_capacity(cases.len());
        for case in &cases {
            let inner = Place {
                breakable: true,
                case_top: !case.fall_through,
            };
            let (body, f) = self.block(stmts_of(&case.body), inner);
            // A `break` leaves the switch without returning.
            let f = if f == Flow::Always && breaks(&case.body) {
                Flow::Maybe
            } else {
                f
            };
            flows.push(f);
            new_cases.push(naga::SwitchCase {
                value: case.value,
                body,
                fall_through: case.fall_through,
            });
        }
        // A case that falls through ends as the next one does.
        let mut next = Flow::Never;
        for (case, f) in cases.iter().zip(flows.iter_mut()).rev() {
            if case.fall_through && *f == Flow::Never {
                *f = next;
            } else if case.fall_through && *f == Flow::Maybe && next == Flow::Always {
                *f = Flow::Always;
            }
            next = *f;
        }
        let flow = flows
            .iter()
            .copied()
            .reduce(Flow::join)
            .unwrap_or(Flow::Never);
        out.push(
            Statement::Switch {
                selector,
                cases: new_cases,
            },
            at.span,
        );
        match flow {
            Flow::Never => Next::Statement,
            Flow::Always => Next::End(Flow::Always),
            Flow::Maybe => self.end_after_maybe(out, at, true),
        }
    }

    /// A `loop` whose body may return (its `break` leaves the loop): the rest is guarded.
    fn loop_stmt(
        &mut self,
        out: &mut Block,
        (body, continuing, break_if): (Block, Block, Option<Handle<Expression>>),
        at: At,
    ) -> Next {
        let inner = Place {
            breakable: true,
            case_top: false,
        };
        let (nb, f) = self.block(stmts_of(&body), inner);
        out.push(
            Statement::Loop {
                body: nb,
                continuing,
                break_if,
            },
            at.span,
        );
        if f != Flow::Never {
            self.end_after_maybe(out, at, true)
        } else {
            Next::Statement
        }
    }

    /// The rest of a block after a statement that may have returned. `left_construct`: the
    /// statement was a loop or switch, whose `break`s left only itself.
    fn after_maybe(
        &mut self,
        mut out: Block,
        rest: Vec<(Statement, Span)>,
        place: Place,
        left_construct: bool,
        span: Span,
    ) -> (Block, Flow) {
        let or_always = |f| {
            if f == Flow::Always {
                Flow::Always
            } else {
                Flow::Maybe
            }
        };
        if place.breakable {
            // A return inside an `if` or block here has broken out already; one inside a loop or
            // switch left only that: leave ours too (unless it ends here anyway).
            if left_construct && !(rest.is_empty() && place.case_top) {
                let cond = self.flag_load(&mut out, span);
                let leave = Block::from_vec(vec![Statement::Break]);
                out.push(If(cond, leave, Block::new()).into(), span);
            }
            let (mut rest, f) = self.block(rest, place);
            out.append(&mut rest);
            return (out, or_always(f));
        }
        if rest.is_empty() {
            return (out, Flow::Maybe);
        }
        // `if !returned { rest }`
        let cond = self.flag_load(&mut out, span);
        let start = self.fun.expressions.len();
        let not = self.fun.expressions.append(
            Expression::Unary {
                op: naga::UnaryOperator::LogicalNot,
                expr: cond,
            },
            span,
        );
        out.push(
            Statement::Emit(self.fun.expressions.range_from(start)),
            span,
        );
        let (rest, f) = self.block(rest, place);
        out.push(If(not, rest, Block::new()).into(), span);
        (out, or_always(f))
    }

    /// `returned`, loaded (and emitted) at the end of `out`.
    fn flag_load(&mut self, out: &mut Block, span: Span) -> Handle<Expression> {
        self.flag_read = true;
        let start = self.fun.expressions.len();
        let load = self
            .fun
            .expressions
            .append(Expression::Load { pointer: self.flag }, span);
        out.push(
            Statement::Emit(self.fun.expressions.range_from(start)),
            span,
        );
        load
    }
}

/// An `if` statement.
struct If(Handle<Expression>, Block, Block);

impl From<If> for Statement {
    fn from(If(condition, accept, reject): If) -> Statement {
        Statement::If {
            condition,
            accept,
            reject,
        }
    }
}

/// True when `block` has a `break` that leaves the construct around it (not one of an inner loop
/// or switch).
fn breaks(block: &Block) -> bool {
    block.iter().any(|s| match s {
        Statement::Break => true,
        Statement::Block(b) => breaks(b),
        Statement::If { accept, reject, .. } => breaks(accept) || breaks(reject),
        _ => false,
    })
}

fn stmts_of(block: &Block) -> Vec<(Statement, Span)> {
    block.span_iter().map(|(s, sp)| (s.clone(), *sp)).collect()
}

fn concat(mut a: Block, b: &mut Block) -> Block {
    a.append(b);
    a
}

/// Remove the stores to `flag` (nobody reads it).
fn strip_stores(block: &mut Block, flag: Handle<Expression>) {
    let stmts: Vec<(Statement, Span)> = stmts_of(block);
    let mut out = Block::with_capacity(stmts.len());
    for (mut s, span) in stmts {
        match &mut s {
            Statement::Store { pointer, .. } if *pointer == flag => continue,
            Statement::Block(b) => strip_stores(b, flag),
            Statement::If { accept, reject, .. } => {
                strip_stores(accept, flag);
                strip_stores(reject, flag);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    strip_stores(&mut c.body, flag);
                }
            }
            Statement::Loop { body, .. } => strip_stores(body, flag),
            _ => {}
        }
        out.push(s, span);
    }
    *block = out;
}
