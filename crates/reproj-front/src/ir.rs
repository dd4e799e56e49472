//! Small helpers over naga IR that every stage needs: the operands of an expression, rebuilding an
//! expression with mapped operands, the local variable a pointer expression points into, and a
//! module-wide diagnostic filter.

use naga::{Expression, Handle, SampleLevel};

/// The operand handles of `expr`, in a fixed order (the order `map_operands` visits them).
pub fn operands(expr: &Expression) -> Vec<Handle<Expression>> {
    let mut out = Vec::new();
    let mut copy = expr.clone();
    map_operands(&mut copy, &mut |h| {
        out.push(h);
        h
    });
    out
}

/// Replace every operand handle of `expr` with `f(handle)`.
pub fn map_operands(
    expr: &mut Expression,
    f: &mut dyn FnMut(Handle<Expression>) -> Handle<Expression>,
) {
    use Expression as E;
    let opt = |h: &mut Option<Handle<Expression>>,
               f: &mut dyn FnMut(Handle<Expression>) -> Handle<Expression>| {
        if let Some(x) = h.as_mut() {
            *x = f(*x);
        }
    };
    match expr {
        E::Literal(_)
        | E::Constant(_)
        | E::Override(_)
        | E::ZeroValue(_)
        | E::FunctionArgument(_)
        | E::GlobalVariable(_)
        | E::LocalVariable(_)
        | E::CallResult(_)
        | E::AtomicResult { .. }
        | E::WorkGroupUniformLoadResult { .. }
        | E::RayQueryProceedResult
        | E::SubgroupBallotResult
        | E::SubgroupOperationResult { .. } => {}
        E::Compose { components, .. } => {
            for c in components.iter_mut() {
                *c = f(*c);
            }
        }
        E::Access { base, index } => {
            *base = f(*base);
            *index = f(*index);
        }
        E::AccessIndex { base, .. } => *base = f(*base),
        E::Splat { value, .. } => *value = f(*value),
        E::Swizzle { vector, .. } => *vector = f(*vector),
        E::Load { pointer } => *pointer = f(*pointer),
        E::ImageSample {
            image,
            sampler,
            coordinate,
            array_index,
            offset,
            level,
            depth_ref,
            ..
        } => {
            *image = f(*image);
            *sampler = f(*sampler);
            *coordinate = f(*coordinate);
            opt(array_index, f);
            opt(offset, f);
            match level {
                SampleLevel::Auto | SampleLevel::Zero => {}
                SampleLevel::Exact(h) | SampleLevel::Bias(h) => *h = f(*h),
                SampleLevel::Gradient { x, y } => {
                    *x = f(*x);
                    *y = f(*y);
                }
            }
            opt(depth_ref, f);
        }
        E::ImageLoad {
            image,
            coordinate,
            array_index,
            sample,
            level,
        } => {
            *image = f(*image);
            *coordinate = f(*coordinate);
            opt(array_index, f);
            opt(sample, f);
            opt(level, f);
        }
        E::ImageQuery { image, query } => {
            *image = f(*image);
            if let naga::ImageQuery::Size { level: Some(l) } = query {
                *l = f(*l);
            }
        }
        E::Unary { expr, .. } => *expr = f(*expr),
        E::Binary { left, right, .. } => {
            *left = f(*left);
            *right = f(*right);
        }
        E::Select {
            condition,
            accept,
            reject,
        } => {
            *condition = f(*condition);
            *accept = f(*accept);
            *reject = f(*reject);
        }
        E::Derivative { expr, .. } => *expr = f(*expr),
        E::Relational { argument, .. } => *argument = f(*argument),
        E::Math {
            arg,
            arg1,
            arg2,
            arg3,
            ..
        } => {
            *arg = f(*arg);
            opt(arg1, f);
            opt(arg2, f);
            opt(arg3, f);
        }
        E::As { expr, .. } => *expr = f(*expr),
        E::ArrayLength(h) => *h = f(*h),
        E::RayQueryVertexPositions { query, .. } | E::RayQueryGetIntersection { query, .. } => {
            *query = f(*query)
        }
        E::CooperativeLoad { data, .. } => {
            data.pointer = f(data.pointer);
            data.stride = f(data.stride);
        }
        E::CooperativeMultiplyAdd { a, b, c } => {
            *a = f(*a);
            *b = f(*b);
            *c = f(*c);
        }
    }
}

