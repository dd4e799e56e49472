//! Bind group layouts and bind groups of a fragment interface, bound from the scene (a variant's
//! own group is the runtime's).

use std::collections::BTreeMap;
use std::num::NonZeroU64;

use crate::error::ReplayError;
use reproj_scene::reflect::{self, Interface, ResourceKind};

use reproj_scene_gpu::view_dimension;

use super::*;

/// The layout entries of group `g`'s resources `rs`, and what of `scene` is bound to each
/// ([`Binding::resolve`]).
pub(super) fn group_entries<'r>(
    label: &str,
    g: u32,
    rs: &[&reflect::Resource],
    scene: &'r Scene,
) -> Result<
    (
        Vec<wgpu::BindGroupLayoutEntry>,
        Vec<wgpu::BindingResource<'r>>,
    ),
    ReplayError,
> {
    let mut entries = Vec::new();
    let mut bind = Vec::new();
    for r in rs {
        let binding = Binding {
            label,
            group: g,
            r,
            scene,
        };
        let (ty, res) = binding.resolve()?;
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: r.binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty,
            count: None,
        });
        bind.push(res);
    }
    Ok((entries, bind))
}

/// The bind group entries of resources `rs`, bound to `bind` (in the same order).
pub(super) fn entries_of<'r>(
    rs: &[&reflect::Resource],
    bind: Vec<wgpu::BindingResource<'r>>,
) -> Vec<wgpu::BindGroupEntry<'r>> {
    rs.iter()
        .zip(bind)
        .map(|(r, resource)| wgpu::BindGroupEntry {
            binding: r.binding,
            resource,
        })
        .collect()
}

/// An interface's resources by group.
pub(super) fn by_group(iface: &Interface) -> BTreeMap<u32, Vec<&reflect::Resource>> {
    let mut by_group: BTreeMap<u32, Vec<&reflect::Resource>> = BTreeMap::new();
    for r in &iface.resources {
        by_group.entry(r.group).or_default().push(r);
    }
    by_group
}

/// Bind group layouts and bind groups of one fragment entry point.
pub(super) struct Bindings {
    pub(super) layouts: BTreeMap<u32, wgpu::BindGroupLayout>,
    pub(super) groups: BTreeMap<u32, wgpu::BindGroup>,
    /// Each layout's entries, written out: part of the pipeline cache key.
    pub(super) layout_keys: BTreeMap<u32, String>,
}

/// Give the resources (and uniform fields) of a pass module the names they have in the original
/// shader, matched by group and binding (fields by position: the struct is the same).
pub(super) fn restore_names(iface: &mut Interface, original: &Interface) {
    for r in &mut iface.resources {
        let Some(o) = original
            .resources
            .iter()
            .find(|o| o.group == r.group && o.binding == r.binding)
        else {
            continue;
        };
        r.name = o.name.clone();
        if let (
            ResourceKind::Uniform { fields, .. },
            ResourceKind::Uniform {
                fields: ofields, ..
            },
        ) = (&mut r.kind, &o.kind)
            && fields.len() == ofields.len()
        {
            for (f, of) in fields.iter_mut().zip(ofields) {
                f.name = of.name.clone();
            }
        }
    }
}

impl Bindings {
    /// No bind group: a pass that binds only the vertex transforms.
    pub(super) fn empty() -> Bindings {
        Bindings {
            layouts: BTreeMap::new(),
            groups: BTreeMap::new(),
            layout_keys: BTreeMap::new(),
        }
    }
}

/// One resource of a fragment interface being bound from the scene: where it is, and the scene.
/// (A variant's own bindings are the runtime's, `variant/gpu.rs`.)
struct Binding<'a, 'r> {
    /// The pass, for messages.
    label: &'a str,
    group: u32,
    r: &'a reflect::Resource,
    scene: &'r Scene,
}

/// A resource's layout entry type and the resource bound to it.
type Bound<'r> = (wgpu::BindingType, wgpu::BindingResource<'r>);

