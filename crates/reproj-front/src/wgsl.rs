//! The one WGSL writer: every module reproj writes as WGSL (an instanced pass, naga's WGSL of a
//! GLSL or SPIR-V input) goes through [`write_wgsl`], so the text reaches a fixed point on a
//! round trip (names naga invented dropped) and keeps what naga's writer leaves out (the global
//! `diagnostic` directives, `enable f16;` where only expressions are f16).

use naga::Module;

/// A name naga's WGSL writer invents for an expression it binds with `let` (`_e12`, `_e12_1`):
/// the number is the expression's handle.
pub fn generated(name: &str) -> bool {
    name.strip_prefix("_e").is_some_and(|rest| {
        !rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit() || b == b'_')
    })
}

/// Write WGSL. Names naga's writer invented on an earlier trip (`_e12`, `_e12_1`, ...) are dropped
/// first, so that the writer invents them again the same way and the text reaches a fixed point.
/// The module's global `diagnostic(...)` directives, which naga's writer leaves out, are written
/// first. `enable f16;` is written whenever an expression is f16 data (naga's writer looks only at
/// the type arena, which need not hold f16 when literals and conversions make the values).
pub fn write_wgsl(
    module: &Module,
    info: &naga::valid::ModuleInfo,
) -> Result<String, naga::back::wgsl::Error> {
    // naga's writer has no WGSL for a ray query and panics on one (`unreachable!`).
    let functions = module.functions.iter().map(|(_, f)| f);
    if functions
        .chain(module.entry_points.iter().map(|ep| &ep.function))
        .any(|f| has_ray_query(&f.body))
    {
        return Err(naga::back::wgsl::Error::Unsupported {
            kind: "statement",
            value: "a ray query (naga's WGSL writer cannot write one)".into(),
        });
    }
    let mut module = module.clone();
    let strip = |f: &mut naga::Function| f.named_expressions.retain(|_, name| !generated(name));
    for (_, f) in module.functions.iter_mut() {
        strip(f);
    }
    for ep in &mut module.entry_points {
        strip(&mut ep.function);
    }
    let text =
        naga::back::wgsl::write_string(&module, info, naga::back::wgsl::WriterFlags::empty())?;
    let enable = if uses_f16(&module, info) && !text.starts_with("enable f16;") {
        "enable f16;\n\n"
    } else {
        ""
    };
    Ok(diagnostic_directives(&module) + enable + &text)
}

/// Whether `block` or a block inside it holds a ray query.
fn has_ray_query(block: &naga::Block) -> bool {
    use naga::Statement as S;
    block.iter().any(|s| match s {
        S::RayQuery { .. } => true,
        S::Block(b) => has_ray_query(b),
        S::If { accept, reject, .. } => has_ray_query(accept) || has_ray_query(reject),
        S::Switch { cases, .. } => cases.iter().any(|c| has_ray_query(&c.body)),
        S::Loop {
            body, continuing, ..
        } => has_ray_query(body) || has_ray_query(continuing),
        _ => false,
    })
}

/// True when a type or an expression of `module` is f16 data.
fn uses_f16(module: &Module, info: &naga::valid::ModuleInfo) -> bool {
    let f16 = |inner: &naga::TypeInner| inner.scalar() == Some(naga::Scalar::F16);
    let in_function = |f: &naga::Function, fi: &naga::valid::FunctionInfo| {
        f.expressions
            .iter()
            .any(|(h, _)| f16(fi[h].ty.inner_with(&module.types)))
    };
    module.types.iter().any(|(_, t)| f16(&t.inner))
        || module
            .functions
            .iter()
            .any(|(h, f)| in_function(f, &info[h]))
        || module
            .entry_points
            .iter()
            .enumerate()
            .any(|(i, ep)| in_function(&ep.function, info.get_entry_point(i)))
}

/// The module's global diagnostic filters as WGSL directives, outermost first.
fn diagnostic_directives(module: &Module) -> String {
    use naga::diagnostic_filter::{
        FilterableTriggeringRule as R, Severity, StandardFilterableTriggeringRule as S,
    };
    let mut lines = Vec::new();
    let mut node = module.diagnostic_filter_leaf;
    while let Some(h) = node {
        let n = &module.diagnostic_filters[h];
        let severity = match n.inner.new_severity {
            Severity::Off => "off",
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Error => "error",
        };
        let rule = match &n.inner.triggering_rule {
            R::Standard(S::DerivativeUniformity) => "derivative_uniformity".to_string(),
            R::Unknown(name) => name.to_string(),
            R::User(parts) => format!("{}.{}", parts[0], parts[1]),
        };
        lines.push(format!("diagnostic({severity}, {rule});\n"));
        node = n.parent;
    }
    lines.reverse();
    if lines.is_empty() {
        String::new()
    } else {
        lines.concat() + "\n"
    }
}
