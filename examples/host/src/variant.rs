//! Running a reproj variant from its `manifest.json` alone — the part of this host an engine copies.
//!
//! [`Variant::new`] builds everything once, in the manifest's order:
//!
//! 1. `required_features` were requested when the device was opened (`main.rs`, `gpu.rs`);
//! 2. `textures`: one texture each, the frame's size, with the listed format and usages;
//! 3. `samplers`: one sampler each;
//! 4. `params`: the `reproj_params` uniform buffer of `params.size` bytes;
//! 5. per pass, one bind group layout per group from each binding's `layout`;
//! 6. per pass and per entry of `frames.ping_pong`, the bind groups from each binding's
//!    `resource` (`own`: the engine's resource at that group and binding; `params`; `texture`: the
//!    texture playing that role in that ping-pong entry; `sampler`: by name);
//! 7. per pass, the pipeline: the engine's vertex stage plus the manifest's `vertex` contract,
//!    the pass's WGSL file and entry point, one color target per `colors[].location` (`format`, or
//!    the engine's frame format for `null`), the depth state (`depth.format`, `compare`, `write`).
//!
//! Each frame `i`, [`Variant::write_params`] writes `params.fields` and [`Variant::encode_frame`]
//! records the passes in order with their attachments (`frame` is the engine's frame target,
//! anything else a role looked up in `frames.ping_pong[i % len]`) and their load/clear and store
//! operations. No role, binding or pass name is assumed: a manifest that adds a texture, a role
//! or a color target runs unchanged.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use anyhow::{Context, anyhow, bail};

use crate::engine::{self, Engine, Pipelines};
use crate::gpu::{Gpu, Timer};
use crate::manifest::{self, LoadOp, Manifest, ParamValue, Resource};
use crate::webgpu;

/// A texture of the manifest's `textures`.
struct Texture {
    view: wgpu::TextureView,
    format: wgpu::TextureFormat,
}

/// One pass, ready to record.
struct PassGpu {
    label: String,
    pipes: Pipelines,
    /// Bind groups (group index, group) for each entry of `frames.ping_pong`.
    groups: Vec<Vec<(u32, wgpu::BindGroup)>>,
}

/// A variant on the GPU.
pub struct Variant {
    pub manifest: Manifest,
    textures: BTreeMap<String, Texture>,
    params: wgpu::Buffer,
    passes: Vec<PassGpu>,
}

impl std::fmt::Debug for Variant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Variant")
            .field("strategy", &self.manifest.strategy)
            .field("passes", &self.passes.len())
            .finish()
    }
}

/// Every bind group index a variant's passes use (the engine keeps its own bindings out of them).
pub fn groups_used(m: &Manifest) -> BTreeSet<u32> {
    let mut g: BTreeSet<u32> = m
        .passes
        .iter()
        .flat_map(|p| p.bindings.iter().map(|b| b.group))
        .collect();
    g.insert(m.group);
    g
}

/// A clear color from a manifest value: `null` is the engine's own clear color.
fn clear_color(value: &Option<Vec<f64>>, engine_clear: wgpu::Color) -> anyhow::Result<wgpu::Color> {
    match value.as_deref() {
        None => Ok(engine_clear),
        Some([r, g, b, a]) => Ok(wgpu::Color {
            r: *r,
            g: *g,
            b: *b,
            a: *a,
        }),
        Some(v) => bail!("a color clear value has 4 numbers, the manifest gives {v:?}"),
    }
}

