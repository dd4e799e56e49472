//! A group shared with the original shader: where the shader uses all four bind groups, reproj
//! puts its bindings in one of them past the shader's own (the manifest's `binding_base`), and the
//! runtime binds the application's resources of that group beside its own, in one bind group.

use std::collections::BTreeMap;

use crate::RuntimeError;
use crate::plan::PassPlan;

/// The application's own bindings of the variant's group, for a variant that shares it
/// ([`crate::Variant::shares_group`]): their layout entries and their resources (binding numbers
/// below [`crate::Variant::binding_base`]). The runtime keeps handles to the resources (wgpu's
/// handles are reference-counted) and binds them in every bind group it makes of that group;
/// give them again with [`crate::VariantResources::set_shared`] when they change.
#[derive(Debug, Clone, Copy)]
pub struct SharedGroup<'a> {
    pub layout: &'a [wgpu::BindGroupLayoutEntry],
    pub resources: &'a [wgpu::BindGroupEntry<'a>],
}

/// One of the application's resources, held by the runtime.
#[derive(Debug, Clone)]
enum Held {
    Buffer {
        buffer: wgpu::Buffer,
        offset: u64,
        size: Option<wgpu::BufferSize>,
    },
    Sampler(wgpu::Sampler),
    TextureView(wgpu::TextureView),
}

/// The application's bindings of the shared group, checked and held.
#[derive(Debug, Clone, Default)]
pub(crate) struct Shared {
    pub layout: Vec<wgpu::BindGroupLayoutEntry>,
    held: Vec<(u32, Held)>,
}

impl Shared {
    /// Check `given` against the passes' declarations: given exactly where the variant shares a
    /// group (`base` above 0), every binding a pass declares there has a layout entry and a
    /// resource, and nothing is at the runtime's bindings.
    pub fn new(
        given: Option<&SharedGroup<'_>>,
        group: u32,
        base: u32,
        passes: &[PassPlan],
    ) -> Result<Shared, RuntimeError> {
        let usage = |says: String| RuntimeError::usage("Setup::shared", says);
        let Some(given) = given else {
            if base > 0 {
                let names: BTreeMap<u32, &str> = passes
                    .iter()
                    .flat_map(|p| p.shared_own.iter().map(|(b, n)| (*b, n.as_str())))
                    .collect();
                return Err(usage(format!(
                    "is None, but the variant shares group {group} with the shader's own bindings ({}): give their layout entries and resources",
                    names
                        .iter()
                        .map(|(b, n)| format!("`{n}` at binding {b}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
            return Ok(Shared::default());
        };
        if base == 0 {
            return Err(usage(format!(
                "is given, but the variant's group {group} is its own (manifest `binding_base` 0)"
            )));
        }
        for e in given
            .layout
            .iter()
            .map(|e| e.binding)
            .chain(given.resources.iter().map(|e| e.binding))
        {
            if e >= base {
                return Err(usage(format!(
                    "binds binding {e} of group {group}, which is reproj's (from binding {base} on)"
                )));
            }
        }
        for p in passes {
            for (b, name) in &p.shared_own {
                if !given.layout.iter().any(|e| e.binding == *b) {
                    return Err(usage(format!(
                        "{} declares the application's `{name}` at @group({group}) @binding({b}), which has no layout entry here",
                        p.label
                    )));
                }
                if !given.resources.iter().any(|e| e.binding == *b) {
                    return Err(usage(format!(
                        "{} declares the application's `{name}` at @group({group}) @binding({b}), which has no resource here",
                        p.label
                    )));
                }
            }
        }
        let held = given
            .resources
            .iter()
            .map(|e| {
                let h = match &e.resource {
                    wgpu::BindingResource::Buffer(b) => Held::Buffer {
                        buffer: b.buffer.clone(),
                        offset: b.offset,
                        size: b.size,
                    },
                    wgpu::BindingResource::Sampler(s) => Held::Sampler((*s).clone()),
                    wgpu::BindingResource::TextureView(v) => Held::TextureView((*v).clone()),
                    _ => {
                        return Err(usage(format!(
                            "binding {}: only a buffer, a sampler or a texture view can share the variant's group",
                            e.binding
                        )));
                    }
                };
                Ok((e.binding, h))
            })
            .collect::<Result<_, _>>()?;
        Ok(Shared {
            layout: given.layout.to_vec(),
            held,
        })
    }

    /// The application's layout entries of the shared group that pass `p` declares (none where
    /// the group is the variant's own). A pass binds only those: lavapipe 22.3 faults drawing a
    /// pass of a shader on all four groups whose shared group's layout holds a uniform the pass
    /// does not declare.
    pub fn layout_for<'s>(
        &'s self,
        p: &'s PassPlan,
    ) -> impl Iterator<Item = wgpu::BindGroupLayoutEntry> + 's {
        self.layout
            .iter()
            .copied()
            .filter(|e| p.shared_own.contains_key(&e.binding))
    }

    /// The application's bind group entries of the shared group that pass `p` declares (as
    /// [`Shared::layout_for`]).
    pub fn entries_for<'s>(
        &'s self,
        p: &PassPlan,
    ) -> impl Iterator<Item = wgpu::BindGroupEntry<'s>> {
        let declared = self
            .held
            .iter()
            .filter(|(binding, _)| p.shared_own.contains_key(binding));
        declared.map(|(binding, h)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: match h {
                Held::Buffer {
                    buffer,
                    offset,
                    size,
                } => wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer,
                    offset: *offset,
                    size: *size,
                }),
                Held::Sampler(s) => wgpu::BindingResource::Sampler(s),
                Held::TextureView(v) => wgpu::BindingResource::TextureView(v),
            },
        })
    }
}
