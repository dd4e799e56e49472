//! Push constants (naga's immediates: WGSL `var<immediate>`, GLSL `layout(push_constant)`) in
//! every output language: what the host must set (the manifest's `immediates`), and whether each
//! language's block can hold them byte for byte.
//!
//! The bytes a host writes are the WGSL layout (naga's offsets). Vulkan GLSL declares the block
//! `layout(push_constant)` with each member at its offset; what lies inside a member follows
//! `std430`, which is WGSL's layout unless a nested struct or array was laid out by hand (a
//! SPIR-V or GLSL input's explicit offsets). OpenGL has no push constants: the same file, when
//! `VULKAN` is not defined, declares a `std140` uniform block at a binding of its own (the
//! manifest's GLSL `immediates.slot`) where `std140` gives the same bytes, and an `#error` where it
//! does not (an array of scalars, a `mat2x2`), so that no OpenGL host reads wrong bytes.

use naga::{Handle, TypeInner};

/// The layout rules a GLSL block follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// `std430`: Vulkan's push-constant blocks.
    Std430,
    /// `std140`: OpenGL's uniform blocks.
    Std140,
}

/// The push-constant global of `module`, if it has one (naga allows one per entry point).
pub fn global(module: &naga::Module) -> Option<Handle<naga::GlobalVariable>> {
    module
        .global_variables
        .iter()
        .find(|(_, g)| g.space == naga::AddressSpace::Immediate)
        .map(|(h, _)| h)
}

/// Size in bytes of the push constants of `module`'s global `var`: what a host sets.
pub fn size(module: &naga::Module, var: Handle<naga::GlobalVariable>) -> u32 {
    let ty = module.global_variables[var].ty;
    module.types[ty].inner.size(module.to_ctx())
}

/// Whether a GLSL block under `rule` holds `module`'s push constants at naga's offsets: each
/// member of the block at its offset (which `layout(offset = N)` states) and aligned as `rule`
/// asks, and what lies inside each member laid out as `rule` lays it out.
pub fn block_agrees(module: &naga::Module, var: Handle<naga::GlobalVariable>, rule: Rule) -> bool {
    let ty = module.global_variables[var].ty;
    match &module.types[ty].inner {
        TypeInner::Struct { members, .. } => members
            .iter()
            .all(|m| layout(module, m.ty, rule).is_some_and(|(align, _)| m.offset % align == 0)),
        _ => layout(module, ty, rule).is_some(),
    }
}

/// Why `module`'s push constants cannot be written as a Vulkan GLSL block, if they cannot.
pub fn glsl_refusal(module: &naga::Module) -> Option<String> {
    let var = global(module)?;
    let name = module.global_variables[var]
        .name
        .as_deref()
        .unwrap_or("the push-constant block");
    if !block_agrees(module, var, Rule::Std430) {
        return Some(format!(
            "the push constants `{name}` hold a struct or array laid out by hand, which a GLSL push-constant block (std430 inside each member) cannot reproduce; write this shader in SPIR-V, HLSL or MSL"
        ));
    }
    // The block's members are lifted into the block: the block cannot be read as one value.
    let ty = module.global_variables[var].ty;
    let whole = matches!(module.types[ty].inner, TypeInner::Struct { .. })
        && module
            .functions
            .iter()
            .map(|(_, f)| f)
            .chain(module.entry_points.iter().map(|e| &e.function))
            .any(|f| {
                f.expressions.iter().any(|(_, e)| match *e {
                    naga::Expression::Load { pointer } => {
                        f.expressions[pointer] == naga::Expression::GlobalVariable(var)
                    }
                    _ => false,
                })
            });
    whole.then(|| {
        format!(
            "the pass reads the push constants `{name}` as one value, which a GLSL block cannot be; read its members instead"
        )
    })
}

/// Alignment and size of `ty` under `rule`, where its naga layout (WGSL's, or a SPIR-V input's
/// explicit strides and offsets) is that rule's; `None` where it is not.
fn layout(module: &naga::Module, ty: Handle<naga::Type>, rule: Rule) -> Option<(u32, u32)> {
    let round = |n: u32, to: u32| n.div_ceil(to) * to;
    let std140 = |align: u32| match rule {
        Rule::Std140 => round(align, 16),
        Rule::Std430 => align,
    };
    match module.types[ty].inner {
        TypeInner::Scalar(s) => Some((s.width as u32, s.width as u32)),
        TypeInner::Vector { size, scalar } => {
            let w = scalar.width as u32;
            let align = if size == naga::VectorSize::Bi {
                2 * w
            } else {
                4 * w
            };
            Some((align, size as u32 * w))
        }
        TypeInner::Matrix {
            columns,
            rows,
            scalar,
        } => {
            // An array of columns: naga's column stride is the column's alignment.
            let w = scalar.width as u32;
            let column = if rows == naga::VectorSize::Bi {
                2 * w
            } else {
                4 * w
            };
            let stride = std140(column);
            (stride == column).then_some((stride, columns as u32 * stride))
        }
        TypeInner::Array {
            base,
            size: naga::ArraySize::Constant(n),
            stride,
        } => {
            let (align, size) = layout(module, base, rule)?;
            let align = std140(align);
            (stride == round(size, align)).then_some((align, n.get() * stride))
        }
        TypeInner::Struct { ref members, span } => {
            let mut end = 0;
            let mut max = 1;
            for m in members {
                let (align, size) = layout(module, m.ty, rule)?;
                if m.offset != round(end, align) {
                    return None;
                }
                end = m.offset + size;
                max = max.max(align);
            }
            let align = std140(max);
            (span == round(end, align)).then_some((align, span))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn module(wgsl: &str) -> (naga::Module, Handle<naga::GlobalVariable>) {
        let m = naga::front::wgsl::parse_str(wgsl).unwrap();
        let var = global(&m).unwrap();
        (m, var)
    }

    #[test]
    fn vectors_and_scalars_agree_with_both_rules() {
        let (m, var) =
            module("struct P { tint: vec4<f32>, gain: f32, time: f32 };\nvar<immediate> pc: P;");
        assert_eq!(size(&m, var), 32);
        assert!(block_agrees(&m, var, Rule::Std430));
        assert!(block_agrees(&m, var, Rule::Std140));
        assert_eq!(glsl_refusal(&m), None);
    }

    #[test]
    fn an_array_of_scalars_has_no_std140_form() {
        let (m, var) =
            module("struct P { w: array<f32, 3>, tint: vec4<f32> };\nvar<immediate> pc: P;");
        assert!(block_agrees(&m, var, Rule::Std430));
        assert!(!block_agrees(&m, var, Rule::Std140));
    }

    #[test]
    fn a_mat2x2_has_no_std140_form() {
        let (m, var) = module("struct P { m: mat2x2<f32> };\nvar<immediate> pc: P;");
        assert!(block_agrees(&m, var, Rule::Std430));
        assert!(!block_agrees(&m, var, Rule::Std140));
    }

    #[test]
    fn a_nested_struct_laid_out_by_hand_is_refused_in_glsl() {
        let (m, var) = module(
            "struct I { @size(16) a: f32, b: f32 };\nstruct P { i: I };\nvar<immediate> pc: P;",
        );
        assert!(!block_agrees(&m, var, Rule::Std430));
        assert!(glsl_refusal(&m).unwrap().contains("`pc`"));
    }
}
