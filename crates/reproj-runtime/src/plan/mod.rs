//! The manifest checked once, at load, into wgpu values: every name resolved, every role mapped to
//! a texture for every ping-pong entry, every format, usage and binding type converted. After
//! [`Plan::new`] nothing about the manifest can fail; creating and recording only meet what the
//! application passed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::RuntimeError;
use crate::manifest::{self, Manifest, ParamValue};
use crate::webgpu;

mod pass;

pub(crate) use pass::Sources;

/// A texture of the manifest's `textures` (all are the frame's size).
#[derive(Debug, Clone)]
pub(crate) struct TexturePlan {
    pub name: String,
    pub format: wgpu::TextureFormat,
    pub usage: wgpu::TextureUsages,
    pub mip_levels: u32,
    pub sample_count: u32,
}

#[derive(Debug, Clone)]
pub(crate) struct SamplerPlan {
    pub name: String,
    pub mag: wgpu::FilterMode,
    pub min: wgpu::FilterMode,
    pub mipmap: wgpu::MipmapFilterMode,
    pub address: wgpu::AddressMode,
}

/// A color attachment: the application's frame, or a texture (an index into `textures`) per
/// ping-pong entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Attachment {
    Frame,
    Texture(Vec<usize>),
}

#[derive(Debug, Clone, Copy)]
pub(crate) enum ColorLoad {
    /// `None`: the application's clear color.
    Clear(Option<wgpu::Color>),
    Load,
}

#[derive(Debug, Clone)]
pub(crate) struct ColorPlan {
    pub location: u32,
    pub attachment: Attachment,
    /// `None`: the frame's format (only for the frame).
    pub format: Option<wgpu::TextureFormat>,
    pub load: ColorLoad,
    pub store: bool,
}

#[derive(Debug, Clone)]
pub(crate) struct DepthPlan {
    /// The attachment's texture per ping-pong entry (the application's depth target replaces it).
    pub textures: Vec<usize>,
    pub format: wgpu::TextureFormat,
    pub compare: wgpu::CompareFunction,
    pub write: bool,
    /// `Some(z)`: clear to `z`; `None`: load.
    pub clear: Option<f32>,
    pub store: bool,
}

/// What the runtime binds at a binding of the variant's own group.
#[derive(Debug, Clone)]
pub(crate) enum Added {
    Params,
    /// A texture (index into `textures`) per ping-pong entry.
    Texture(Vec<usize>),
    Sampler(usize),
    /// The application's motion vectors ([`crate::Setup::motion`]).
    Motion,
}

#[derive(Debug, Clone)]
pub(crate) struct AddedBinding {
    pub group: u32,
    pub binding: u32,
    pub ty: wgpu::BindingType,
    pub resource: Added,
}

#[derive(Debug, Clone)]
pub(crate) struct PassPlan {
    /// `pass 1 reproject (pass1_reproject.wgsl)`: names the pass in errors and GPU labels.
    pub label: String,
    pub source: String,
    pub entry: String,
    pub colors: Vec<ColorPlan>,
    pub depth: DepthPlan,
    /// The bindings the runtime binds (the variant's group).
    pub added: Vec<AddedBinding>,
    /// Groups of the application's own resources (`resource: own`) the pass's shader declares,
    /// but the variant's.
    pub own_groups: BTreeMap<u32, String>,
    /// The application's own resources in the variant's group, where it shares one: by binding.
    pub shared_own: BTreeMap<u32, String>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ParamType {
    U32,
    F32,
}

#[derive(Debug, Clone)]
pub(crate) struct ParamPlan {
    pub name: String,
    pub offset: usize,
    pub ty: ParamType,
    pub value: ParamValue,
}

/// The manifest, checked.
#[derive(Debug, Clone)]
pub(crate) struct Plan {
    pub required_features: wgpu::Features,
    pub textures: Vec<TexturePlan>,
    /// The texture every pass uses as its depth attachment: the application's depth target takes
    /// its place (see [`Plan::new`] for why that is the same frame).
    pub depth_texture: usize,
    pub samplers: Vec<SamplerPlan>,
    pub ping_pong: usize,
    pub params_size: usize,
    pub params: Vec<ParamPlan>,
    pub passes: Vec<PassPlan>,
    /// The render passes a frame records, as ranges of `passes` ([`render_passes`]).
    pub render_passes: Vec<std::ops::Range<usize>>,
    /// The variant's group (`group`): the application leaves it to the runtime, giving its own
    /// bindings there ([`crate::SharedGroup`]) where the variant shares it.
    pub group: u32,
    /// The added bindings' first binding number in `group` (0: the group is the variant's own).
    pub binding_base: u32,
    /// What a depth texture the runtime owns is cleared to before the first frame.
    pub depth_clear: f32,
    /// A pass reads the application's motion vectors (`reprojection: motion_vectors`).
    pub motion: bool,
}

/// Errors of one manifest file, naming the field.
pub(crate) struct At<'a>(&'a Path);

