//! Buffer layouts: the leaves (scalars, vectors, matrices at their byte offsets) of a uniform
//! buffer's type, and a read-only storage buffer's fixed part and runtime-sized array, walked
//! with naga's layouter so that the WGSL layout rules hold.

use naga::{ArraySize, Handle, Module, ScalarKind, TypeInner, proc::Layouter};

use super::{RuntimeArray, ScalarTy, StorageLayout, UniformField, type_text};

/// The leaves of a value of type `ty` at byte `offset` called `name`, appended to `out`: structs
/// and fixed-size arrays of structs are walked (offsets from naga's layouter and the members'
/// own offsets, so the WGSL uniform and storage layout rules hold), everything else is one leaf.
pub(super) fn uniform_leaves(
    module: &Module,
    layouter: &Layouter,
    name: &str,
    ty: Handle<naga::Type>,
    offset: u32,
    out: &mut Vec<UniformField>,
) -> Result<(), String> {
    match module.types[ty].inner {
        TypeInner::Struct { ref members, .. } => {
            for m in members {
                let mname = m.name.clone().unwrap_or_default();
                let path = if name.is_empty() {
                    mname
                } else {
                    format!("{name}.{mname}")
                };
                uniform_leaves(module, layouter, &path, m.ty, offset + m.offset, out)?;
            }
            Ok(())
        }
        TypeInner::Array {
            base,
            size: ArraySize::Constant(n),
            stride,
        } if matches!(module.types[base].inner, TypeInner::Struct { .. }) => {
            for i in 0..n.get() {
                let path = format!("{name}[{i}]");
                uniform_leaves(module, layouter, &path, base, offset + i * stride, out)?;
            }
            Ok(())
        }
        _ => {
            out.push(uniform_leaf(module, layouter, name, ty, offset)?);
            Ok(())
        }
    }
}

fn uniform_leaf(
    module: &Module,
    layouter: &Layouter,
    name: &str,
    ty: Handle<naga::Type>,
    offset: u32,
) -> Result<UniformField, String> {
    let scalar_of = |s: naga::Scalar| -> Option<ScalarTy> {
        match (s.kind, s.width) {
            (ScalarKind::Float, 4) => Some(ScalarTy::F32),
            (ScalarKind::Sint, 4) => Some(ScalarTy::I32),
            (ScalarKind::Uint, 4) => Some(ScalarTy::U32),
            _ => None,
        }
    };
    let tyname = type_text(module, ty);
    let bad = || format!("uniform field `{name}` has type {tyname}, which the replay cannot fill");
    let simple = |inner: &TypeInner| -> Option<(ScalarTy, u32, u32, u32)> {
        match *inner {
            TypeInner::Scalar(s) => Some((scalar_of(s)?, 1, 1, 0)),
            TypeInner::Vector { size, scalar } => Some((scalar_of(scalar)?, size as u32, 1, 0)),
            TypeInner::Matrix {
                columns,
                rows,
                scalar,
            } => {
                let r = rows as u32;
                let col_stride = if r == 2 { 8 } else { 16 };
                Some((scalar_of(scalar)?, r, columns as u32, col_stride))
            }
            _ => None,
        }
    };
    let inner = &module.types[ty].inner;
    if let Some((scalar, rows, cols, col_stride)) = simple(inner) {
        return Ok(UniformField {
            name: name.to_owned(),
            offset,
            scalar,
            rows,
            cols,
            col_stride,
            count: 1,
            stride: layouter[ty].size,
            ty: tyname,
        });
    }
    if let TypeInner::Array {
        base,
        size: ArraySize::Constant(n),
        stride,
    } = *inner
        && let Some((scalar, rows, cols, col_stride)) = simple(&module.types[base].inner)
    {
        return Ok(UniformField {
            name: name.to_owned(),
            offset,
            scalar,
            rows,
            cols,
            col_stride,
            count: n.get(),
            stride,
            ty: tyname,
        });
    }
    Err(bad())
}

/// The layout of a read-only storage buffer of type `ty`.
pub(super) fn storage_layout(
    module: &Module,
    layouter: &Layouter,
    ty: Handle<naga::Type>,
) -> Result<StorageLayout, String> {
    let size = layouter[ty].size;
    let runtime_of = |name: &str, ty: Handle<naga::Type>, offset: u32| -> Result<_, String> {
        let TypeInner::Array {
            base,
            size: ArraySize::Dynamic,
            stride,
        } = module.types[ty].inner
        else {
            return Ok(None);
        };
        let mut element = Vec::new();
        uniform_leaves(module, layouter, "", base, 0, &mut element)?;
        Ok(Some(RuntimeArray {
            name: name.to_owned(),
            offset,
            stride,
            element,
        }))
    };
    let mut fields = Vec::new();
    let mut runtime = runtime_of("", ty, 0)?;
    if runtime.is_none() {
        match &module.types[ty].inner {
            TypeInner::Struct { members, .. } => {
                for m in members {
                    let mname = m.name.clone().unwrap_or_default();
                    match runtime_of(&mname, m.ty, m.offset)? {
                        Some(rt) => runtime = Some(rt),
                        None => {
                            uniform_leaves(module, layouter, &mname, m.ty, m.offset, &mut fields)?
                        }
                    }
                }
            }
            _ => uniform_leaves(module, layouter, "", ty, 0, &mut fields)?,
        }
    }
    Ok(StorageLayout {
        size,
        fields,
        runtime,
    })
}