impl Variant {
    /// Build the variant in `dir` (its `manifest.json`, already read, and pass files) for
    /// `engine`'s scene and frame target.
    pub fn new(gpu: &Gpu, engine: &Engine, dir: &Path, m: Manifest) -> anyhow::Result<Variant> {
        let dev = &gpu.device;
        let size = engine.frame.size();

        // 2. Textures, all the frame's size (the only size in version 3).
        let mut textures = BTreeMap::new();
        for t in &m.textures {
            if t.size != "frame" {
                bail!("texture `{}`: unknown size `{}`", t.name, t.size);
            }
            let format = webgpu::texture_format(&t.format)
                .with_context(|| format!("texture `{}`", t.name))?;
            let tex = dev.create_texture(&wgpu::TextureDescriptor {
                label: Some(&t.name),
                size,
                mip_level_count: t.mip_levels,
                sample_count: t.sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: webgpu::texture_usages(&t.usage)
                    .with_context(|| format!("texture `{}`", t.name))?,
                view_formats: &[],
            });
            let view = tex.create_view(&Default::default());
            textures.insert(t.name.clone(), Texture { view, format });
        }

        // 3. Samplers.
        let mut samplers = BTreeMap::new();
        for s in &m.samplers {
            let what = || format!("sampler `{}`", s.name);
            let address = webgpu::address_mode(&s.address_mode).with_context(what)?;
            let sampler = dev.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(&s.name),
                address_mode_u: address,
                address_mode_v: address,
                address_mode_w: address,
                mag_filter: webgpu::filter(&s.mag_filter).with_context(what)?,
                min_filter: webgpu::filter(&s.min_filter).with_context(what)?,
                mipmap_filter: webgpu::mipmap_filter(&s.mipmap_filter).with_context(what)?,
                ..Default::default()
            });
            samplers.insert(s.name.clone(), sampler);
        }

        // 4. The params uniform buffer (written every frame by `write_params`).
        let params = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("reproj_params"),
            size: u64::from(m.params.size.max(16)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        for f in &m.params.fields {
            if f.offset + 4 > m.params.size || !matches!(f.ty.as_str(), "u32" | "f32") {
                bail!(
                    "param `{}`: a {} at offset {} does not fit a {}-byte buffer of u32/f32 fields",
                    f.name,
                    f.ty,
                    f.offset,
                    m.params.size
                );
            }
        }

        // 7 (shared). The engine's vertex stage, with the manifest's prev-clip contract.
        let vs_src = engine.vertex_wgsl(Some(&m.vertex))?;
        let vs = Engine::shader_module(gpu, "host vertex stage (variant)", &vs_src)?;

        let mut passes = Vec::new();
        for (i, p) in m.passes.iter().enumerate() {
            let label = format!("pass {} {} ({})", i + 1, p.kind, p.file);
            let ctx = || label.clone();

            // 5. Bind group layouts, one per group, from the bindings' `layout` entries.
            let mut by_group: BTreeMap<u32, Vec<&manifest::Binding>> = BTreeMap::new();
            for b in &p.bindings {
                if b.group == engine.vertex_group {
                    bail!(
                        "{label}: binding `{}` is in group {}, the engine's vertex group",
                        b.name,
                        b.group
                    );
                }
                by_group.entry(b.group).or_default().push(b);
            }
            let mut layouts = BTreeMap::new();
            for (g, bs) in &by_group {
                let entries = bs
                    .iter()
                    .map(|b| {
                        Ok(wgpu::BindGroupLayoutEntry {
                            binding: b.binding,
                            visibility: wgpu::ShaderStages::FRAGMENT,
                            ty: webgpu::binding_type(&b.layout)
                                .with_context(|| format!("binding `{}`", b.name))?,
                            count: None,
                        })
                    })
                    .collect::<anyhow::Result<Vec<_>>>()
                    .with_context(ctx)?;
                let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(&label),
                    entries: &entries,
                });
                layouts.insert(*g, layout);
            }

            // 6. Bind groups from the bindings' `resource`, once per ping-pong entry.
            let mut groups = Vec::new();
            for frame in 0..m.frames.ping_pong.len() as u32 {
                let mut per_group = Vec::new();
                for (g, bs) in &by_group {
                    let mut entries = Vec::new();
                    for b in bs {
                        let at =
                            || format!("{label}: `{}` @group({g}) @binding({})", b.name, b.binding);
                        let resource = match &b.resource {
                            Resource::Own => {
                                engine.own_resource(b.group, b.binding).ok_or_else(|| {
                                    anyhow!(
                                        "{}: the original shader declares no resource there",
                                        at()
                                    )
                                })?
                            }
                            Resource::Params => params.as_entire_binding(),
                            Resource::Texture { role } => {
                                let name = m.texture_for(role, frame).with_context(at)?;
                                let t = textures.get(name).ok_or_else(|| {
                                    anyhow!("{}: no texture `{name}` in `textures`", at())
                                })?;
                                wgpu::BindingResource::TextureView(&t.view)
                            }
                            Resource::Sampler { name } => {
                                wgpu::BindingResource::Sampler(samplers.get(name).ok_or_else(
                                    || anyhow!("{}: no sampler `{name}` in `samplers`", at()),
                                )?)
                            }
                        };
                        entries.push(wgpu::BindGroupEntry {
                            binding: b.binding,
                            resource,
                        });
                    }
                    per_group.push((
                        *g,
                        dev.create_bind_group(&wgpu::BindGroupDescriptor {
                            label: Some(&label),
                            layout: &layouts[g],
                            entries: &entries,
                        }),
                    ));
                }
                groups.push(per_group);
            }

            // 7. The pipeline: layouts (the engine's vertex group included), color targets by
            // location, depth state.
            let top = layouts
                .keys()
                .copied()
                .chain([engine.vertex_group])
                .max()
                .unwrap_or(0);
            let bgls: Vec<Option<&wgpu::BindGroupLayout>> = (0..=top)
                .map(|g| {
                    if g == engine.vertex_group {
                        Some(engine.vertex_layout())
                    } else {
                        layouts.get(&g)
                    }
                })
                .collect();
            let layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&label),
                bind_group_layouts: &bgls,
                immediate_size: 0,
            });
            let mut targets: Vec<Option<wgpu::ColorTargetState>> = Vec::new();
            for c in &p.colors {
                if let Some(b) = &c.blend {
                    bail!(
                        "{label}: color target {} asks for blending `{b}`",
                        c.location
                    );
                }
                let format = match &c.format {
                    Some(f) => webgpu::texture_format(f).with_context(ctx)?,
                    None => engine::FRAME_FORMAT,
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
            if let Some(s) = &p.depth.stencil {
                bail!("{label}: the depth state asks for stencil `{s}`");
            }
            let depth = wgpu::DepthStencilState {
                format: webgpu::texture_format(&p.depth.format).with_context(ctx)?,
                depth_write_enabled: Some(p.depth.write),
                depth_compare: Some(webgpu::compare(&p.depth.compare).with_context(ctx)?),
                stencil: Default::default(),
                bias: Default::default(),
            };
            let file = dir.join(&p.file);
            let src = std::fs::read_to_string(&file)
                .with_context(|| format!("reading {}", file.display()))?;
            let fs = Engine::shader_module(gpu, &label, &src)?;
            let pipes = engine.pipelines(gpu, &label, &layout, &vs, &fs, &p.entry, &targets, depth);
            gpu.check(&format!("building {label}"))?;
            passes.push(PassGpu {
                label,
                pipes,
                groups,
            });
        }

        let v = Variant {
            manifest: m,
            textures,
            params,
            passes,
        };
        v.clear_textures(gpu)?;
        Ok(v)
    }

    /// Clear every render-attachment texture once, before frame 0: depth formats to
    /// `conventions.depth_clear`, color formats to 0. (Frame 0 reads nothing anyway: its
    /// `steady` params make every pixel fresh.)
    fn clear_textures(&self, gpu: &Gpu) -> anyhow::Result<()> {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for t in &self.manifest.textures {
            let usage = webgpu::texture_usages(&t.usage)?;
            if !usage.contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
                continue;
            }
            let tex = &self.textures[&t.name];
            if tex.format.is_depth_stencil_format() {
                enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("clear"),
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &tex.view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(self.manifest.conventions.depth_clear as f32),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    ..Default::default()
                });
            } else {
                enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("clear"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &tex.view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    ..Default::default()
                });
            }
        }
        gpu.queue.submit([enc.finish()]);
        gpu.wait()?;
        gpu.check("clearing the variant's textures")
    }

    /// Set the `steady` value of parameter `name` (the refresh period `delta_n`, say).
    pub fn set_param(&mut self, name: &str, value: f64) -> anyhow::Result<()> {
        let f = self
            .manifest
            .params
            .fields
            .iter_mut()
            .find(|f| f.name == name)
            .ok_or_else(|| anyhow!("the manifest's params have no field `{name}`"))?;
        match &mut f.value {
            ParamValue::Steady { value: v, .. } | ParamValue::Constant { value: v } => *v = value,
            ParamValue::FrameIndex => bail!("param `{name}` is the frame index"),
        }
        Ok(())
    }

    /// Write frame `frame`'s `reproj_params`: per field, `constant` → its value; `steady` → `first`
    /// on frame 0 (nothing to reuse yet; also after a camera cut) else `value`; `frame_index` →
    /// the frame number. `u32` fields are rounded.
    pub fn write_params(&self, gpu: &Gpu, frame: u32) {
        let p = &self.manifest.params;
        let mut bytes = vec![0u8; p.size.max(16) as usize];
        for f in &p.fields {
            let x = match f.value {
                ParamValue::Constant { value } => value,
                ParamValue::Steady { value, first } => {
                    if frame == 0 {
                        first
                    } else {
                        value
                    }
                }
                ParamValue::FrameIndex => f64::from(frame),
            };
            let le = if f.ty == "u32" {
                (x.round().max(0.0) as u32).to_le_bytes()
            } else {
                (x as f32).to_le_bytes()
            };
            let at = f.offset as usize;
            bytes[at..at + 4].copy_from_slice(&le);
        }
        gpu.queue.write_buffer(&self.params, 0, &bytes);
    }

    /// Whether the frame target must hold the engine's background before the first pass: the first
    /// pass that draws to `frame` loads it (`--frame-load load`).
    pub fn loads_frame_first(&self) -> bool {
        self.manifest
            .passes
            .iter()
            .flat_map(|p| &p.colors)
            .find(|c| c.attachment == manifest::FRAME)
            .is_some_and(|c| matches!(c.load, LoadOp::Load))
    }

    /// Number of passes (one timestamp pair each).
    pub fn pass_count(&self) -> u32 {
        self.passes.len() as u32
    }

    /// Record frame `frame`: the passes in order, each with its attachments and load/store ops.
    pub fn encode_frame(
        &self,
        enc: &mut wgpu::CommandEncoder,
        engine: &Engine,
        frame: u32,
        timer: &Timer,
    ) -> anyhow::Result<()> {
        let m = &self.manifest;
        let texture = |role: &str| -> anyhow::Result<&Texture> {
            let name = m.texture_for(role, frame)?;
            self.textures
                .get(name)
                .ok_or_else(|| anyhow!("no texture `{name}` in `textures`"))
        };
        let store = |s: bool| {
            if s {
                wgpu::StoreOp::Store
            } else {
                wgpu::StoreOp::Discard
            }
        };
        for (i, (p, gp)) in m.passes.iter().zip(&self.passes).enumerate() {
            let mut colors: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = Vec::new();
            for c in &p.colors {
                let view = if c.attachment == manifest::FRAME {
                    &engine.frame_view
                } else {
                    &texture(&c.attachment)
                        .with_context(|| format!("{}: color {}", gp.label, c.location))?
                        .view
                };
                let load = match &c.load {
                    LoadOp::Load => wgpu::LoadOp::Load,
                    LoadOp::Clear { value } => wgpu::LoadOp::Clear(
                        clear_color(value, engine.clear).with_context(|| gp.label.clone())?,
                    ),
                };
                let at = c.location as usize;
                if colors.len() <= at {
                    colors.resize(at + 1, None);
                }
                colors[at] = Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load,
                        store: store(c.store),
                    },
                });
            }
            let d = &p.depth;
            let depth_load = match &d.load {
                LoadOp::Load => wgpu::LoadOp::Load,
                LoadOp::Clear { value } => wgpu::LoadOp::Clear(match value.as_deref() {
                    Some([z, ..]) => *z as f32,
                    _ => m.conventions.depth_clear as f32,
                }),
            };
            let depth_view = &texture(&d.attachment)
                .with_context(|| format!("{}: depth", gp.label))?
                .view;
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&gp.label),
                color_attachments: &colors,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: depth_load,
                        store: store(d.store),
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.writes(i as u32),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let plan = &gp.groups[frame as usize % gp.groups.len()];
            for (g, bg) in plan {
                pass.set_bind_group(*g, bg, &[]);
            }
            engine.draw(&mut pass, &gp.pipes);
        }
        Ok(())
    }
}
