//! Push constants at explicit offsets kept through WGSL.
//!
//! Vulkan GLSL often starts a stage's push constants past another stage's (`layout(offset = 64)
//! vec4 tint;`: a range shared with the vertex stage), or leaves gaps between members. naga's
//! WGSL writer states no offsets (no `@size` or `@align`), and every pass reproj writes, and the
//! WGSL form the replay renders, comes from WGSL: the members would move to WGSL's own offsets and
//! a host would set the wrong bytes. So each gap becomes an explicit padding member
//! (`_pad0: array<u32, 16>`), whose natural layout puts every member back at its offset, and the
//! struct's member indices are shifted where the code reads them.

use naga::{Expression, Handle, TypeInner};

/// A function of the module, or the entry point at an index.
type Where = Result<Handle<naga::Function>, usize>;

/// Pad the push-constant struct of `module` (if any) so that WGSL's layout gives each member the
/// offset the GLSL stated, and renumber the member accesses. A module that does not validate, or
/// a gap that is not whole words, is left as it is.
pub(super) fn pad_push_constants(module: &mut naga::Module) {
    let Some((var, ty)) = module
        .global_variables
        .iter()
        .find(|(_, g)| g.space == naga::AddressSpace::Immediate)
        .map(|(h, g)| (h, g.ty))
    else {
        return;
    };
    let TypeInner::Struct { members, span } = module.types[ty].inner.clone() else {
        return;
    };
    let mut layouter = naga::proc::Layouter::default();
    if layouter.update(module.to_ctx()).is_err() {
        return;
    }
    // Where each member lands, and the padding before it.
    let mut padded = Vec::new();
    let mut moved = Vec::new();
    let mut end = 0;
    for m in &members {
        let layout = &layouter[m.ty];
        if m.offset != layout.alignment.round_up(end) {
            let gap = m.offset.checked_sub(end).filter(|g| g % 4 == 0 && *g > 0);
            let Some(gap) = gap else { return };
            padded.push((end, gap / 4));
        }
        moved.push((moved.len() + padded.len()) as u32);
        end = m.offset + layout.size;
    }
    if padded.is_empty() {
        return;
    }
    let Ok(info) = crate::shader::validator().validate(module) else {
        return;
    };
    // Every access to a member of the struct, by function, before anything changes.
    let mut renumber: Vec<(Where, Handle<Expression>)> = Vec::new();
    let reads_struct = |res: &naga::proc::TypeResolution| match *res {
        naga::proc::TypeResolution::Handle(h) => {
            h == ty
                || matches!(module.types[h].inner, TypeInner::Pointer { base, .. } if base == ty)
        }
        naga::proc::TypeResolution::Value(TypeInner::Pointer { base, .. }) => base == ty,
        _ => false,
    };
    let mut scan = |f: &naga::Function, fi: &naga::valid::FunctionInfo, which| {
        for (h, e) in f.expressions.iter() {
            if let Expression::AccessIndex { base, .. } = *e
                && reads_struct(&fi[base].ty)
            {
                renumber.push((which, h));
            }
        }
    };
    for (fh, f) in module.functions.iter() {
        scan(f, &info[fh], Ok(fh));
    }
    for (i, ep) in module.entry_points.iter().enumerate() {
        scan(&ep.function, info.get_entry_point(i), Err(i));
    }
    // The padded struct.
    let original = module.clone();
    let word = module.types.insert(
        naga::Type {
            name: None,
            inner: TypeInner::Scalar(naga::Scalar::U32),
        },
        naga::Span::UNDEFINED,
    );
    let mut new_members = Vec::new();
    let mut pads = padded.into_iter().peekable();
    for (n, m) in members.into_iter().enumerate() {
        while new_members.len() < moved[n] as usize {
            let (offset, words) = pads.next().expect("a pad before this member");
            let array = module.types.insert(
                naga::Type {
                    name: None,
                    inner: TypeInner::Array {
                        base: word,
                        size: naga::ArraySize::Constant(
                            std::num::NonZeroU32::new(words).expect("a gap of whole words"),
                        ),
                        stride: 4,
                    },
                },
                naga::Span::UNDEFINED,
            );
            new_members.push(naga::StructMember {
                name: Some(format!("_pad{}", new_members.len())),
                ty: array,
                binding: None,
                offset,
            });
        }
        new_members.push(m);
    }
    // A new struct after its padding types (a type comes after those it uses); the old one,
    // which spv-in's pointer types still name, is renamed out of the way.
    let name = module.types[ty].name.clone();
    let padded_ty = module.types.insert(
        naga::Type {
            name: name.clone(),
            inner: TypeInner::Struct {
                members: new_members,
                span,
            },
        },
        naga::Span::UNDEFINED,
    );
    if let Some(name) = name {
        let old = module.types[ty].inner.clone();
        module.types.replace(
            ty,
            naga::Type {
                name: Some(format!("{name}_unpadded")),
                inner: old,
            },
        );
    }
    module.global_variables[var].ty = padded_ty;
    for (which, h) in renumber {
        let f = match which {
            Ok(fh) => &mut module.functions[fh],
            Err(i) => &mut module.entry_points[i].function,
        };
        if let Expression::AccessIndex { ref mut index, .. } = f.expressions[h] {
            *index = moved[*index as usize];
        }
    }
    // Anything else that used the struct whole (a local copy of the block) would no longer
    // match: then the module is left as it was.
    if crate::shader::validator().validate(module).is_err() {
        *module = original;
    }
}
