//! One pass of the manifest, checked: its file, color targets, depth state and bindings.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use super::{
    Added, AddedBinding, At, Attachment, ColorLoad, ColorPlan, DepthPlan, PassPlan, SamplerPlan,
    TexturePlan,
};
use crate::RuntimeError;
use crate::files::{self, ReadLimits};
use crate::manifest::{self, LoadOp, Manifest, Pass, Resource};
use crate::webgpu;

/// A pass's bindings, sorted by who binds them ([`Check::bindings`]).
struct Bound {
    added: Vec<AddedBinding>,
    own_groups: BTreeMap<u32, String>,
    shared_own: BTreeMap<u32, String>,
}

/// Where the passes' WGSL comes from.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Sources<'a> {
    /// The files the manifest names, in its folder, read within the limits.
    Files {
        dir: &'a Path,
        limits: &'a ReadLimits,
    },
    /// Given in memory, in the manifest's pass order.
    Given(&'a [String]),
}

/// What checking a pass needs of the manifest already checked.
pub(super) struct Check<'a> {
    pub at: &'a At<'a>,
    pub sources: Sources<'a>,
    pub m: &'a Manifest,
    pub textures: &'a [TexturePlan],
    pub samplers: &'a [SamplerPlan],
}

impl Check<'_> {
    /// Pass `i`: its source read, its targets and bindings resolved.
    pub fn pass(&self, i: usize, p: &Pass) -> Result<PassPlan, RuntimeError> {
        let at = self.at;
        let source = match self.sources {
            Sources::Files { dir, limits } => {
                let file = files::inside(dir, &p.file)
                    .map_err(|why| at.err(format!("passes[{i}].file"), why))?;
                files::read_text(&file, files::FileKind::Shader, limits)?
            }
            // `Plan::new` checked there is one per pass.
            Sources::Given(given) => given[i].clone(),
        };
        let Bound {
            added,
            own_groups,
            shared_own,
        } = self.bindings(i, p)?;
        Ok(PassPlan {
            label: format!("pass {} {} ({})", i + 1, p.kind, p.file),
            source,
            entry: p.entry.clone(),
            colors: self.colors(i, p)?,
            depth: self.depth(i, p)?,
            added,
            own_groups,
            shared_own,
        })
    }

    /// The texture playing `role` in every ping-pong entry (`field` names where the role is).
    fn resolve(&self, field: &str, role: &str) -> Result<Vec<usize>, RuntimeError> {
        (0..self.m.frames.ping_pong.len())
            .map(|k| {
                let name = self.m.texture_for(role, k).ok_or_else(|| {
                    self.at.err(
                        field,
                        format!(
                            "no texture plays the role `{role}` (frames.ping_pong[{k}], textures)"
                        ),
                    )
                })?;
                self.textures
                    .iter()
                    .position(|t| t.name == name)
                    .ok_or_else(|| {
                        self.at.err(
                            format!("frames.ping_pong[{k}]"),
                            format!("maps `{role}` to `{name}`, which is not in `textures`"),
                        )
                    })
            })
            .collect()
    }

    fn colors(&self, i: usize, p: &Pass) -> Result<Vec<ColorPlan>, RuntimeError> {
        let at = self.at;
        let mut colors = Vec::new();
        for (c_i, c) in p.colors.iter().enumerate() {
            let field = |rest: &str| format!("passes[{i}].colors[{c_i}].{rest}");
            if let Some(b) = &c.blend {
                return Err(at.err(
                    field("blend"),
                    format!("blending `{b}` is not supported (null only)"),
                ));
            }
            let format = c
                .format
                .as_deref()
                .map(webgpu::texture_format)
                .transpose()
                .map_err(|e| at.err(field("format"), e))?;
            let attachment = if c.attachment == manifest::FRAME {
                Attachment::Frame
            } else {
                let ts = self.resolve(&field("attachment"), &c.attachment)?;
                for t in ts.iter().map(|&t| &self.textures[t]) {
                    if format.is_some_and(|f| f != t.format) {
                        return Err(at.err(
                            field("format"),
                            format!("is not the format of texture `{}`", t.name),
                        ));
                    }
                    if !t.usage.contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
                        return Err(at.err(
                            field("attachment"),
                            format!("texture `{}` has no `render_attachment` usage", t.name),
                        ));
                    }
                }
                Attachment::Texture(ts)
            };
            let load = match &c.load {
                LoadOp::Load => ColorLoad::Load,
                LoadOp::Clear { value: None } => ColorLoad::Clear(None),
                LoadOp::Clear { value: Some(v) } => match v.as_slice() {
                    &[r, g, b, a] => ColorLoad::Clear(Some(wgpu::Color { r, g, b, a })),
                    _ => {
                        return Err(at.err(
                            field("load.value"),
                            format!("a color clear value has 4 numbers, not {}", v.len()),
                        ));
                    }
                },
            };
            colors.push(ColorPlan {
                location: c.location,
                attachment,
                format,
                load,
                store: c.store,
            });
        }
        let mut locations: Vec<u32> = colors.iter().map(|c| c.location).collect();
        locations.sort_unstable();
        if locations.windows(2).any(|w| w[0] == w[1]) {
            return Err(at.err(
                format!("passes[{i}].colors"),
                "two color targets share a location",
            ));
        }
        Ok(colors)
    }

    fn depth(&self, i: usize, p: &Pass) -> Result<DepthPlan, RuntimeError> {
        let at = self.at;
        let field = |rest: &str| format!("passes[{i}].depth.{rest}");
        let d = &p.depth;
        if let Some(s) = &d.stencil {
            return Err(at.err(
                field("stencil"),
                format!("stencil `{s}` is not supported (null only)"),
            ));
        }
        let format = webgpu::texture_format(&d.format).map_err(|e| at.err(field("format"), e))?;
        let textures = self.resolve(&field("attachment"), &d.attachment)?;
        for t in textures.iter().map(|&t| &self.textures[t]) {
            if t.format != format {
                return Err(at.err(
                    field("format"),
                    format!("is not the format of texture `{}`", t.name),
                ));
            }
        }
        let clear = match &d.load {
            LoadOp::Load => None,
            LoadOp::Clear { value } => Some(match value.as_deref() {
                Some(&[z, ..]) => z as f32,
                Some([]) => return Err(at.err(field("load.value"), "is empty")),
                None => self.m.conventions.depth_clear as f32,
            }),
        };
        Ok(DepthPlan {
            textures,
            format,
            compare: webgpu::compare(&d.compare).map_err(|e| at.err(field("compare"), e))?,
            write: d.write,
            clear,
            store: d.store,
        })
    }

    /// The bindings the runtime binds (the variant's), the groups of the application's own
    /// resources the pass declares (one resource's name each, for messages), and the
    /// application's own bindings in the variant's group where it shares one.
    fn bindings(&self, i: usize, p: &Pass) -> Result<Bound, RuntimeError> {
        let at = self.at;
        let base = self.m.binding_base;
        let mut added = Vec::new();
        let mut own_groups = BTreeMap::new();
        let mut shared_own = BTreeMap::new();
        let mut seen = BTreeSet::new();
        for (b_i, b) in p.bindings.iter().enumerate() {
            let field = |rest: &str| format!("passes[{i}].bindings[{b_i}]{rest}");
            if !seen.insert((b.group, b.binding)) {
                return Err(at.err(
                    field(""),
                    format!(
                        "@group({}) @binding({}) is declared twice",
                        b.group, b.binding
                    ),
                ));
            }
            let group = self.m.group;
            let resource = match &b.resource {
                Resource::Own if b.group != group => {
                    own_groups.entry(b.group).or_insert_with(|| b.name.clone());
                    continue;
                }
                Resource::Own if b.binding < base => {
                    shared_own.insert(b.binding, b.name.clone());
                    continue;
                }
                Resource::Own => {
                    return Err(at.err(
                        field(".resource"),
                        format!(
                            "`{}` is the application's own resource, but @group({group}) @binding({}) is among the bindings reproj added (`group`, from `binding_base` {base} on)",
                            b.name, b.binding
                        ),
                    ));
                }
                _ if b.group == group && b.binding < base => {
                    return Err(at.err(
                        field(".binding"),
                        format!(
                            "`{}` is a binding reproj added, but its binding {} is below `binding_base` {base}, where the application's own are",
                            b.name, b.binding
                        ),
                    ));
                }
                _ if b.group != group => {
                    return Err(at.err(
                        field(".resource"),
                        format!(
                            "`{}` is a binding reproj added, but it is in group {}, not the variant's group {group} (`group`)",
                            b.name, b.group
                        ),
                    ));
                }
                Resource::Params => Added::Params,
                Resource::Motion => Added::Motion,
                Resource::Texture { role } => {
                    Added::Texture(self.resolve(&field(".resource.role"), role)?)
                }
                Resource::Sampler { name } => Added::Sampler(
                    self.samplers
                        .iter()
                        .position(|s| &s.name == name)
                        .ok_or_else(|| {
                            at.err(
                                field(".resource.name"),
                                format!("no sampler `{name}` in `samplers`"),
                            )
                        })?,
                ),
            };
            added.push(AddedBinding {
                group: b.group,
                binding: b.binding,
                ty: webgpu::binding_type(&b.layout).map_err(|e| at.err(field(".layout"), e))?,
                resource,
            });
        }
        Ok(Bound {
            added,
            own_groups,
            shared_own,
        })
    }
}
