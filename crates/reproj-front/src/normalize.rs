//! Normalization: the fragment entry point as one expression DAG.
//!
//! Every helper the entry point calls is inlined (recursively, with its locals and arguments),
//! local-variable loads in straight-line code are replaced by the stored value, identical pure
//! expressions are shared, and dead code is dropped. Loops and branches stay statements; a value
//! read after a loop stays a `Load`, whose subtree is the loop. The result is a valid module with a
//! single fragment entry point, and the output color's expression (the *root*).

use std::collections::HashMap;

use naga::{Expression, Handle, Span};

use crate::rebuild::{Rebuilt, Rewrite, rebuild_live};
use crate::shader::{FrontError, Lang, Shader, validator};
use crate::unroll::{UnrollOptions, unroll};

/// A normalized shader: one fragment entry point whose result is the root of an expression DAG.
#[derive(Debug, Clone)]
pub struct Normalized {
    /// Module with only the chosen entry point (index 0) and what it uses; helpers inlined away.
    pub module: naga::Module,
    pub info: naga::valid::ModuleInfo,
    /// Name of the entry point.
    pub entry: String,
    /// The output color: the `@location(0)` value of the final top-level `return`.
    pub root: Handle<Expression>,
    /// Expressions that came from an inlined helper, with the span of the call in the entry point.
    pub call_site: HashMap<Handle<Expression>, Span>,
    /// The unrolling it was normalized with (node ids depend on it).
    pub unroll: UnrollOptions,
}

impl Normalized {
    /// The normalized entry-point function.
    pub fn function(&self) -> &naga::Function {
        &self.module.entry_points[0].function
    }

    /// Analysis results of the normalized entry point.
    pub fn function_info(&self) -> &naga::valid::FunctionInfo {
        self.info.get_entry_point(0)
    }
}

/// Options of [`normalize`].
#[derive(Debug, Clone, Default)]
pub struct NormalizeOptions {
    /// Fragment entry point name; `None` picks the only one.
    pub entry: Option<String>,
    /// Constant-trip loops to unroll after inlining (their iterations then forward like
    /// straight-line code, so per-iteration values become nodes).
    pub unroll: UnrollOptions,
}

/// Normalize the chosen fragment entry point of `shader`.
pub fn normalize(shader: &Shader, opts: &NormalizeOptions) -> Result<Normalized, FrontError> {
    let index = shader.fragment_entry(opts.entry.as_deref())?;
    // Early returns (in the entry point or a helper) rewritten to one exit per function. Should
    // the rewrite not validate (a bug), the shader is read as written, and an early return in a
    // helper is refused with its place as before.
    let single =
        crate::exits::single_exit(&shader.module).filter(|m| validator().validate(m).is_ok());
    let source = single.as_ref().unwrap_or(&shader.module);
    let ep = &source.entry_points[index];
    if ep.function.result.is_none() {
        return Err(shader.unsupported(
            shader.entry_span(&ep.name),
            format!(
                "the fragment entry point `{}` has no output: reproj caches part of the color \
                 it returns at @location(0)",
                ep.name
            ),
        ));
    }
    let located = |e: FrontError| match e {
        FrontError::UnsupportedAt { span, what } => shader.unsupported(span, what),
        e => e,
    };
    let rebuilt = rebuild_live(source, &ep.function, &Rewrite::Normalize).map_err(located)?;
    let rebuilt = unroll_and_forward(source, rebuilt, &opts.unroll).map_err(located)?;
    let root_value = rebuilt.root.ok_or_else(|| {
        shader.unsupported(
            shader.entry_span(&ep.name),
            format!(
                "the fragment entry point `{}` never returns its output",
                ep.name
            ),
        )
    })?;
    let call_site = rebuilt.call_site;
    let mut module = source.clone();
    module.entry_points = vec![naga::EntryPoint {
        function: rebuilt.function,
        ..ep.clone()
    }];
    module.functions = naga::Arena::new();
    let before = module.entry_points[0].function.expressions.len();
    let mut compacted = module.clone();
    naga::compact::compact(&mut compacted, naga::compact::KeepUnused::No);
    if compacted.entry_points[0].function.expressions.len() == before {
        module = compacted;
    }
    let info = validator()
        .validate(&module)
        .map_err(|e| FrontError::Internal {
            what: format!(
                "the normalized module does not validate ({}); please report this shader",
                e.emit_to_string(&shader.source)
            ),
        })?;
    // The root is the @location(0) member when the entry point returns a struct.
    let fun = &module.entry_points[0].function;
    let root = match fun.result.as_ref().map(|r| &module.types[r.ty].inner) {
        Some(naga::TypeInner::Struct { members, .. }) => {
            let loc0 = members
                .iter()
                .position(|m| {
                    matches!(m.binding, Some(naga::Binding::Location { location: 0, .. }))
                })
                .ok_or_else(|| {
                    shader.unsupported(
                        shader.entry_span(&ep.name),
                        "the output struct has no @location(0) member",
                    )
                })?;
            match &fun.expressions[root_value] {
                Expression::Compose { components, .. } => components[loc0],
                _ => {
                    let at = Some(fun.expressions.get_span(root_value))
                        .filter(|s| s.is_defined())
                        .or_else(|| last_return(&ep.function.body))
                        .unwrap_or_else(|| shader.entry_span(&ep.name));
                    return Err(shader.unsupported(
                        at,
                        "the returned output struct must be built in straight-line code (a \
                         constructor, or its fields stored one by one outside branches)",
                    ));
                }
            }
        }
        _ => root_value,
    };
    if shader.lang != Lang::Wgsl {
        check_traced(shader, &module, root)?;
    }
    // The root must be a node (f32/f16 data), or `NodeTable::root` has nothing to find.
    let root_ty = info.get_entry_point(0)[root].ty.inner_with(&module.types);
    if !matches!(
        root_ty.scalar(),
        Some(naga::Scalar {
            kind: naga::ScalarKind::Float,
            width: 2 | 4
        })
    ) {
        return Err(shader.unsupported(
            fun.expressions.get_span(root),
            "the output color must be f32 or f16 data (not integer or f64)",
        ));
    }
    Ok(Normalized {
        module,
        info,
        entry: ep.name.clone(),
        root,
        call_site,
        unroll: opts.unroll,
    })
}