impl At<'_> {
    pub(crate) fn err(&self, field: impl Into<String>, message: impl Into<String>) -> RuntimeError {
        RuntimeError::Manifest {
            path: self.0.to_owned(),
            field: field.into(),
            message: message.into(),
        }
    }
}

impl Plan {
    /// Check `m` (read from `path`) with its passes' WGSL from `sources`.
    pub fn new(path: &Path, m: &Manifest, sources: Sources<'_>) -> Result<Plan, RuntimeError> {
        let at = At(path);
        if let Sources::Given(given) = sources
            && given.len() != m.passes.len()
        {
            return Err(at.err(
                "passes",
                format!(
                    "lists {} passes, {} sources were given",
                    m.passes.len(),
                    given.len()
                ),
            ));
        }
        if !m.conventions.are_webgpu() {
            return Err(at.err(
                "conventions",
                format!(
                    "the passes assume {:?}, not WebGPU's conventions, which wgpu uses",
                    m.conventions
                ),
            ));
        }
        if m.frames.ping_pong.is_empty() {
            return Err(at.err("frames.ping_pong", "is empty"));
        }
        if m.passes.is_empty() {
            return Err(at.err("passes", "is empty"));
        }
        let required_features =
            webgpu::features(&m.required_features).map_err(|e| at.err("required_features", e))?;
        let textures = textures(&at, m)?;
        let samplers = samplers(&at, m)?;
        let check = pass::Check {
            at: &at,
            sources,
            m,
            textures: &textures,
            samplers: &samplers,
        };
        let passes = m
            .passes
            .iter()
            .enumerate()
            .map(|(i, p)| check.pass(i, p))
            .collect::<Result<Vec<_>, _>>()?;
        let depth_texture = depth_attachment(&at, &textures, &passes)?;
        let motion = passes
            .iter()
            .any(|p| p.added.iter().any(|b| matches!(b.resource, Added::Motion)));
        match (m.reprojection.as_str(), motion) {
            ("vertex", false) | ("motion_vectors", true) => {}
            ("vertex" | "motion_vectors", _) => {
                return Err(at.err(
                    "reprojection",
                    format!(
                        "is `{}`, but {} pass binds the motion vectors (resource `motion`)",
                        m.reprojection,
                        if motion { "a" } else { "no" }
                    ),
                ));
            }
            (other, _) => {
                return Err(at.err(
                    "reprojection",
                    format!("`{other}` is neither `vertex` nor `motion_vectors`"),
                ));
            }
        }
        let (params_size, params) = params(&at, m)?;
        Ok(Plan {
            required_features,
            textures,
            depth_texture,
            samplers,
            ping_pong: m.frames.ping_pong.len(),
            params_size,
            params,
            render_passes: render_passes(&passes),
            passes,
            group: m.group,
            binding_base: m.binding_base,
            depth_clear: m.conventions.depth_clear as f32,
            motion,
        })
    }
}

/// The render passes a frame records, as ranges of `passes`: a pass joins the one before it
/// where it draws into the same attachments at the same locations, loads every one of them
/// and the depth, and the pass before stores them all — the two then share one render pass
/// (no store and reload of every target in between: `docs/PASSES.md`, "One render pass"),
/// which loads as the first and stores as the last.
fn render_passes(passes: &[PassPlan]) -> Vec<std::ops::Range<usize>> {
    let mut groups: Vec<std::ops::Range<usize>> = Vec::new();
    for (i, p) in passes.iter().enumerate() {
        let joins = i > 0 && {
            let before = &passes[i - 1];
            let targets = |p: &PassPlan| -> Vec<(u32, Attachment)> {
                p.colors
                    .iter()
                    .map(|c| (c.location, c.attachment.clone()))
                    .collect()
            };
            targets(p) == targets(before)
                && p.depth.clear.is_none()
                && p.colors.iter().all(|c| matches!(c.load, ColorLoad::Load))
                && before.depth.store
                && before.colors.iter().all(|c| c.store)
        };
        match groups.last_mut() {
            Some(g) if joins => g.end = i + 1,
            _ => groups.push(i..i + 1),
        }
    }
    groups
}

