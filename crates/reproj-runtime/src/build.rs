//! The GPU objects of a variant: its textures, samplers and, per pass, the layouts of its own
//! group and one pipeline per vertex stage of the application. Every call runs in a validation
//! error scope, so wgpu's complaints come back as errors naming the pass.

use std::collections::BTreeMap;

use crate::RuntimeError;
use crate::plan::{Attachment, PassPlan, Plan, SamplerPlan};
use crate::setup::Setup;
use crate::shared::Shared;

/// A texture of the manifest's `textures`, on the device.
#[derive(Debug)]
pub(crate) struct Texture {
    pub view: wgpu::TextureView,
}

/// One pass, ready to record.
#[derive(Debug)]
pub(crate) struct PassGpu {
    /// One per vertex stage of the setup.
    pub pipelines: Vec<wgpu::RenderPipeline>,
    /// The layouts of the runtime's group(s), by index.
    pub layouts: BTreeMap<u32, wgpu::BindGroupLayout>,
    /// The runtime's bind groups (group index, group) for each entry of `frames.ping_pong`.
    pub groups: Vec<Vec<(u32, wgpu::BindGroup)>>,
    /// The debug entry's pipelines ([`crate::Setup::classification`]), one per vertex stage:
    /// the first pass's only, empty elsewhere.
    pub classify: Vec<wgpu::RenderPipeline>,
}

/// The first pass's debug entry point: the hit map ([`crate::Setup::classification`]).
pub const CLASSIFY_ENTRY: &str = "reproj_classify";

/// Run `f` in a validation error scope; wgpu's error comes back naming `what`.
pub(crate) fn checked<T>(
    device: &wgpu::Device,
    what: &str,
    f: impl FnOnce() -> T,
) -> Result<T, RuntimeError> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    match pollster::block_on(scope.pop()) {
        Some(e) => Err(RuntimeError::Gpu {
            what: what.to_owned(),
            message: e.to_string(),
        }),
        None => Ok(out),
    }
}

/// The textures the runtime owns, the frame's size (`None` for the depth attachment).
pub(crate) fn textures(device: &wgpu::Device, plan: &Plan, size: [u32; 2]) -> Vec<Option<Texture>> {
    plan.textures
        .iter()
        .enumerate()
        .map(|(i, t)| {
            (i != plan.depth_texture).then(|| {
                let tex = device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(&t.name),
                    size: wgpu::Extent3d {
                        width: size[0],
                        height: size[1],
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: t.mip_levels,
                    sample_count: t.sample_count,
                    dimension: wgpu::TextureDimension::D2,
                    format: t.format,
                    usage: t.usage,
                    view_formats: &[],
                });
                Texture {
                    view: tex.create_view(&Default::default()),
                }
            })
        })
        .collect()
}

pub(crate) fn sampler(device: &wgpu::Device, s: &SamplerPlan) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(&s.name),
        address_mode_u: s.address,
        address_mode_v: s.address,
        address_mode_w: s.address,
        mag_filter: s.mag,
        min_filter: s.min,
        mipmap_filter: s.mipmap,
        ..Default::default()
    })
}

