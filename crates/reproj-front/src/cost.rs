//! Static cost of a node's subtree (`docs/COST.md`): what one operation costs, and how many times
//! a loop body runs when its bound is a literal. The node table weights each expression with these.

use naga::{Block, Expression, Statement, TypeInner};

/// Assumed trip count of a loop whose bound reproj cannot read.
pub const DEFAULT_TRIP_COUNT: f64 = 8.0;

/// Static cost of one operation (see `docs/COST.md`): ALU operations cost per component;
/// transcendental functions and texture fetches cost more.
pub fn op_cost(e: &Expression, result: &TypeInner) -> f64 {
    use naga::MathFunction as M;
    let width = |inner: &TypeInner| -> f64 {
        match *inner {
            TypeInner::Vector { size, .. } => size as u8 as f64,
            TypeInner::Matrix { columns, rows, .. } => (columns as u8 * rows as u8) as f64,
            _ => 1.0,
        }
    };
    let w = width(result);
    match *e {
        Expression::Literal(_)
        | Expression::Constant(_)
        | Expression::Override(_)
        | Expression::ZeroValue(_)
        | Expression::Compose { .. }
        | Expression::Access { .. }
        | Expression::AccessIndex { .. }
        | Expression::Splat { .. }
        | Expression::Swizzle { .. }
        | Expression::FunctionArgument(_)
        | Expression::GlobalVariable(_)
        | Expression::LocalVariable(_)
        | Expression::Load { .. }
        | Expression::CallResult(_) => 0.0,
        Expression::ImageSample { .. } => 20.0,
        Expression::ImageLoad { .. } => 10.0,
        Expression::ImageQuery { .. } => 2.0,
        Expression::Unary { .. }
        | Expression::Select { .. }
        | Expression::As { .. }
        | Expression::Relational { .. } => w,
        Expression::Binary {
            op: naga::BinaryOperator::Divide | naga::BinaryOperator::Modulo,
            ..
        } => 4.0 * w,
        Expression::Binary { .. } => w,
        Expression::Derivative { .. } => 2.0 * w,
        Expression::Math { fun, .. } => match fun {
            M::Dot | M::Dot4I8Packed | M::Dot4U8Packed => 4.0,
            M::Cross => 6.0,
            M::Length | M::Distance => 8.0,
            M::Normalize => 4.0 * w + 4.0,
            M::Reflect | M::FaceForward => 3.0 * w,
            M::Refract => 6.0 * w + 4.0,
            M::Sqrt | M::InverseSqrt => 4.0 * w,
            M::Exp | M::Exp2 | M::Log | M::Log2 | M::Sin | M::Cos | M::Tan => 8.0 * w,
            M::Pow => 16.0 * w,
            M::Asin
            | M::Acos
            | M::Atan
            | M::Atan2
            | M::Sinh
            | M::Cosh
            | M::Tanh
            | M::Asinh
            | M::Acosh
            | M::Atanh => 10.0 * w,
            M::Mix | M::SmoothStep | M::Fma => 3.0 * w,
            M::Inverse | M::Determinant => 20.0 * w,
            _ => w,
        },
        _ => w,
    }
}

/// Trip count of a loop whose first `if` compares a loaded counter with a literal bound.
pub(crate) fn trip_count(fun: &naga::Function, body: &Block) -> f64 {
    for stmt in body.iter() {
        if let Statement::If {
            condition,
            accept,
            reject,
        } = stmt
        {
            let breaks = accept
                .iter()
                .chain(reject.iter())
                .any(|s| matches!(s, Statement::Break));
            if !breaks {
                continue;
            }
            if let Expression::Binary { op, right, .. } = fun.expressions[*condition] {
                let bound = match fun.expressions[right] {
                    Expression::Literal(naga::Literal::I32(v)) => Some(v as f64),
                    Expression::Literal(naga::Literal::U32(v)) => Some(v as f64),
                    _ => None,
                };
                if let Some(b) = bound {
                    let n = match op {
                        naga::BinaryOperator::Less | naga::BinaryOperator::NotEqual => b,
                        naga::BinaryOperator::LessEqual => b + 1.0,
                        _ => DEFAULT_TRIP_COUNT,
                    };
                    return n.clamp(1.0, 4096.0);
                }
            }
            return DEFAULT_TRIP_COUNT;
        }
    }
    DEFAULT_TRIP_COUNT
}