/// Operand positions through which a value reaches its user only discontinuously: comparison
/// operands, a `select` condition, `step`, rounding functions, `fract`, `sign`, `%`, and
/// conversions to integers or booleans. Returns, for each operand in [`operands`] order, whether
/// that edge is discontinuous.
pub fn discontinuous_edges(expr: &Expression, result_is_float: bool) -> Vec<bool> {
    use naga::{BinaryOperator as B, MathFunction as M};
    let ops = operands(expr);
    let all = |v: bool| vec![v; ops.len()];
    match *expr {
        Expression::Binary { op, .. } => all(matches!(
            op,
            B::Equal
                | B::NotEqual
                | B::Less
                | B::LessEqual
                | B::Greater
                | B::GreaterEqual
                | B::Modulo
                | B::And
                | B::ExclusiveOr
                | B::InclusiveOr
                | B::LogicalAnd
                | B::LogicalOr
                | B::ShiftLeft
                | B::ShiftRight
        )),
        Expression::Select { .. } => vec![true, false, false],
        Expression::Math { fun, .. } => all(matches!(
            fun,
            M::Step
                | M::Floor
                | M::Ceil
                | M::Round
                | M::Trunc
                | M::Fract
                | M::Sign
                | M::Modf
                | M::Frexp
        ) || !result_is_float),
        Expression::As { .. } => all(!result_is_float),
        Expression::Relational { .. } => all(true),
        Expression::Unary {
            op: naga::UnaryOperator::LogicalNot | naga::UnaryOperator::BitwiseNot,
            ..
        } => all(true),
        // Indices pick a component: the result jumps when the index changes.
        Expression::Access { .. } => vec![false, true],
        Expression::ImageLoad { .. } => {
            // image, coordinate (integer texel: discontinuous), the rest are integers too.
            let mut v = all(true);
            v[0] = false;
            v
        }
        _ => all(false),
    }
}

/// The local variable a pointer expression points into, following `Access`/`AccessIndex`.
pub fn root_local(
    exprs: &naga::Arena<Expression>,
    mut ptr: Handle<Expression>,
) -> Option<Handle<naga::LocalVariable>> {
    loop {
        match exprs[ptr] {
            Expression::LocalVariable(v) => return Some(v),
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => ptr = base,
            _ => return None,
        }
    }
}

/// The global variable a pointer or handle expression refers to, following `Access`/`AccessIndex`.
pub fn root_global(
    exprs: &naga::Arena<Expression>,
    mut ptr: Handle<Expression>,
) -> Option<Handle<naga::GlobalVariable>> {
    loop {
        match exprs[ptr] {
            Expression::GlobalVariable(v) => return Some(v),
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => ptr = base,
            _ => return None,
        }
    }
}

/// Number of f32 values in a float-valued type, or `None` if the type holds anything else.
pub fn float_count(inner: &naga::TypeInner, types: &naga::UniqueArena<naga::Type>) -> Option<u32> {
    use naga::TypeInner as T;
    let is_f32 = |s: &naga::Scalar| s.kind == naga::ScalarKind::Float && s.width == 4;
    match inner {
        T::Scalar(s) if is_f32(s) => Some(1),
        T::Vector { size, scalar } if is_f32(scalar) => Some(*size as u32),
        T::Matrix {
            columns,
            rows,
            scalar,
        } if is_f32(scalar) => Some(*columns as u32 * *rows as u32),
        T::Array {
            base,
            size: naga::ArraySize::Constant(n),
            ..
        } => float_count(&types[*base].inner, types).map(|c| c * n.get()),
        T::Struct { members, .. } => members
            .iter()
            .map(|m| float_count(&types[m.ty].inner, types))
            .sum(),
        _ => None,
    }
}

/// True when the type is any floating-point value (f16 or f32 scalars, vectors, matrices, or
/// aggregates of them): such an expression is a candidate node.
pub fn is_float_valued(inner: &naga::TypeInner, types: &naga::UniqueArena<naga::Type>) -> bool {
    use naga::TypeInner as T;
    match inner {
        T::Scalar(s) | T::Vector { scalar: s, .. } | T::Matrix { scalar: s, .. } => {
            s.kind == naga::ScalarKind::Float
        }
        T::Array { base, .. } => is_float_valued(&types[*base].inner, types),
        T::Struct { members, .. } => {
            !members.is_empty()
                && members
                    .iter()
                    .all(|m| is_float_valued(&types[m.ty].inner, types))
        }
        _ => false,
    }
}

/// Turn WGSL's `derivative_uniformity` diagnostic off for the whole module, as a global
/// `diagnostic(off, derivative_uniformity)` does (the WGSL written from the module keeps it). Used
/// where derivatives are uniform enough in fact but the analysis cannot see it: GLSL, which has no
/// uniformity rule, and the instancer's fused entry, whose recompute branch is uniform per quad.
pub fn derivative_uniformity_off(module: &mut naga::Module) {
    use naga::diagnostic_filter::{
        DiagnosticFilter, DiagnosticFilterNode, FilterableTriggeringRule, Severity,
        StandardFilterableTriggeringRule,
    };
    let node = DiagnosticFilterNode {
        inner: DiagnosticFilter {
            new_severity: Severity::Off,
            triggering_rule: FilterableTriggeringRule::Standard(
                StandardFilterableTriggeringRule::DerivativeUniformity,
            ),
        },
        parent: module.diagnostic_filter_leaf,
    };
    module.diagnostic_filter_leaf = Some(
        module
            .diagnostic_filters
            .append(node, naga::Span::UNDEFINED),
    );
}
