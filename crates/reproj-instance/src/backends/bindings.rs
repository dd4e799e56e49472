//! Each language's bindings, explicit and listed. One table per language over the resources of
//! every pass (so a resource has the same slot in each pass), handed to naga's writer (GLSL's and
//! HLSL's `binding_map`, HLSL's sampler index buffers, MSL's `per_entry_point_map`) and written
//! into the manifest ([`LanguageOutput`]), so a host binds by the table instead of guessing what
//! naga chose (`layout(binding)` missing in GLSL, `[[user(fake0)]]` in MSL).

use crate::backends::immediates::{self, Rule};
use crate::manifest::{LanguageBinding, LanguageImmediates, LanguageOutput};
use crate::{PassModule, backends::OutputLang, backends::pass_file_in};

/// The HLSL register space of each bind group's sampler index buffer (naga's sampler heap model,
/// as wgpu's DX12 backend binds it): `register(tG, space255)` for group G.
pub const SAMPLER_INDEX_SPACE: u8 = 255;

/// What kind of resource a global is, as the languages tell them apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Uniform,
    Storage { writable: bool },
    Texture,
    StorageTexture,
    Sampler,
}

impl Kind {
    /// The manifest's word for it.
    fn name(self) -> &'static str {
        match self {
            Kind::Uniform => "uniform",
            Kind::Storage { writable: false } => "read-only-storage",
            Kind::Storage { writable: true } => "storage",
            Kind::Texture => "texture",
            Kind::StorageTexture => "storage-texture",
            Kind::Sampler => "sampler",
        }
    }
}

/// One resource of the passes.
#[derive(Debug, Clone)]
struct Resource {
    group: u32,
    binding: u32,
    name: String,
    kind: Kind,
    /// Elements of a binding array (1 otherwise).
    count: u32,
}

/// Every bound global of `passes`, once, by (group, binding); the first pass's name.
fn resources(passes: &[PassModule]) -> Vec<Resource> {
    let mut out: Vec<Resource> = Vec::new();
    for p in passes {
        for (_, var) in p.module.global_variables.iter() {
            let Some(rb) = &var.binding else { continue };
            if out
                .iter()
                .any(|r| (r.group, r.binding) == (rb.group, rb.binding))
            {
                continue;
            }
            // A binding array binds its elements' kind, in as many consecutive MSL slots.
            let (ty, count) = match p.module.types[var.ty].inner {
                naga::TypeInner::BindingArray { base, size } => (
                    base,
                    match size {
                        naga::ArraySize::Constant(n) => n.get(),
                        _ => 1,
                    },
                ),
                _ => (var.ty, 1),
            };
            let kind = match (&p.module.types[ty].inner, var.space) {
                (naga::TypeInner::Sampler { .. }, _) => Kind::Sampler,
                (
                    naga::TypeInner::Image {
                        class: naga::ImageClass::Storage { .. },
                        ..
                    },
                    _,
                ) => Kind::StorageTexture,
                (naga::TypeInner::Image { .. }, _) => Kind::Texture,
                (_, naga::AddressSpace::Storage { access }) => Kind::Storage {
                    writable: access.contains(naga::StorageAccess::STORE),
                },
                _ => Kind::Uniform,
            };
            out.push(Resource {
                group: rb.group,
                binding: rb.binding,
                name: var.name.clone().unwrap_or_default(),
                kind,
                count,
            });
        }
    }
    out.sort_by_key(|r| (r.group, r.binding));
    out
}

