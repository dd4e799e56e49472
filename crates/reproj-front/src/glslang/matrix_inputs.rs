//! Matrix fragment inputs split into their columns.
//!
//! GLSL lets a fragment input be a matrix (`layout(location = 2) in mat4 view;`, one location per
//! column: Vulkan samples pass a camera's matrices to the fragment stage this way); WGSL, and
//! naga's validator, take only scalars and vectors as entry-point inputs. naga's SPIR-V reader
//! copies each input from an entry-point argument into a private global in a wrapper
//! (`Store { pointer: global, value: FunctionArgument(i) }` at the top of its body). For a matrix
//! argument, the wrapper here takes one vector argument per column, at consecutive locations with
//! the matrix's interpolation, and stores the matrix composed of them: the same values reach the
//! shader, through an interface WGSL can express. Any other use of a matrix argument is left as it
//! is (naga's validator then names it).

use naga::{Binding, Expression, Function, Handle, Module, Statement, Type, TypeInner};

use crate::ir::operands;

/// Split every matrix input of every fragment entry point of `module` into column vectors.
pub(crate) fn split_matrix_inputs(module: &mut Module) {
    for ep in &mut module.entry_points {
        if ep.stage == naga::ShaderStage::Fragment {
            split_function(&mut module.types, &mut ep.function);
        }
    }
}

/// A matrix argument: its index, and its columns' count and vector type.
struct MatrixArg {
    index: usize,
    columns: u32,
    column_ty: Handle<Type>,
}

fn split_function(types: &mut naga::UniqueArena<Type>, fun: &mut Function) {
    let mut matrices = Vec::new();
    for (index, arg) in fun.arguments.iter().enumerate() {
        let TypeInner::Matrix {
            columns,
            rows,
            scalar,
        } = types[arg.ty].inner
        else {
            continue;
        };
        if !matches!(arg.binding, Some(Binding::Location { .. })) {
            continue;
        }
        let column_ty = types.insert(
            Type {
                name: None,
                inner: TypeInner::Vector { size: rows, scalar },
            },
            naga::Span::UNDEFINED,
        );
        matrices.push(MatrixArg {
            index,
            columns: columns as u32,
            column_ty,
        });
    }
    matrices.retain(|m| only_stored(fun, m.index));
    if matrices.is_empty() {
        return;
    }

    // The new argument list, and where each old argument starts in it.
    let mut starts = Vec::with_capacity(fun.arguments.len());
    let mut arguments = Vec::new();
    for (index, arg) in fun.arguments.iter().enumerate() {
        starts.push(arguments.len() as u32);
        match matrices.iter().find(|m| m.index == index) {
            Some(m) => {
                for c in 0..m.columns {
                    let mut binding = arg.binding.clone();
                    if let Some(Binding::Location { location, .. }) = &mut binding {
                        *location += c;
                    }
                    arguments.push(naga::FunctionArgument {
                        name: arg.name.as_ref().map(|n| format!("{n}_col{c}")),
                        ty: m.column_ty,
                        binding,
                    });
                }
            }
            None => arguments.push(arg.clone()),
        }
    }
    let old_types: Vec<Handle<Type>> = fun.arguments.iter().map(|a| a.ty).collect();
    fun.arguments = arguments;

    // Renumber the argument expressions; a matrix's first expression becomes its first column.
    let handles: Vec<Handle<Expression>> = fun.expressions.iter().map(|(h, _)| h).collect();
    let mut matrix_exprs = Vec::new();
    for h in handles {
        if let Expression::FunctionArgument(i) = fun.expressions[h] {
            let i = i as usize;
            fun.expressions[h] = Expression::FunctionArgument(starts[i]);
            if let Some(m) = matrices.iter().find(|m| m.index == i) {
                matrix_exprs.push((h, starts[i], m.columns, old_types[i]));
            }
        }
    }

    // Each matrix composed of its columns, after every other expression.
    let mut composed = Vec::new();
    for (h, start, columns, ty) in matrix_exprs {
        let span = fun.expressions.get_span(h);
        let mut components = vec![h];
        for c in 1..columns {
            components.push(
                fun.expressions
                    .append(Expression::FunctionArgument(start + c), span),
            );
        }
        let compose = fun
            .expressions
            .append(Expression::Compose { ty, components }, span);
        composed.push((h, compose));
    }

    // The stores of a matrix argument store the composed matrix, emitted just before.
    let body = std::mem::take(&mut fun.body);
    let mut emitted = Vec::new();
    for (statement, span) in body.span_into_iter() {
        let statement = match statement {
            Statement::Store { pointer, value } => {
                match composed.iter().find(|&&(h, _)| h == value) {
                    Some(&(_, compose)) => {
                        if !emitted.contains(&compose) {
                            fun.body.push(
                                Statement::Emit(naga::Range::new_from_bounds(compose, compose)),
                                span,
                            );
                            emitted.push(compose);
                        }
                        Statement::Store {
                            pointer,
                            value: compose,
                        }
                    }
                    None => Statement::Store { pointer, value },
                }
            }
            other => other,
        };
        fun.body.push(statement, span);
    }
}

/// True when argument `index` is read only as the value of stores at the top of the body, as
/// naga's SPIR-V reader writes its entry-point wrappers (so the stores can take another value).
fn only_stored(fun: &Function, index: usize) -> bool {
    let args: Vec<Handle<Expression>> = fun
        .expressions
        .iter()
        .filter(|(_, e)| matches!(e, Expression::FunctionArgument(i) if *i as usize == index))
        .map(|(h, _)| h)
        .collect();
    let in_expression = fun
        .expressions
        .iter()
        .any(|(_, e)| operands(e).iter().any(|o| args.contains(o)));
    if in_expression {
        return false;
    }
    fun.body.iter().all(|s| match s {
        Statement::Emit(_) => true,
        Statement::Store { pointer, .. } => !args.contains(pointer),
        Statement::Call { arguments, .. } => !arguments.iter().any(|a| args.contains(a)),
        Statement::Return { value } => !value.is_some_and(|v| args.contains(&v)),
        _ => false,
    })
}
