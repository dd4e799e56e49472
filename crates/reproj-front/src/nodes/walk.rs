//! Where each expression of the normalized function is evaluated (in a loop, under a non-uniform
//! branch, how many times), the stores to its locals and the conditions around each `discard`
//! ([`Walk`]), and the dependency edges built from them ([`dependencies`]): a load depends on
//! every store to its local and on the control that guards it.

use std::collections::HashMap;

use naga::{Block, Expression, Handle, Statement};

use crate::cost::trip_count;
use crate::ir;

/// Where an expression is evaluated.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Place {
    pub(super) in_loop: bool,
    pub(super) non_uniform: bool,
    /// Product of the enclosing loops' trip counts.
    pub(super) weight: f64,
}

/// A store to a local: the value, the pointer and the conditions around it.
pub(super) struct StoreInfo {
    value: Handle<Expression>,
    pointer: Handle<Expression>,
    control: Vec<Handle<Expression>>,
}

/// Dependency edges of each expression: `(dependency, discontinuous)`, its operands and, for a
/// load, every store to its local with the pointer and the control that guards it.
pub(super) fn dependencies(
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
pub(super) struct Walk<'a> {
    fun: &'a naga::Function,
    info: &'a naga::valid::FunctionInfo,
    /// The conditions of the statements around the one being walked.
    control: Vec<Handle<Expression>>,
    pub(super) places: HashMap<Handle<Expression>, Place>,
    pub(super) stores: HashMap<Handle<naga::LocalVariable>, Vec<StoreInfo>>,
    /// The conditions around each `discard`.
    pub(super) kills: Vec<Handle<Expression>>,
}

impl<'a> Walk<'a> {
    /// Walk the function's body.
    pub(super) fn function(
        fun: &'a naga::Function,
        info: &'a naga::valid::FunctionInfo,
    ) -> Walk<'a> {
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