impl<'r> Binding<'_, 'r> {
    /// The resource is not one the replay binds.
    fn missing(&self, what: &str) -> ReplayError {
        ReplayError::Variant {
            message: format!(
                "{}: {what} `{}` at @group({}) @binding({}) is not one the replay knows",
                self.label, self.r.name, self.group, self.r.binding
            ),
        }
    }

    /// The resource's layout entry type and what is bound to it, by its kind.
    fn resolve(&self) -> Result<Bound<'r>, ReplayError> {
        match &self.r.kind {
            ResourceKind::Uniform { size, .. } => self.uniform(*size),
            ResourceKind::Storage(_) => self.storage(),
            ResourceKind::Texture { dim } => self.texture(*dim),
            ResourceKind::DepthTexture => self.depth_texture(),
            ResourceKind::Sampler { comparison } => self.scene_sampler(*comparison),
            ResourceKind::Unsupported(w) => Err(ReplayError::Unsupported { what: w.clone() }),
        }
    }

    /// A uniform buffer of the scene.
    fn uniform(&self, size: u32) -> Result<Bound<'r>, ReplayError> {
        let buf = &self
            .scene
            .uniforms
            .get(&self.r.name)
            .ok_or_else(|| self.missing("uniform"))?
            .0;
        Ok((
            wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: NonZeroU64::new(size as u64),
            },
            buf.as_entire_binding(),
        ))
    }

    /// A read-only storage buffer of the scene.
    fn storage(&self) -> Result<Bound<'r>, ReplayError> {
        let buf = &self
            .scene
            .storage
            .get(&self.r.name)
            .ok_or_else(|| self.missing("storage buffer"))?
            .0;
        Ok((
            wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            buf.as_entire_binding(),
        ))
    }

    /// A float texture of the scene (filterable).
    fn texture(&self, dim: reflect::TexDim) -> Result<Bound<'r>, ReplayError> {
        let view = self
            .scene
            .textures
            .get(&self.r.name)
            .ok_or_else(|| self.missing("texture"))?;
        Ok((
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: view_dimension(dim),
                multisampled: false,
            },
            wgpu::BindingResource::TextureView(view),
        ))
    }

    /// A depth texture: the scene's depth pass.
    fn depth_texture(&self) -> Result<Bound<'r>, ReplayError> {
        let view = &self
            .scene
            .depth
            .get(&self.r.name)
            .ok_or_else(|| self.missing("depth texture"))?
            .view;
        Ok((
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            wgpu::BindingResource::TextureView(view),
        ))
    }

    /// A sampler of the scene, a comparison one where the shader declares it.
    fn scene_sampler(&self, comparison: bool) -> Result<Bound<'r>, ReplayError> {
        let s = self
            .scene
            .samplers
            .get(&self.r.name)
            .ok_or_else(|| self.missing("sampler"))?;
        Ok((
            wgpu::BindingType::Sampler(if comparison {
                wgpu::SamplerBindingType::Comparison
            } else {
                wgpu::SamplerBindingType::Filtering
            }),
            wgpu::BindingResource::Sampler(s),
        ))
    }
}

impl Renderer {
    /// Layouts and bind groups of one fragment interface (every group but the vertex group): each
    /// group's resources resolved ([`Renderer::group_entries`]), then its layout and bind group made.
    pub(super) fn bindings(
        &self,
        label: &str,
        iface: &Interface,
        scene: &Scene,
    ) -> Result<Bindings, ReplayError> {
        let mut out = Bindings::empty();
        for (g, rs) in by_group(iface) {
            let (entries, bind) = group_entries(label, g, &rs, scene)?;
            let (layout, group) = self.bind_group(
                &format!("{label}: bind group {g}"),
                label,
                &entries,
                &rs,
                bind,
            )?;
            out.layouts.insert(g, layout);
            out.groups.insert(g, group);
            out.layout_keys.insert(g, format!("{entries:?}"));
        }
        Ok(out)
    }

    /// One group's layout, from `entries`, and its bind group of `bind` (by `rs`' bindings), in
    /// the error scope `what`.
    fn bind_group(
        &self,
        what: &str,
        label: &str,
        entries: &[wgpu::BindGroupLayoutEntry],
        rs: &[&reflect::Resource],
        bind: Vec<wgpu::BindingResource<'_>>,
    ) -> Result<(wgpu::BindGroupLayout, wgpu::BindGroup), ReplayError> {
        self.scoped(what, || {
            let layout = self
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(label),
                    entries,
                });
            let group_entries = entries_of(rs, bind);
            let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &layout,
                entries: &group_entries,
            });
            (layout, group)
        })
    }
}