/// The texture every pass draws its depth into, which the application's depth target replaces.
///
/// Every pass of every emitted variant draws into one depth texture that the first pass clears,
/// no pass samples, and no frame keeps for the next (the lookup reads last frame's depth from the
/// `r32float` depth copy, or from the payload's depth channel). The runtime therefore draws into the application's depth target instead
/// of allocating that texture; a manifest where the depth attachment differs between passes or
/// frames, is sampled or is drawn as a color is refused.
fn depth_attachment(
    at: &At<'_>,
    textures: &[TexturePlan],
    passes: &[PassPlan],
) -> Result<usize, RuntimeError> {
    let mut depth = None;
    for (i, p) in passes.iter().enumerate() {
        for &t in &p.depth.textures {
            if *depth.get_or_insert(t) != t {
                return Err(at.err(
                    format!("passes[{i}].depth.attachment"),
                    "resolves to another texture than the other passes' or frames' depth: the runtime draws every pass into the application's one depth target (a variant written before the depth copy reads the previous frame's depth buffer so: write it again with `reproj instance` or `reproj emit`)",
                ));
            }
        }
    }
    let depth = depth.ok_or_else(|| at.err("passes", "no pass has a depth attachment"))?;
    let name = &textures[depth].name;
    let read = passes.iter().any(|p| {
        p.added
            .iter()
            .any(|b| matches!(&b.resource, Added::Texture(ts) if ts.contains(&depth)))
            || p.colors
                .iter()
                .any(|c| matches!(&c.attachment, Attachment::Texture(ts) if ts.contains(&depth)))
    });
    if read {
        return Err(at.err(
            "passes",
            format!(
                "the depth attachment `{name}` is also sampled or drawn as a color: the runtime draws into the application's depth target, which the passes may not read"
            ),
        ));
    }
    if !textures[depth].format.is_depth_stencil_format() {
        return Err(at.err(
            "textures",
            format!("the depth attachment `{name}` has no depth format"),
        ));
    }
    Ok(depth)
}

fn textures(at: &At<'_>, m: &Manifest) -> Result<Vec<TexturePlan>, RuntimeError> {
    let mut out: Vec<TexturePlan> = Vec::new();
    for (i, t) in m.textures.iter().enumerate() {
        let field = |rest: &str| format!("textures[{i}].{rest}");
        if out.iter().any(|o| o.name == t.name) {
            return Err(at.err(field("name"), format!("`{}` is declared twice", t.name)));
        }
        if t.size != "frame" {
            return Err(at.err(
                field("size"),
                format!("unknown size `{}` (`frame` only)", t.size),
            ));
        }
        // A render attachment has one level and one sample here: no manifest reproj writes asks
        // for more, and the passes' pipelines are single-sampled.
        if t.mip_levels != 1 {
            return Err(at.err(field("mip_levels"), format!("{} (1 only)", t.mip_levels)));
        }
        if t.sample_count != 1 {
            return Err(at.err(
                field("sample_count"),
                format!("{} (1 only)", t.sample_count),
            ));
        }
        out.push(TexturePlan {
            name: t.name.clone(),
            format: webgpu::texture_format(&t.format).map_err(|e| at.err(field("format"), e))?,
            usage: webgpu::texture_usages(&t.usage).map_err(|e| at.err(field("usage"), e))?,
            mip_levels: t.mip_levels,
            sample_count: t.sample_count,
        });
    }
    Ok(out)
}

fn samplers(at: &At<'_>, m: &Manifest) -> Result<Vec<SamplerPlan>, RuntimeError> {
    m.samplers
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let e = |rest: &str| {
                let field = format!("samplers[{i}].{rest}");
                move |message: String| at.err(field, message)
            };
            Ok(SamplerPlan {
                name: s.name.clone(),
                mag: webgpu::filter(&s.mag_filter).map_err(e("mag_filter"))?,
                min: webgpu::filter(&s.min_filter).map_err(e("min_filter"))?,
                mipmap: webgpu::mipmap_filter(&s.mipmap_filter).map_err(e("mipmap_filter"))?,
                address: webgpu::address_mode(&s.address_mode).map_err(e("address_mode"))?,
            })
        })
        .collect()
}

/// The params buffer: its size (at least 16 bytes, a uniform buffer's minimum) and its fields,
/// each a `u32` or `f32` inside it.
fn params(at: &At<'_>, m: &Manifest) -> Result<(usize, Vec<ParamPlan>), RuntimeError> {
    let size = m.params.size as usize;
    let mut out = Vec::new();
    for (i, f) in m.params.fields.iter().enumerate() {
        let ty = match f.ty.as_str() {
            "u32" => ParamType::U32,
            "f32" => ParamType::F32,
            other => {
                return Err(at.err(
                    format!("params.fields[{i}].type"),
                    format!("`{other}` (u32 or f32 only)"),
                ));
            }
        };
        let offset = f.offset as usize;
        if !offset.is_multiple_of(4) || offset + 4 > size {
            return Err(at.err(
                format!("params.fields[{i}].offset"),
                format!(
                    "`{}` at offset {offset} does not fit a {size}-byte buffer of 4-byte fields",
                    f.name
                ),
            ));
        }
        out.push(ParamPlan {
            name: f.name.clone(),
            offset,
            ty,
            value: f.value.clone(),
        });
    }
    Ok((size.max(16).next_multiple_of(16), out))
}

