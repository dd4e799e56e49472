//! What WGSL as engines write it leaves to an older naga or to the host, filled in before the
//! module is validated.
//!
//! - **Integer varyings without `@interpolate(flat)`.** naga 30 wants the `flat` written on a
//!   vertex output or fragment input of integer type (as the WGSL standard does); earlier naga
//!   read such a varying as flat, and shaders written for it (wgpu's own texture-array example,
//!   Learn Wgpu's terrain) leave it out. It is read as flat, which is what it always meant.
//! - **Resources without `@group`/`@binding`.** Blade binds a shader's resources by name, from the
//!   layouts the host declares, so its WGSL writes none. Each such resource takes group 0 and the
//!   next binding that group leaves free, in declaration order, and a warning names each
//!   ([`InputWarning::BindingAssigned`]): a host binds them where the variant's manifest says.

use std::collections::BTreeSet;
use std::path::Path;

use naga::{AddressSpace, Binding, Handle, Interpolation, Module, ShaderStage, Type, TypeInner};

use crate::input::InputWarning;

/// Fill in `module`'s integer varyings and unbound resources (the module docs): the warnings for
/// the bindings chosen, and whether anything was filled in (the module then says more than its
/// text, and a device is given naga's WGSL of it: [`crate::Shader::to_wgsl`]).
pub fn fill_in(path: &Path, module: &mut Module) -> (Vec<InputWarning>, bool) {
    let flat = flat_integer_varyings(module);
    let warnings = assign_bindings(path, module);
    let changed = flat || !warnings.is_empty();
    (warnings, changed)
}

/// Whether a varying of type `ty` is an integer one.
fn is_integer(module: &Module, ty: Handle<Type>) -> bool {
    matches!(
        module.types[ty].inner.scalar_kind(),
        Some(naga::ScalarKind::Sint | naga::ScalarKind::Uint)
    )
}

/// `binding` made flat when it is a location of an integer type without interpolation (true then).
fn make_flat(module: &Module, ty: Handle<Type>, binding: &mut Option<Binding>) -> bool {
    if let Some(Binding::Location {
        interpolation: interpolation @ None,
        sampling,
        ..
    }) = binding
        && is_integer(module, ty)
    {
        *interpolation = Some(Interpolation::Flat);
        *sampling = None;
        return true;
    }
    false
}

/// The struct `ty` with its integer location members made flat (true when one was).
fn flat_members(module: &mut Module, ty: Handle<Type>) -> bool {
    let TypeInner::Struct { members, span } = &module.types[ty].inner else {
        return false;
    };
    let mut members = members.clone();
    let span = *span;
    for m in &mut members {
        make_flat(module, m.ty, &mut m.binding);
    }
    // `replace` takes only a type the arena does not hold yet: an unchanged one stays.
    if matches!(&module.types[ty].inner, TypeInner::Struct { members: old, .. } if *old == members)
    {
        return false;
    }
    let name = module.types[ty].name.clone();
    module.types.replace(
        ty,
        Type {
            name,
            inner: TypeInner::Struct { members, span },
        },
    );
    true
}

/// Integer varyings made flat (the module docs); true when one was.
fn flat_integer_varyings(module: &mut Module) -> bool {
    let mut changed = false;
    let mut structs = Vec::new();
    for i in 0..module.entry_points.len() {
        let stage = module.entry_points[i].stage;
        let mut f = std::mem::take(&mut module.entry_points[i].function);
        match stage {
            ShaderStage::Fragment => {
                for arg in &mut f.arguments {
                    changed |= make_flat(module, arg.ty, &mut arg.binding);
                    structs.push(arg.ty);
                }
            }
            ShaderStage::Vertex => {
                if let Some(r) = &mut f.result {
                    changed |= make_flat(module, r.ty, &mut r.binding);
                    structs.push(r.ty);
                }
            }
            _ => {}
        }
        module.entry_points[i].function = f;
    }
    structs.sort();
    structs.dedup();
    for ty in structs {
        changed |= flat_members(module, ty);
    }
    changed
}

/// Whether a global in `space` is a resource a host binds.
fn is_resource(space: AddressSpace) -> bool {
    matches!(
        space,
        AddressSpace::Uniform | AddressSpace::Storage { .. } | AddressSpace::Handle
    )
}

fn assign_bindings(path: &Path, module: &mut Module) -> Vec<InputWarning> {
    let mut taken: BTreeSet<u32> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| g.binding.as_ref())
        .filter(|b| b.group == 0)
        .map(|b| b.binding)
        .collect();
    let mut warnings = Vec::new();
    for (_, g) in module.global_variables.iter_mut() {
        if g.binding.is_some() || !is_resource(g.space) {
            continue;
        }
        let binding = (0..).find(|b| !taken.contains(b)).unwrap_or(0);
        taken.insert(binding);
        g.binding = Some(naga::ResourceBinding { group: 0, binding });
        warnings.push(InputWarning::BindingAssigned {
            name: g.name.clone().unwrap_or_default(),
            group: 0,
            binding,
            path: path.to_owned(),
        });
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unbound_resources_take_the_free_bindings_of_group_0() {
        let mut module = naga::front::wgsl::parse_str(
            "var<uniform> a: vec4<f32>;
             @group(0) @binding(0) var<uniform> b: vec4<f32>;
             var<uniform> c: vec4<f32>;
             @fragment fn fs() -> @location(0) vec4<f32> { return a + b + c; }",
        )
        .unwrap();
        let (warnings, changed) = fill_in(Path::new("x.wgsl"), &mut module);
        assert!(changed);
        let bindings: Vec<_> = module
            .global_variables
            .iter()
            .map(|(_, g)| g.binding.as_ref().unwrap().binding)
            .collect();
        assert_eq!(bindings, [1, 0, 2]);
        assert_eq!(warnings.len(), 2);
        crate::parse::validator().validate(&module).unwrap();
    }

    #[test]
    fn integer_varyings_are_read_as_flat() {
        let mut module = naga::front::wgsl::parse_str(
            "struct V { @builtin(position) p: vec4<f32>, @location(0) i: u32 };
             @vertex fn vs() -> V { return V(vec4<f32>(0.0), 1u); }
             @fragment fn fs(v: V) -> @location(0) vec4<f32> { return vec4<f32>(f32(v.i)); }",
        )
        .unwrap();
        assert!(crate::parse::validator().validate(&module).is_err());
        assert_eq!(
            fill_in(Path::new("x.wgsl"), &mut module),
            (Vec::new(), true)
        );
        crate::parse::validator().validate(&module).unwrap();
        // Filled in once, nothing is left to fill in.
        assert_eq!(
            fill_in(Path::new("x.wgsl"), &mut module),
            (Vec::new(), false)
        );
    }
}