/// The span of the last top-level `return` of a function body.
fn last_return(body: &naga::Block) -> Option<Span> {
    body.span_iter()
        .filter(|(s, span)| matches!(s, naga::Statement::Return { .. }) && span.is_defined())
        .map(|(_, span)| *span)
        .last()
}

/// Unroll the loops of a normalized function and normalize it again, so that the unrolled
/// iterations forward like straight-line code; the call sites follow the copies.
fn unroll_and_forward(
    module: &naga::Module,
    rebuilt: Rebuilt,
    options: &UnrollOptions,
) -> Result<Rebuilt, FrontError> {
    if options.max_trip == 0 {
        return Ok(rebuilt);
    }
    let unrolled = unroll(module, &rebuilt.function, options);
    if unrolled.loops == 0 {
        return Ok(rebuilt);
    }
    let again = rebuild_live(module, &unrolled.function, &Rewrite::Normalize)?;
    let mut call_site = HashMap::new();
    for (copy, origin) in unrolled.origin.iter().enumerate() {
        if let (Some(origin), Some(Some(new))) = (origin, again.map.get(copy))
            && let Some(span) = rebuilt.call_site.get(origin)
        {
            call_site.entry(*new).or_insert(*span);
        }
    }
    Ok(Rebuilt { call_site, ..again })
}

/// GLSL and SPIR-V outputs are variables that a wrapper entry point reads back after calling the
/// real `main`: after normalization the output must be the value written, or a load of a local
/// variable whose stores the node table follows. A zero (never written) or a load from memory
/// reproj does not follow means the output could not be traced: say so rather than report nothing
/// cacheable.
fn check_traced(
    shader: &Shader,
    module: &naga::Module,
    root: Handle<Expression>,
) -> Result<(), FrontError> {
    let fun = &module.entry_points[0].function;
    let span = fun.expressions.get_span(root);
    let lang = match shader.lang {
        Lang::Glsl => "GLSL",
        _ => "SPIR-V",
    };
    // The value the output is made of, past member and component selection.
    let mut value = root;
    while let Expression::AccessIndex { base, .. }
    | Expression::Access { base, .. }
    | Expression::Swizzle { vector: base, .. } = fun.expressions[value]
    {
        value = base;
    }
    match fun.expressions[value] {
        Expression::ZeroValue(_) => Err(shader.unsupported(
            span,
            format!(
                "the output is never written: the {lang} entry point returns its output variable \
                 unwritten (write it in `main`, outside helpers with early returns)"
            ),
        )),
        Expression::Load { pointer }
            if crate::ir::root_local(&fun.expressions, pointer).is_none() =>
        {
            let name = crate::ir::root_global(&fun.expressions, pointer)
                .and_then(|g| module.global_variables[g].name.clone())
                .unwrap_or_else(|| "memory".into());
            Err(shader.unsupported(
                span,
                format!(
                    "the output is read back from `{name}`, which reproj cannot follow to the value \
                     written (the {lang} output must be written from values computed in `main`)"
                ),
            ))
        }
        _ => Ok(()),
    }
}
