//! Copying one naga module into another.
//!
//! The fused and two-pass strategies call the reprojection lookup (a WGSL library, `lookup.wgsl`)
//! from inside the shader's own module. naga has no linker, so the library is parsed on its own and
//! its types, globals, functions and entry points are appended to the shader's module with every
//! cross-arena handle remapped. Names are kept: the library's are all prefixed `reproj_`/`Reproj`.

use std::collections::HashMap;

use naga::{Block, Expression, Function, Handle, Module, Statement, Type, TypeInner};

/// Where the imported items landed in the destination module, by name.
#[derive(Debug, Default)]
pub struct Imported {
    pub functions: HashMap<String, Handle<Function>>,
    pub types: HashMap<String, Handle<Type>>,
}

/// Append every type, global variable, function and entry point of `src` to `dst`.
///
/// `src` must have no constants, overrides or global initializers (the library has none); an
/// expression that refers to one is reported as an error rather than copied wrongly.
pub fn import_module(dst: &mut Module, src: &Module) -> Result<Imported, String> {
    if !src.constants.is_empty() || !src.overrides.is_empty() {
        return Err("the imported module declares constants or overrides".into());
    }
    let mut out = Imported::default();
    let mut types: HashMap<Handle<Type>, Handle<Type>> = HashMap::new();
    for (h, ty) in src.types.iter() {
        let map = |t: Handle<Type>| types[&t];
        let inner = match &ty.inner {
            TypeInner::Struct { members, span } => TypeInner::Struct {
                members: members
                    .iter()
                    .map(|m| naga::StructMember {
                        ty: map(m.ty),
                        ..m.clone()
                    })
                    .collect(),
                span: *span,
            },
            TypeInner::Array { base, size, stride } => TypeInner::Array {
                base: map(*base),
                size: *size,
                stride: *stride,
            },
            TypeInner::Pointer { base, space } => TypeInner::Pointer {
                base: map(*base),
                space: *space,
            },
            TypeInner::BindingArray { base, size } => TypeInner::BindingArray {
                base: map(*base),
                size: *size,
            },
            other => other.clone(),
        };
        let nh = dst.types.insert(
            Type {
                name: ty.name.clone(),
                inner,
            },
            src.types.get_span(h),
        );
        if let Some(name) = &ty.name {
            out.types.insert(name.clone(), nh);
        }
        types.insert(h, nh);
    }
    let mut globals = HashMap::new();
    for (h, g) in src.global_variables.iter() {
        if g.init.is_some() {
            return Err(format!(
                "the imported global {:?} has an initializer",
                g.name
            ));
        }
        let ng = dst.global_variables.append(
            naga::GlobalVariable {
                ty: types[&g.ty],
                ..g.clone()
            },
            src.global_variables.get_span(h),
        );
        globals.insert(h, ng);
    }
    let mut functions = HashMap::new();
    let maps = Maps {
        types: &types,
        globals: &globals,
    };
    for (h, f) in src.functions.iter() {
        let nf = maps.function(f, &functions)?;
        let nh = dst.functions.append(nf, src.functions.get_span(h));
        if let Some(name) = &f.name {
            out.functions.insert(name.clone(), nh);
        }
        functions.insert(h, nh);
    }
    for ep in &src.entry_points {
        let function = maps.function(&ep.function, &functions)?;
        dst.entry_points.push(naga::EntryPoint {
            function,
            ..ep.clone()
        });
    }
    Ok(out)
}

struct Maps<'a> {
    types: &'a HashMap<Handle<Type>, Handle<Type>>,
    globals: &'a HashMap<Handle<naga::GlobalVariable>, Handle<naga::GlobalVariable>>,
}

impl Maps<'_> {
    fn function(
        &self,
        f: &Function,
        functions: &HashMap<Handle<Function>, Handle<Function>>,
    ) -> Result<Function, String> {
        let mut nf = f.clone();
        for a in &mut nf.arguments {
            a.ty = self.types[&a.ty];
        }
        if let Some(r) = &mut nf.result {
            r.ty = self.types[&r.ty];
        }
        for (_, v) in nf.local_variables.iter_mut() {
            v.ty = self.types[&v.ty];
        }
        for (_, e) in nf.expressions.iter_mut() {
            self.expression(e, functions)?;
        }
        remap_calls(&mut nf.body, functions);
        Ok(nf)
    }

    fn expression(
        &self,
        e: &mut Expression,
        functions: &HashMap<Handle<Function>, Handle<Function>>,
    ) -> Result<(), String> {
        match e {
            Expression::ZeroValue(ty)
            | Expression::Compose { ty, .. }
            | Expression::AtomicResult { ty, .. }
            | Expression::WorkGroupUniformLoadResult { ty }
            | Expression::SubgroupOperationResult { ty } => *ty = self.types[ty],
            Expression::GlobalVariable(g) => *g = self.globals[g],
            Expression::CallResult(f) => *f = functions[f],
            Expression::Constant(_) | Expression::Override(_) => {
                return Err("the imported module refers to a constant".into());
            }
            _ => {}
        }
        Ok(())
    }
}

fn remap_calls(block: &mut Block, functions: &HashMap<Handle<Function>, Handle<Function>>) {
    for s in block.iter_mut() {
        match s {
            Statement::Call { function, .. } => *function = functions[function],
            Statement::Block(b) => remap_calls(b, functions),
            Statement::If { accept, reject, .. } => {
                remap_calls(accept, functions);
                remap_calls(reject, functions);
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                remap_calls(body, functions);
                remap_calls(continuing, functions);
            }
            Statement::Switch { cases, .. } => {
                for c in cases {
                    remap_calls(&mut c.body, functions);
                }
            }
            _ => {}
        }
    }
}
