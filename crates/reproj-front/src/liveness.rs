//! Liveness: which expressions and statements of a call-free function contribute to its result or
//! side effects. Stores to variables nobody reads, loops and branches left with nothing live inside,
//! and the expressions only they used are dead. The rebuild walker copies only the live part.

use std::collections::HashSet;

use naga::{Block, Expression, Function, Handle, LocalVariable, Statement};

use crate::ir;

/// Live expressions and live statements (by pre-order statement index, see [`crate::rebuild`]).
#[derive(Debug, Default, Clone)]
pub struct Liveness {
    pub exprs: HashSet<Handle<Expression>>,
    pub stmts: HashSet<usize>,
    pub vars: HashSet<Handle<LocalVariable>>,
}

/// Compute the liveness of `fun` (least fixed point: returns, discards and stores to globals are
/// live; a store is live when its variable is read by a live expression; a loop or branch is live
/// when something inside it is).
pub fn liveness(fun: &Function) -> Liveness {
    let mut l = Liveness::default();
    loop {
        let before = (l.exprs.len(), l.stmts.len(), l.vars.len());
        let mut index = 0;
        walk(fun, &fun.body, &mut l, &mut index, false);
        if (l.exprs.len(), l.stmts.len(), l.vars.len()) == before {
            return l;
        }
    }
}

fn mark(fun: &Function, l: &mut Liveness, h: Handle<Expression>) {
    let mut stack = vec![h];
    while let Some(h) = stack.pop() {
        if !l.exprs.insert(h) {
            continue;
        }
        let e = &fun.expressions[h];
        if let Expression::Load { pointer } = *e
            && let Some(v) = ir::root_local(&fun.expressions, pointer)
        {
            l.vars.insert(v);
        }
        stack.extend(ir::operands(e));
    }
}

/// Walk a block; returns whether anything in it is live. `in_live_loop`: break/continue are live.
fn walk(
    fun: &Function,
    block: &Block,
    l: &mut Liveness,
    index: &mut usize,
    in_live_loop: bool,
) -> bool {
    let mut any = false;
    for stmt in block.iter() {
        let i = *index;
        *index += 1;
        let live = match stmt {
            Statement::Emit(_) => false,
            Statement::Return { value } => {
                if let Some(v) = value {
                    mark(fun, l, *v);
                }
                true
            }
            Statement::Kill => true,
            Statement::Break | Statement::Continue => in_live_loop,
            Statement::Store { pointer, value } => {
                let live = match ir::root_local(&fun.expressions, *pointer) {
                    Some(v) => l.vars.contains(&v),
                    None => true,
                };
                if live {
                    mark(fun, l, *pointer);
                    mark(fun, l, *value);
                }
                live
            }
            Statement::Block(b) => walk(fun, b, l, index, in_live_loop),
            Statement::If {
                condition,
                accept,
                reject,
            } => {
                let a = walk(fun, accept, l, index, in_live_loop);
                let r = walk(fun, reject, l, index, in_live_loop);
                if a || r {
                    mark(fun, l, *condition);
                }
                a || r
            }
            Statement::Switch { selector, cases } => {
                let mut live = false;
                for c in cases {
                    live |= walk(fun, &c.body, l, index, in_live_loop);
                }
                if live {
                    mark(fun, l, *selector);
                }
                live
            }
            Statement::Loop {
                body,
                continuing,
                break_if,
            } => {
                // First: is anything but the loop's own control live? Then walk again with
                // break/continue live so that their conditions are kept.
                let start = *index;
                let mut probe = l.clone();
                let mut k = start;
                let live = walk(fun, body, &mut probe, &mut k, false)
                    | walk(fun, continuing, &mut probe, &mut k, false)
                    || l.stmts.contains(&i);
                *index = start;
                let live_inner =
                    walk(fun, body, l, index, live) | walk(fun, continuing, l, index, live);
                if (live || live_inner)
                    && let Some(b) = break_if
                {
                    mark(fun, l, *b);
                }
                live || live_inner
            }
            // Anything else has effects we do not model: keep it.
            _ => {
                let mut e = Vec::new();
                stmt_operands(stmt, &mut e);
                for h in e {
                    mark(fun, l, h);
                }
                true
            }
        };
        if live {
            l.stmts.insert(i);
            any = true;
        }
    }
    any
}

fn stmt_operands(stmt: &Statement, out: &mut Vec<Handle<Expression>>) {
    if let Statement::ImageStore {
        image,
        coordinate,
        array_index,
        value,
    } = stmt
    {
        out.extend([*image, *coordinate, *value]);
        out.extend(*array_index);
    }
}