impl Plan {
    /// The `reproj_params` bytes of frame `frame` (counted from the last restart): per field,
    /// `constant` → its value; `steady` → `first` on frame 0 (nothing to reuse yet) else `value`,
    /// or `delta_n` for the field named `delta_n` when given; `frame_index` → `clock`, else `frame`. `u32`
    /// fields are rounded.
    pub fn params_bytes(&self, frame: u32, clock: Option<u32>, delta_n: Option<u32>) -> Vec<u8> {
        let mut bytes = vec![0u8; self.params_size];
        for f in &self.params {
            let x = match f.value {
                ParamValue::Steady { first, .. } if frame == 0 => first,
                ParamValue::Steady { value, .. } | ParamValue::Constant { value } => {
                    match delta_n {
                        Some(n) if f.name == manifest::DELTA_N => f64::from(n.max(1)),
                        _ => value,
                    }
                }
                ParamValue::FrameIndex => f64::from(clock.unwrap_or(frame)),
            };
            let le = match f.ty {
                ParamType::U32 => (x.round().max(0.0) as u32).to_le_bytes(),
                ParamType::F32 => (x as f32).to_le_bytes(),
            };
            bytes[f.offset..f.offset + 4].copy_from_slice(&le);
        }
        bytes
    }

    /// Whether a `delta_n` parameter exists for [`crate::FrameInputs::delta_n`] to set.
    pub fn has_delta_n(&self) -> bool {
        self.params
            .iter()
            .any(|f| f.name == manifest::DELTA_N && !matches!(f.value, ParamValue::FrameIndex))
    }
}

/// `dir/manifest.json`.
pub(crate) fn manifest_path(dir: &Path) -> PathBuf {
    dir.join("manifest.json")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plan with the params of every manifest reproj writes (16 bytes: Δn, clock, block, ε).
    fn plan() -> Plan {
        let field = |name: &str, offset, ty, value| ParamPlan {
            name: name.into(),
            offset,
            ty,
            value,
        };
        Plan {
            required_features: wgpu::Features::empty(),
            textures: Vec::new(),
            depth_texture: 0,
            samplers: Vec::new(),
            ping_pong: 2,
            params_size: 16,
            params: vec![
                field(
                    "delta_n",
                    0,
                    ParamType::U32,
                    ParamValue::Steady {
                        value: 8.0,
                        first: 1.0,
                    },
                ),
                field("clock", 4, ParamType::U32, ParamValue::FrameIndex),
                field(
                    "block",
                    8,
                    ParamType::U32,
                    ParamValue::Constant { value: 4.0 },
                ),
                field(
                    "depth_epsilon",
                    12,
                    ParamType::F32,
                    ParamValue::Constant { value: 0.01 },
                ),
            ],
            passes: Vec::new(),
            render_passes: Vec::new(),
            group: 1,
            binding_base: 0,
            depth_clear: 1.0,
            motion: false,
        }
    }

    fn words(bytes: &[u8]) -> [u32; 4] {
        std::array::from_fn(|i| u32::from_le_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap()))
    }

    #[test]
    fn params_are_first_on_frame_0_then_steady_or_the_given_delta_n() {
        let p = plan();
        assert!(p.has_delta_n());
        let eps = 0.01f32.to_bits();
        // Frame 0: nothing to reuse, Δn is `first` whatever is asked.
        assert_eq!(words(&p.params_bytes(0, None, None)), [1, 0, 4, eps]);
        assert_eq!(words(&p.params_bytes(0, None, Some(16))), [1, 0, 4, eps]);
        assert_eq!(words(&p.params_bytes(5, None, None)), [8, 5, 4, eps]);
        assert_eq!(words(&p.params_bytes(5, None, Some(16))), [16, 5, 4, eps]);
        // Δn is at least 1.
        assert_eq!(words(&p.params_bytes(5, None, Some(0))), [1, 5, 4, eps]);
        // The clock the host gives; frame 0 still refreshes everything.
        assert_eq!(words(&p.params_bytes(5, Some(12), None)), [8, 12, 4, eps]);
        assert_eq!(
            words(&p.params_bytes(0, Some(12), Some(16))),
            [1, 12, 4, eps]
        );
    }
}