/// The table of `lang` for `passes`: the files and every resource's slot.
pub fn language_output(passes: &[PassModule], lang: OutputLang) -> LanguageOutput {
    let resources = resources(passes);
    let mut bindings = Vec::new();
    // Running counters: GLSL's one binding space (Vulkan GLSL's set 0), MSL's three.
    let (mut glsl, mut msl_buffer, mut msl_texture, mut msl_sampler) = (0u32, 0u32, 0u32, 0u32);
    let next = |n: &mut u32, count: u32| {
        *n += count;
        *n - count
    };
    for r in &resources {
        let (slot, space, target) = match lang {
            // naga's GLSL writer combines each texture with the sampler it is sampled with into
            // one `sampler2D` at the texture's binding: samplers have no binding of their own.
            OutputLang::Glsl if r.kind == Kind::Sampler => continue,
            OutputLang::Glsl => {
                let n = next(&mut glsl, r.count);
                (n, None, format!("layout(binding = {n})"))
            }
            OutputLang::Hlsl => match r.kind {
                Kind::Sampler => (
                    r.binding,
                    None,
                    format!(
                        "nagaGroup{}SamplerIndexArray[{}] (register(t{}, space{SAMPLER_INDEX_SPACE}))",
                        r.group, r.binding, r.group
                    ),
                ),
                kind => {
                    let letter = match kind {
                        Kind::Uniform => 'b',
                        Kind::Storage { writable: false } | Kind::Texture => 't',
                        _ => 'u',
                    };
                    // As naga writes it: space 0 is left unsaid.
                    let space = match r.group {
                        0 => String::new(),
                        g => format!(", space{g}"),
                    };
                    (
                        r.binding,
                        Some(r.group),
                        format!("register({letter}{}{space})", r.binding),
                    )
                }
            },
            OutputLang::Msl => {
                let (counter, attr) = match r.kind {
                    Kind::Uniform | Kind::Storage { .. } => (&mut msl_buffer, "buffer"),
                    Kind::Texture | Kind::StorageTexture => (&mut msl_texture, "texture"),
                    Kind::Sampler => (&mut msl_sampler, "sampler"),
                };
                let n = next(counter, r.count);
                (n, None, format!("[[{attr}({n})]]"))
            }
            OutputLang::SpirV => (
                r.binding,
                Some(r.group),
                format!("DescriptorSet {}, Binding {}", r.group, r.binding),
            ),
        };
        bindings.push(LanguageBinding {
            group: r.group,
            binding: r.binding,
            name: r.name.clone(),
            kind: r.kind.name().into(),
            slot,
            space,
            target,
        });
    }
    let push = language_immediates(passes, lang, &mut glsl, msl_buffer);
    let notes = match lang {
        OutputLang::Glsl => vec![
            "GLSL 4.50 for Vulkan (glslangValidator -V) and OpenGL: every resource in one binding space (Vulkan descriptor set 0); each texture is combined with the sampler it is sampled with into one sampler at the texture's binding, so samplers are not listed. Push constants: a `layout(push_constant)` block where `VULKAN` is defined (glslang -V, shaderc), else a std140 uniform block at the binding `immediates.slot` gives (in OpenGL's uniform-buffer binding points), or an `#error` where std140 cannot hold their bytes (no `slot`).".into(),
        ],
        OutputLang::Hlsl => vec![
            format!("Shader model 5.1. Buffers and textures at register(<b|t|u>binding, space<group>). Samplers through naga's sampler heap (as wgpu's DX12 backend): SamplerState heap at register(s0, space0), SamplerComparisonState heap at register(s0, space1), and per group G a StructuredBuffer<uint> of heap indices at register(tG, space{SAMPLER_INDEX_SPACE}), read at the sampler's slot. Push constants (a GLSL input's) at register(b0, space{}).", super::IMMEDIATES_SPACE),
        ],
        OutputLang::Msl => vec![format!(
            "MSL 2.1: buffers, textures and samplers numbered apart, in the order of (group, binding); buffer {msl_buffer} holds push constants and buffer {} the sizes of runtime-sized arrays, where a pass has them.",
            msl_buffer + 1
        )],
        OutputLang::SpirV => vec![
            "SPIR-V 1.x: descriptor set = group, binding = binding (as WebGPU's).".into(),
        ],
    };
    LanguageOutput {
        lang: lang.key().into(),
        files: passes.iter().map(|p| pass_file_in(p, lang)).collect(),
        bindings,
        notes,
        immediates: push,
    }
}

