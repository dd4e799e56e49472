//! The bind group layout entries of a pass: one per global variable the pass uses, read off its
//! type (buffer, texture, sampler), with the group the added bindings go to.

use super::*;

/// WGSL spelling of a type (naga's own printer; structs by name).
pub(super) fn type_name(module: &Module, ty: Handle<naga::Type>) -> String {
    use naga::common::wgsl::TypeContext;
    module.to_ctx().type_to_string(ty)
}

/// The bind group layout entry of a global variable, from its type.
fn layout_entry(module: &Module, g: &naga::GlobalVariable, filterable: bool) -> LayoutEntry {
    use naga::TypeInner as T;
    let inner = &module.types[g.ty].inner;
    match (g.space, inner) {
        (naga::AddressSpace::Uniform, _) => LayoutEntry::Buffer {
            buffer_type: "uniform".into(),
            min_binding_size: u64::from(inner.size(module.to_ctx())),
        },
        (naga::AddressSpace::Storage { access }, _) => LayoutEntry::Buffer {
            buffer_type: if access.contains(naga::StorageAccess::STORE) {
                "storage"
            } else {
                "read-only-storage"
            }
            .into(),
            min_binding_size: u64::from(inner.size(module.to_ctx())),
        },
        (_, T::Sampler { comparison }) => LayoutEntry::Sampler {
            sampler_type: if *comparison {
                "comparison"
            } else if filterable {
                "filtering"
            } else {
                "non-filtering"
            }
            .into(),
        },
        (
            _,
            T::Image {
                dim,
                arrayed,
                class,
            },
        ) => {
            let view_dimension = match (dim, arrayed) {
                (naga::ImageDimension::D1, _) => "1d",
                (naga::ImageDimension::D2, false) => "2d",
                (naga::ImageDimension::D2, true) => "2d-array",
                (naga::ImageDimension::D3, _) => "3d",
                (naga::ImageDimension::Cube, false) => "cube",
                (naga::ImageDimension::Cube, true) => "cube-array",
            }
            .to_string();
            match class {
                naga::ImageClass::Sampled { kind, multi } => LayoutEntry::Texture {
                    sample_type: match kind {
                        naga::ScalarKind::Sint => "sint",
                        naga::ScalarKind::Uint => "uint",
                        _ if filterable => "float",
                        _ => "unfilterable-float",
                    }
                    .into(),
                    view_dimension,
                    multisampled: *multi,
                },
                naga::ImageClass::Depth { multi } => LayoutEntry::Texture {
                    sample_type: "depth".into(),
                    view_dimension,
                    multisampled: *multi,
                },
                naga::ImageClass::Storage { format, access } => LayoutEntry::StorageTexture {
                    format: format!("{format:?}").to_lowercase(),
                    access: if access
                        .contains(naga::StorageAccess::LOAD | naga::StorageAccess::STORE)
                    {
                        "read-write"
                    } else if access.contains(naga::StorageAccess::STORE) {
                        "write-only"
                    } else {
                        "read-only"
                    }
                    .into(),
                    view_dimension,
                },
                naga::ImageClass::External => LayoutEntry::Texture {
                    sample_type: "float".into(),
                    view_dimension,
                    multisampled: false,
                },
            }
        }
        _ => LayoutEntry::Buffer {
            buffer_type: "uniform".into(),
            min_binding_size: u64::from(inner.size(module.to_ctx())),
        },
    }
}

/// The bindings of a pass module: the shader's own (bound as for the original) and the
/// instancer's, each with its layout entry and the resource it takes.
pub(super) fn bindings(
    module: &Module,
    place: contract::AddedPlace,
    reconstruct: Reconstruct,
) -> Vec<Binding> {
    let mut out: Vec<Binding> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            let b = g.binding.as_ref()?;
            let name = g.name.clone().unwrap_or_default();
            let space = match g.space {
                naga::AddressSpace::Uniform => "uniform ",
                naga::AddressSpace::Storage { .. } => "storage ",
                _ => "",
            };
            let added = place.holds(b.group, b.binding);
            let (resource, filterable) = if !added {
                (BindingResource::Own, true)
            } else {
                match name.as_str() {
                    contract::PARAMS => (BindingResource::Params, false),
                    contract::PREV_PAYLOAD => (
                        BindingResource::Texture {
                            role: ROLE_PREV_PAYLOAD.into(),
                        },
                        reconstruct.filters(),
                    ),
                    contract::CUR_PAYLOAD => (
                        BindingResource::Texture {
                            role: ROLE_CUR_PAYLOAD.into(),
                        },
                        false,
                    ),
                    contract::PREV_DEPTH => (
                        BindingResource::Texture {
                            role: ROLE_PREV_DEPTH_COPY.into(),
                        },
                        false,
                    ),
                    contract::LINEAR_SAMPLER => (
                        BindingResource::Sampler {
                            name: SAMPLER_LINEAR.into(),
                        },
                        true,
                    ),
                    contract::MOTION => (BindingResource::Motion, false),
                    other => unreachable!("the lookup library declares no binding `{other}`"),
                }
            };
            Some(Binding {
                group: b.group,
                binding: b.binding,
                name,
                ty: format!("{space}{}", type_name(module, g.ty)),
                added,
                layout: layout_entry(module, g, filterable),
                resource,
            })
        })
        .collect();
    out.sort_by_key(|b| (b.group, b.binding));
    out
}
