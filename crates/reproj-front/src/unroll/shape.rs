//! What the unroller reads off a loop before expanding it: the counter's values over the
//! iterations, and whether the body escapes the loop or stores to its counter. Pure functions of
//! the source IR, kept apart from the walker that copies and expands.

use naga::{BinaryOperator, Block, Function, Handle, Literal, LocalVariable, Statement};

use crate::ir;

/// `a op b` as `b op' a`.
pub(super) fn flip(op: BinaryOperator) -> Option<BinaryOperator> {
    use BinaryOperator as B;
    Some(match op {
        B::Less => B::Greater,
        B::LessEqual => B::GreaterEqual,
        B::Greater => B::Less,
        B::GreaterEqual => B::LessEqual,
        B::NotEqual => B::NotEqual,
        _ => return None,
    })
}

/// The counter's values over the iterations and its value after the loop, when the loop ends
/// within `max` iterations.
pub(super) fn trips(
    start: Literal,
    op: BinaryOperator,
    bound: Literal,
    step: Literal,
    down: bool,
    max: u32,
) -> Option<(Vec<Literal>, Literal)> {
    use BinaryOperator as B;
    let as_i64 = |l: Literal| match l {
        Literal::I32(v) => Some(i64::from(v)),
        Literal::U32(v) => Some(i64::from(v)),
        _ => None,
    };
    let signed = matches!(start, Literal::I32(_));
    if signed != matches!(bound, Literal::I32(_)) || signed != matches!(step, Literal::I32(_)) {
        return None;
    }
    let (mut v, b, s) = (as_i64(start)?, as_i64(bound)?, as_i64(step)?);
    let s = if down { -s } else { s };
    let lit = |v: i64| {
        if signed {
            i32::try_from(v).ok().map(Literal::I32)
        } else {
            u32::try_from(v).ok().map(Literal::U32)
        }
    };
    let mut values = Vec::new();
    loop {
        let go_on = match op {
            B::Less => v < b,
            B::LessEqual => v <= b,
            B::Greater => v > b,
            B::GreaterEqual => v >= b,
            B::NotEqual => v != b,
            _ => return None,
        };
        if !go_on {
            return Some((values, lit(v)?));
        }
        if values.len() >= max as usize {
            return None;
        }
        values.push(lit(v)?);
        // Wrapping or leaving the type's range: not a loop to unroll.
        v += s;
        lit(v)?;
    }
}

/// Whether `block` holds a `break` or `continue` of the loop it is in, or a `return`.
pub(super) fn escapes(block: &Block) -> bool {
    escapes_from(block, false)
}

/// [`escapes`], where a `break` leaves an enclosing switch when `in_switch`.
fn escapes_from(block: &Block, in_switch: bool) -> bool {
    block.iter().any(|s| match s {
        Statement::Break => !in_switch,
        Statement::Continue | Statement::Return { .. } => true,
        Statement::Block(b) => escapes_from(b, in_switch),
        Statement::If { accept, reject, .. } => {
            escapes_from(accept, in_switch) || escapes_from(reject, in_switch)
        }
        Statement::Switch { cases, .. } => cases.iter().any(|c| escapes_from(&c.body, true)),
        // Breaks and continues of a nested loop are its own; a return is not.
        Statement::Loop {
            body, continuing, ..
        } => returns(body) || returns(continuing),
        _ => false,
    })
}

fn returns(block: &Block) -> bool {
    block.iter().any(|s| match s {
        Statement::Return { .. } => true,
        Statement::Block(b) => returns(b),
        Statement::If { accept, reject, .. } => returns(accept) || returns(reject),
        Statement::Switch { cases, .. } => cases.iter().any(|c| returns(&c.body)),
        Statement::Loop {
            body, continuing, ..
        } => returns(body) || returns(continuing),
        _ => false,
    })
}

/// Locals stored anywhere in `block` (source side).
pub(super) fn stored_locals(fun: &Function, block: &Block, out: &mut Vec<Handle<LocalVariable>>) {
    for s in block.iter() {
        match s {
            Statement::Store { pointer, .. } => {
                out.extend(ir::root_local(&fun.expressions, *pointer))
            }
            Statement::Block(b) => stored_locals(fun, b, out),
            Statement::If { accept, reject, .. } => {
                stored_locals(fun, accept, out);
                stored_locals(fun, reject, out);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    stored_locals(fun, &c.body, out);
                }
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                stored_locals(fun, body, out);
                stored_locals(fun, continuing, out);
            }
            _ => {}
        }
    }
}
