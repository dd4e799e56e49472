//! Bind group layouts and bind groups of a fragment interface, including the variant's own group.

use std::collections::BTreeMap;
use std::num::NonZeroU64;

use crate::error::ReplayError;
use reproj_scene::reflect::{self, Interface, ResourceKind};

use crate::gpu::tex_dim;

use reproj_instance::contract;

use super::*;

/// Host-owned resources of the variant's added bind group, by binding name.
pub(super) struct AddedResources<'a> {
    pub(super) params: &'a wgpu::Buffer,
    pub(super) point_sampler: &'a wgpu::Sampler,
    pub(super) linear_sampler: &'a wgpu::Sampler,
    /// The payload is rgba16float (always filterable).
    pub(super) payload_half: bool,
    pub(super) prev_payload: &'a wgpu::TextureView,
    /// The previous frame's depth copy (r32float), read as a float texture.
    pub(super) prev_depth_copy: &'a wgpu::TextureView,
    /// The previous frame's depth buffer, for variants written before the depth copy, whose lookup
    /// declares `reproj_prev_depth` as a depth texture (they list no depth copy target).
    pub(super) prev_depth_buffer: Option<&'a wgpu::TextureView>,
    pub(super) cur_payload: &'a wgpu::TextureView,
    /// The motion vectors of this frame, for a variant that reads them (`reproj_motion`).
    pub(super) motion: Option<&'a wgpu::TextureView>,
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

/// One resource of a fragment interface being bound: where it is, and what it is bound from (the
/// variant's added resources in its own group, the scene's elsewhere).
struct Binding<'a, 'r> {
    /// The pass, for messages.
    label: &'a str,
    group: u32,
    r: &'a reflect::Resource,
    /// In the variant's added group.
    in_added: bool,
    scene: &'r Scene,
    added: Option<&'r AddedResources<'r>>,
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
    /// `float32_filterable`: the device filters 32-bit float textures.
    fn resolve(&self, float32_filterable: bool) -> Result<Bound<'r>, ReplayError> {
        match &self.r.kind {
            ResourceKind::Uniform { size, .. } => self.uniform(*size),
            ResourceKind::Storage(_) => self.storage(),
            ResourceKind::Texture { dim } => self.texture(*dim, float32_filterable),
            ResourceKind::DepthTexture => self.depth_texture(),
            ResourceKind::Sampler { .. } if self.in_added => self.added_sampler(),
            ResourceKind::Sampler { comparison } => self.scene_sampler(*comparison),
            ResourceKind::Unsupported(w) => Err(ReplayError::Unsupported { what: w.clone() }),
        }
    }

    /// A uniform buffer: the variant's parameters in its group, else the scene's.
    fn uniform(&self, size: u32) -> Result<Bound<'r>, ReplayError> {
        let buf = if self.in_added {
            match (self.r.name.as_str(), self.added) {
                (contract::PARAMS, Some(a)) => a.params,
                _ => return Err(self.missing("uniform")),
            }
        } else {
            &self
                .scene
                .uniforms
                .get(&self.r.name)
                .ok_or_else(|| self.missing("uniform"))?
                .0
        };
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

    /// A float texture: the variant's payloads, depth copy and motion vectors in its group
    /// (only the previous payload filterable, where its format is), else the scene's.
    fn texture(
        &self,
        dim: reflect::TexDim,
        float32_filterable: bool,
    ) -> Result<Bound<'r>, ReplayError> {
        let (r, in_added) = (self.r, self.in_added);
        let view = if in_added {
            match (r.name.as_str(), self.added) {
                (contract::PREV_PAYLOAD, Some(a)) => a.prev_payload,
                (contract::PREV_DEPTH, Some(a)) => a.prev_depth_copy,
                (contract::CUR_PAYLOAD, Some(a)) => a.cur_payload,
                (contract::MOTION, Some(a)) => a.motion.ok_or_else(|| self.missing("texture"))?,
                _ => return Err(self.missing("texture")),
            }
        } else {
            self.scene
                .textures
                .get(&r.name)
                .ok_or_else(|| self.missing("texture"))?
        };
        let payload_half = self.added.is_some_and(|a| a.payload_half);
        let filterable =
            !in_added || (r.name == contract::PREV_PAYLOAD && (float32_filterable || payload_half));
        Ok((
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable },
                view_dimension: tex_dim(dim),
                multisampled: false,
            },
            wgpu::BindingResource::TextureView(view),
        ))
    }

    /// A depth texture: the previous depth buffer in the variant's group (a variant written
    /// before the depth copy), else the scene's depth pass.
    fn depth_texture(&self) -> Result<Bound<'r>, ReplayError> {
        let view = match (self.r.name.as_str(), self.added) {
            (contract::PREV_DEPTH, Some(a)) if self.in_added => a
                .prev_depth_buffer
                .ok_or_else(|| self.missing("depth texture"))?,
            _ if !self.in_added => {
                &self
                    .scene
                    .depth
                    .get(&self.r.name)
                    .ok_or_else(|| self.missing("depth texture"))?
                    .view
            }
            _ => return Err(self.missing("depth texture")),
        };
        Ok((
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            wgpu::BindingResource::TextureView(view),
        ))
    }

    /// One of the variant's two samplers (point, linear).
    fn added_sampler(&self) -> Result<Bound<'r>, ReplayError> {
        let (s, ty) = match (self.r.name.as_str(), self.added) {
            (contract::POINT_SAMPLER, Some(a)) => {
                (a.point_sampler, wgpu::SamplerBindingType::NonFiltering)
            }
            (contract::LINEAR_SAMPLER, Some(a)) => {
                (a.linear_sampler, wgpu::SamplerBindingType::Filtering)
            }
            _ => return Err(self.missing("sampler")),
        };
        Ok((
            wgpu::BindingType::Sampler(ty),
            wgpu::BindingResource::Sampler(s),
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
    /// group's resources resolved ([`Binding::resolve`]), then its layout and bind group made.
    pub(super) fn bindings(
        &self,
        label: &str,
        iface: &Interface,
        scene: &Scene,
        added_at: Option<AddedPlace>,
        added: Option<&AddedResources<'_>>,
    ) -> Result<Bindings, ReplayError> {
        let mut by_group: BTreeMap<u32, Vec<&reflect::Resource>> = BTreeMap::new();
        for r in &iface.resources {
            by_group.entry(r.group).or_default().push(r);
        }
        let float32_filterable = self
            .device
            .features()
            .contains(wgpu::Features::FLOAT32_FILTERABLE);
        let mut out = Bindings::empty();
        for (g, rs) in by_group {
            let mut entries = Vec::new();
            let mut bind: Vec<wgpu::BindingResource<'_>> = Vec::new();
            for r in &rs {
                let binding = Binding {
                    label,
                    group: g,
                    r,
                    in_added: added_at.is_some_and(|a| a.holds(g, r.binding)),
                    scene,
                    added,
                };
                let (ty, res) = binding.resolve(float32_filterable)?;
                entries.push(wgpu::BindGroupLayoutEntry {
                    binding: r.binding,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty,
                    count: None,
                });
                bind.push(res);
            }
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
            let group_entries: Vec<wgpu::BindGroupEntry<'_>> = rs
                .iter()
                .zip(bind)
                .map(|(r, resource)| wgpu::BindGroupEntry {
                    binding: r.binding,
                    resource,
                })
                .collect();
            let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &layout,
                entries: &group_entries,
            });
            (layout, group)
        })
    }
}
