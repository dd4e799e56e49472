//! Why a node cannot be cached: what is continuous from the root, what feeds derivatives, the
//! payload's size, and the one [`CullReason`] an expression gets, in a fixed order.

use naga::{Expression, Handle, TypeInner};

use super::CullReason;
use super::walk::Place;

/// Per expression: continuous from the root, and feeding a derivative.
pub(super) struct Flags {
    pub(super) continuous: Vec<bool>,
    pub(super) feeds_derivative: Vec<bool>,
}

/// The expressions the root depends on through continuous edges only.
pub(super) fn continuous_from(
    root: Handle<Expression>,
    deps: &[Vec<(Handle<Expression>, bool)>],
) -> Vec<bool> {
    let mut continuous = vec![false; deps.len()];
    let mut stack = vec![root];
    while let Some(h) = stack.pop() {
        if continuous[h.index()] {
            continue;
        }
        continuous[h.index()] = true;
        for &(d, disc) in &deps[h.index()] {
            if !disc && !continuous[d.index()] {
                stack.push(d);
            }
        }
    }
    continuous
}

/// What feeds explicit derivatives, and the coordinates of samples whose level of detail the
/// hardware derives from them (`textureSample`, `textureSampleBias`): in the shade pass a cached
/// value comes from a texel per pixel, and helper lanes at silhouettes read the background.
pub(super) fn feeds_derivatives(
    fun: &naga::Function,
    deps: &[Vec<(Handle<Expression>, bool)>],
) -> Vec<bool> {
    let mut feeds_derivative = vec![false; deps.len()];
    let mut stack: Vec<Handle<Expression>> = fun
        .expressions
        .iter()
        .filter_map(|(_, e)| match *e {
            Expression::Derivative { expr, .. } => Some(expr),
            Expression::ImageSample {
                coordinate,
                level: naga::SampleLevel::Auto | naga::SampleLevel::Bias(_),
                ..
            } => Some(coordinate),
            _ => None,
        })
        .collect();
    while let Some(h) = stack.pop() {
        if !std::mem::replace(&mut feeds_derivative[h.index()], true) {
            stack.extend(deps[h.index()].iter().map(|&(d, _)| d));
        }
    }
    feeds_derivative
}

/// The f32 components of a payload of this type: 1 to 4, or 0 when it cannot be one.
pub(super) fn payload_components(inner: &TypeInner) -> u32 {
    match inner {
        TypeInner::Scalar(s) if s.width == 4 && s.kind == naga::ScalarKind::Float => 1,
        TypeInner::Vector { size, scalar }
            if scalar.width == 4 && scalar.kind == naga::ScalarKind::Float =>
        {
            *size as u32
        }
        _ => 0,
    }
}

/// Why the expression `h` cannot be cached, the first reason in this order; `None` when it can.
pub(super) fn cull_reason(
    components: u32,
    cost: f64,
    place: Place,
    flags: &Flags,
    h: Handle<Expression>,
) -> Option<CullReason> {
    // Weights are never negative.
    let trivial = cost == 0.0;
    if components == 0 {
        Some(CullReason::PayloadType)
    } else if trivial {
        Some(CullReason::Trivial)
    } else if place.in_loop {
        Some(CullReason::InLoop)
    } else if place.non_uniform {
        Some(CullReason::NonUniformBranch)
    } else if flags.feeds_derivative[h.index()] {
        Some(CullReason::Derivative)
    } else if !flags.continuous[h.index()] {
        Some(CullReason::Discontinuous)
    } else {
        None
    }
}