/// Where `lang` reads the push constants of `passes`, if they have any: GLSL's OpenGL block takes
/// the binding after the resources' (`glsl`, the running counter) where std140 holds the bytes;
/// MSL's the buffer after the resources' (`msl_buffer`, as naga's `immediates_buffer`).
fn language_immediates(
    passes: &[PassModule],
    lang: OutputLang,
    glsl: &mut u32,
    msl_buffer: u32,
) -> Option<LanguageImmediates> {
    let (module, var) = passes
        .iter()
        .find_map(|p| Some((&p.module, immediates::global(&p.module)?)))?;
    Some(match lang {
        OutputLang::Glsl => {
            let gl = immediates::block_agrees(module, var, Rule::Std140).then(|| {
                *glsl += 1;
                *glsl - 1
            });
            LanguageImmediates {
                slot: gl,
                space: None,
                target: match gl {
                    Some(n) => format!(
                        "layout(push_constant) uniform (Vulkan); layout(std140, binding = {n}) uniform (OpenGL)"
                    ),
                    None => "layout(push_constant) uniform (Vulkan; no OpenGL form)".into(),
                },
            }
        }
        OutputLang::Hlsl => LanguageImmediates {
            slot: Some(0),
            space: Some(u32::from(super::IMMEDIATES_SPACE)),
            target: format!("register(b0, space{})", super::IMMEDIATES_SPACE),
        },
        OutputLang::Msl => LanguageImmediates {
            slot: Some(msl_buffer),
            space: None,
            target: format!("[[buffer({msl_buffer})]]"),
        },
        OutputLang::SpirV => LanguageImmediates {
            slot: None,
            space: None,
            target: "PushConstant".into(),
        },
    })
}

/// naga's GLSL binding map for `table`.
pub(super) fn glsl_map(table: &LanguageOutput) -> naga::back::glsl::BindingMap {
    let push = table.immediates.as_ref().and_then(|i| i.slot);
    table
        .bindings
        .iter()
        .map(|b| (resource_binding(b), b.slot as u8))
        .chain(push.map(|n| (naga::back::glsl::IMMEDIATES_BINDING, n as u8)))
        .collect()
}

/// naga's HLSL binding map and sampler index buffers for `table`.
pub(super) fn hlsl_maps(
    table: &LanguageOutput,
) -> (
    naga::back::hlsl::BindingMap,
    naga::back::hlsl::SamplerIndexBufferBindingMap,
) {
    use naga::back::hlsl::{BindTarget, SamplerIndexBufferKey};
    let target = |space: u8, register: u32| BindTarget {
        space,
        register,
        ..Default::default()
    };
    let mut map = naga::back::hlsl::BindingMap::new();
    let mut samplers = naga::back::hlsl::SamplerIndexBufferBindingMap::new();
    for b in &table.bindings {
        match b.space {
            Some(space) => {
                map.insert(resource_binding(b), target(space as u8, b.slot));
            }
            None => {
                map.insert(resource_binding(b), target(0, b.slot));
                samplers.insert(
                    SamplerIndexBufferKey { group: b.group },
                    target(SAMPLER_INDEX_SPACE, b.group),
                );
            }
        }
    }
    (map, samplers)
}

/// naga's MSL resources of every entry point of `module` for `table`.
pub(super) fn msl_map(
    table: &LanguageOutput,
    module: &naga::Module,
) -> naga::back::msl::EntryPointResourceMap {
    use naga::back::msl::{BindSamplerTarget, BindTarget, EntryPointResources};
    let mut buffers = 0u8;
    let mut resources = naga::back::msl::BindingMap::new();
    for b in &table.bindings {
        let slot = b.slot as u8;
        let mut t = BindTarget::default();
        match b.kind.as_str() {
            "sampler" => t.sampler = Some(BindSamplerTarget::Resource(slot)),
            "texture" | "storage-texture" => {
                t.texture = Some(slot);
                t.mutable = b.kind == "storage-texture";
            }
            kind => {
                t.buffer = Some(slot);
                t.mutable = kind == "storage";
                buffers = buffers.max(slot + 1);
            }
        }
        resources.insert(resource_binding(b), t);
    }
    module
        .entry_points
        .iter()
        .map(|e| {
            (
                e.name.clone(),
                EntryPointResources {
                    resources: resources.clone(),
                    immediates_buffer: Some(buffers),
                    sizes_buffer: Some(buffers + 1),
                },
            )
        })
        .collect()
}

fn resource_binding(b: &LanguageBinding) -> naga::ResourceBinding {
    naga::ResourceBinding {
        group: b.group,
        binding: b.binding,
    }
}
