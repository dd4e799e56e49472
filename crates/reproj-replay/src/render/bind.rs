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

impl Renderer {
    /// Layouts and bind groups of one fragment interface (every group but the vertex group).
    pub(super) fn bindings(
        &self,
        label: &str,
        iface: &Interface,
        scene: &Scene,
        added_group: Option<u32>,
        added: Option<&AddedResources<'_>>,
    ) -> Result<Bindings, ReplayError> {
        let added_format_16 = added.is_some_and(|a| a.payload_half);
        let mut by_group: BTreeMap<u32, Vec<&reflect::Resource>> = BTreeMap::new();
        for r in &iface.resources {
            by_group.entry(r.group).or_default().push(r);
        }
        let mut layouts = BTreeMap::new();
        let mut groups = BTreeMap::new();
        let mut layout_keys = BTreeMap::new();
        for (g, rs) in by_group {
            let in_added = Some(g) == added_group;
            let mut entries = Vec::new();
            let mut bind: Vec<wgpu::BindingResource<'_>> = Vec::new();
            for r in &rs {
                let missing = |what: &str| ReplayError::Variant {
                    message: format!(
                        "{label}: {what} `{}` at @group({g}) @binding({}) is not one the replay knows",
                        r.name, r.binding
                    ),
                };
                let (ty, res) = match &r.kind {
                    ResourceKind::Uniform { size, .. } => {
                        let buf = if in_added {
                            match (r.name.as_str(), added) {
                                (contract::PARAMS, Some(a)) => a.params,
                                _ => return Err(missing("uniform")),
                            }
                        } else {
                            &scene
                                .uniforms
                                .get(&r.name)
                                .ok_or_else(|| missing("uniform"))?
                                .0
                        };
                        (
                            wgpu::BindingType::Buffer {
                                ty: wgpu::BufferBindingType::Uniform,
                                has_dynamic_offset: false,
                                min_binding_size: NonZeroU64::new(*size as u64),
                            },
                            buf.as_entire_binding(),
                        )
                    }
                    ResourceKind::Storage(_) => {
                        let buf = &scene
                            .storage
                            .get(&r.name)
                            .ok_or_else(|| missing("storage buffer"))?
                            .0;
                        (
                            wgpu::BindingType::Buffer {
                                ty: wgpu::BufferBindingType::Storage { read_only: true },
                                has_dynamic_offset: false,
                                min_binding_size: None,
                            },
                            buf.as_entire_binding(),
                        )
                    }
                    ResourceKind::Texture { dim } => {
                        let view = if in_added {
                            match (r.name.as_str(), added) {
                                (contract::PREV_PAYLOAD, Some(a)) => a.prev_payload,
                                (contract::PREV_DEPTH, Some(a)) => a.prev_depth_copy,
                                (contract::CUR_PAYLOAD, Some(a)) => a.cur_payload,
                                (contract::MOTION, Some(a)) => {
                                    a.motion.ok_or_else(|| missing("texture"))?
                                }
                                _ => return Err(missing("texture")),
                            }
                        } else {
                            scene
                                .textures
                                .get(&r.name)
                                .ok_or_else(|| missing("texture"))?
                        };
                        let filterable = !in_added
                            || (r.name == contract::PREV_PAYLOAD
                                && (self
                                    .device
                                    .features()
                                    .contains(wgpu::Features::FLOAT32_FILTERABLE)
                                    || added_format_16));
                        (
                            wgpu::BindingType::Texture {
                                sample_type: wgpu::TextureSampleType::Float { filterable },
                                view_dimension: tex_dim(*dim),
                                multisampled: false,
                            },
                            wgpu::BindingResource::TextureView(view),
                        )
                    }
                    ResourceKind::DepthTexture => {
                        let view = match (r.name.as_str(), added) {
                            (contract::PREV_DEPTH, Some(a)) if in_added => a
                                .prev_depth_buffer
                                .ok_or_else(|| missing("depth texture"))?,
                            _ if !in_added => {
                                &scene
                                    .depth
                                    .get(&r.name)
                                    .ok_or_else(|| missing("depth texture"))?
                                    .view
                            }
                            _ => return Err(missing("depth texture")),
                        };
                        (
                            wgpu::BindingType::Texture {
                                sample_type: wgpu::TextureSampleType::Depth,
                                view_dimension: wgpu::TextureViewDimension::D2,
                                multisampled: false,
                            },
                            wgpu::BindingResource::TextureView(view),
                        )
                    }
                    ResourceKind::Sampler { .. } if in_added => {
                        let (s, ty) = match (r.name.as_str(), added) {
                            (contract::POINT_SAMPLER, Some(a)) => {
                                (a.point_sampler, wgpu::SamplerBindingType::NonFiltering)
                            }
                            (contract::LINEAR_SAMPLER, Some(a)) => {
                                (a.linear_sampler, wgpu::SamplerBindingType::Filtering)
                            }
                            _ => return Err(missing("sampler")),
                        };
                        (
                            wgpu::BindingType::Sampler(ty),
                            wgpu::BindingResource::Sampler(s),
                        )
                    }
                    ResourceKind::Sampler { comparison } => {
                        let s = scene
                            .samplers
                            .get(&r.name)
                            .ok_or_else(|| missing("sampler"))?;
                        (
                            wgpu::BindingType::Sampler(if *comparison {
                                wgpu::SamplerBindingType::Comparison
                            } else {
                                wgpu::SamplerBindingType::Filtering
                            }),
                            wgpu::BindingResource::Sampler(s),
                        )
                    }
                    ResourceKind::Unsupported(w) => {
                        return Err(ReplayError::Unsupported { what: w.clone() });
                    }
                };
                entries.push(wgpu::BindGroupLayoutEntry {
                    binding: r.binding,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty,
                    count: None,
                });
                bind.push(res);
            }
            let (layout, group) = self.scoped(&format!("{label}: bind group {g}"), || {
                let layout =
                    self.device
                        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                            label: Some(label),
                            entries: &entries,
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
            })?;
            layouts.insert(g, layout);
            groups.insert(g, group);
            layout_keys.insert(g, format!("{entries:?}"));
        }
        Ok(Bindings {
            layouts,
            groups,
            layout_keys,
        })
    }
}