/// Pass `p`'s layouts and pipelines (one per vertex stage), and with `classify` its debug
/// entry's into a target of that format; its bind groups come from `bind`.
pub(crate) fn build_pass(
    device: &wgpu::Device,
    plan: &Plan,
    p: &PassPlan,
    setup: &Setup<'_>,
    user: &BTreeMap<u32, &wgpu::BindGroupLayout>,
    (shared, classify): (&Shared, Option<wgpu::TextureFormat>),
) -> Result<PassGpu, RuntimeError> {
    for (g, name) in &p.own_groups {
        if !user.contains_key(g) {
            return Err(RuntimeError::usage(
                "Setup::bind_group_layouts",
                format!(
                    "{} declares the application's `{name}` in group {g}, which has no layout here",
                    p.label
                ),
            ));
        }
    }
    let mut targets: Vec<Option<wgpu::ColorTargetState>> = Vec::new();
    for c in &p.colors {
        let format = match (&c.attachment, c.format) {
            (Attachment::Frame, Some(f)) if f != setup.color_format => {
                return Err(RuntimeError::usage(
                    "Setup::color_format",
                    format!(
                        "is {:?}, {} writes the frame as {f:?}",
                        setup.color_format, p.label
                    ),
                ));
            }
            (Attachment::Frame, _) => setup.color_format,
            (Attachment::Texture(ts), f) => f.unwrap_or(plan.textures[ts[0]].format),
        };
        let at = c.location as usize;
        if targets.len() <= at {
            targets.resize(at + 1, None);
        }
        targets[at] = Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        });
    }
    checked(device, &p.label, || {
        let mut layouts = BTreeMap::new();
        // The variant's group also where the pass reads only the application's bindings there.
        let groups: std::collections::BTreeSet<u32> = p
            .added
            .iter()
            .map(|b| b.group)
            .chain((!p.shared_own.is_empty()).then_some(plan.group))
            .collect();
        let app: std::collections::BTreeSet<u32> = user.keys().copied().collect();
        for g in own_indices(&groups, &app) {
            let entries: Vec<wgpu::BindGroupLayoutEntry> = p
                .added
                .iter()
                .filter(|b| b.group == g)
                .map(|b| wgpu::BindGroupLayoutEntry {
                    binding: b.binding,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: b.ty,
                    count: None,
                })
                .chain(shared.layout_for(p).filter(|_| g == plan.group))
                .collect();
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(&p.label),
                entries: &entries,
            });
            layouts.insert(g, layout);
        }
        let top = layouts
            .keys()
            .chain(user.keys())
            .copied()
            .max()
            .unwrap_or(0);
        // No gap: `own_indices` gave every index the application leaves free a layout.
        let bgls: Vec<Option<&wgpu::BindGroupLayout>> = (0..=top)
            .map(|g| layouts.get(&g).or_else(|| user.get(&g).copied()))
            .collect();
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&p.label),
            bind_group_layouts: &bgls,
            immediate_size: 0,
        });
        let fs = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(&p.label),
            source: wgpu::ShaderSource::Wgsl(p.source.as_str().into()),
        });
        let depth = wgpu::DepthStencilState {
            format: p.depth.format,
            depth_write_enabled: Some(p.depth.write),
            depth_compare: Some(p.depth.compare),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let pipelines_of = |entry: &str, targets: &[Option<wgpu::ColorTargetState>], depth| {
            pipelines(
                device,
                setup,
                (&layout, &fs),
                (&p.label, entry),
                targets,
                depth,
            )
        };
        let pipelines = pipelines_of(&p.entry, &targets, depth.clone());
        // The hit map draws the geometry again into a target of its own, nearest first.
        let classify = classify.map_or_else(Vec::new, |format| {
            let target = [Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })];
            let depth = wgpu::DepthStencilState {
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                ..depth.clone()
            };
            pipelines_of(CLASSIFY_ENTRY, &target, depth)
        });
        PassGpu {
            pipelines,
            layouts,
            groups: Vec::new(),
            classify,
        }
    })
}

/// The group indices whose layouts (and bind groups) a pass owns: those it declares bindings in
/// (`declared`), and, with an empty layout, every index below the pipeline's highest group that
/// neither it nor the application (`app`: the indices of `Setup::bind_group_layouts`) uses.
/// Vulkan keeps a descriptor set bound across pipelines only while every lower set's layout is
/// identical, and wgpu does not rebind the sets above an index that became a gap (`None` in a
/// pipeline layout): a pass that declares nothing in the variant's group (2pass's second pass)
/// after one that does would draw with the application's higher groups bound under the other
/// layout — undefined; NVIDIA's driver draws nothing, lavapipe draws as meant. Empty layouts at
/// the gaps are a change of layout there, so wgpu rebinds the sets above.
pub(crate) fn own_indices(
    declared: &std::collections::BTreeSet<u32>,
    app: &std::collections::BTreeSet<u32>,
) -> std::collections::BTreeSet<u32> {
    let top = declared.iter().chain(app).copied().max();
    let gaps = top
        .into_iter()
        .flat_map(|top| 0..top)
        .filter(|g| !declared.contains(g) && !app.contains(g));
    declared.iter().copied().chain(gaps).collect()
}

/// One pipeline per vertex stage of `setup` drawing fragment entry `entry` of `fs` into `targets`
/// with `depth`, under `layout` (`label` names them).
fn pipelines(
    device: &wgpu::Device,
    setup: &Setup<'_>,
    (layout, fs): (&wgpu::PipelineLayout, &wgpu::ShaderModule),
    (label, entry): (&str, &str),
    targets: &[Option<wgpu::ColorTargetState>],
    depth: wgpu::DepthStencilState,
) -> Vec<wgpu::RenderPipeline> {
    setup
        .vertex
        .iter()
        .map(|v| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: v.module,
                    entry_point: Some(v.entry_point),
                    compilation_options: Default::default(),
                    buffers: v.buffers,
                },
                primitive: v.primitive,
                depth_stencil: Some(depth.clone()),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: fs,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::own_indices;

    fn set(v: &[u32]) -> BTreeSet<u32> {
        v.iter().copied().collect()
    }

    /// 2pass on marble: the first pass declares the variant's group 1, the second nothing; the
    /// application has 0 (the shader's) and 2 (its vertex transforms). The second pass owns an
    /// empty group 1, so no pass's pipeline layout has a gap below 2.
    #[test]
    fn a_pass_owns_every_index_the_application_leaves_free_below_its_top() {
        let app = set(&[0, 2]);
        assert_eq!(own_indices(&set(&[1]), &app), set(&[1]));
        assert_eq!(own_indices(&set(&[]), &app), set(&[1]));
        // Above the application's groups, nothing is filled past the pass's own.
        assert_eq!(own_indices(&set(&[3]), &set(&[0])), set(&[1, 2, 3]));
        assert_eq!(own_indices(&set(&[]), &set(&[0, 1])), set(&[]));
        assert_eq!(own_indices(&set(&[]), &set(&[])), set(&[]));
    }
}
