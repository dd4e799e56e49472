//! The manifest of a variant: bind group layouts from the passes' globals, the frame plan (targets,
//! roles, attachments), the parameters and the vertex contract a host follows (`docs/PASSES.md`).

use super::*;

mod bindings;

use bindings::{bindings, type_name};

/// Texture roles of the [`FramePlan`].
pub const ROLE_CUR_PAYLOAD: &str = "cur_payload";
pub const ROLE_PREV_PAYLOAD: &str = "prev_payload";
pub const ROLE_CUR_DEPTH: &str = "cur_depth";
/// The depth attachment (one texture: the depth buffer is not kept from one frame to the next).
pub const ROLE_CUR_DEPTH_COPY: &str = "cur_depth_copy";
/// The previous frame's depth, as the passes that wrote its color copied it (r32float).
pub const ROLE_PREV_DEPTH_COPY: &str = "prev_depth_copy";
/// The frame target's attachment name.
pub const ATTACHMENT_FRAME: &str = "frame";
/// Sampler names.
pub const SAMPLER_LINEAR: &str = "linear";

/// The WGSL of the vertex contract's helper.
pub(crate) const VERTEX_CONTRACT_WGSL: &str = "\
// reproj: the vertex's clip-space position in the previous frame. Write the result to the vertex
// output at @location(prev_clip_location); the clip position itself must be @invariant.
fn reproj_prev_clip(prev_view_proj: mat4x4<f32>, prev_model: mat4x4<f32>, position: vec3<f32>) -> vec4<f32> {
    return prev_view_proj * (prev_model * vec4<f32>(position, 1.0));
}
";

/// What a variant's manifest is built from: the shader, its normalized function, the cached
/// nodes, the options, and what the instancer decided (cache format, added group, the vertex
/// output location of the previous clip position, the finished passes).
pub(crate) struct ManifestInput<'a> {
    pub shader: &'a Shader,
    pub norm: &'a Normalized,
    pub nodes: &'a [&'a Node],
    pub opts: &'a InstanceOptions,
    pub cache_format: CacheFormat,
    /// The payload channel holding the depth, `None` for the depth copy.
    pub depth_channel: Option<u32>,
    /// Where the added bindings are.
    pub place: contract::AddedPlace,
    /// `None` with the engine's motion vectors.
    pub prev_clip_location: Option<u32>,
    pub passes: &'a [PassModule],
}

/// The manifest of a variant: the nodes of its payload, its passes' targets and bindings, the
/// vertex contract, the params, the textures and the ping-pong plan, and the notes for a host.
pub(crate) fn build_manifest(input: &ManifestInput) -> Manifest {
    let ManifestInput {
        shader,
        norm,
        nodes,
        opts,
        cache_format,
        depth_channel,
        place,
        prev_clip_location,
        passes,
    } = *input;
    let mut notes = host_notes(opts, prev_clip_location, depth_channel, place);
    if place.shared() {
        notes.push(format!(
            "The shader uses every bind group, so the bindings reproj adds join its group {} from binding {} on (`binding_base`): bind the shader's own resources of that group and the added ones in one bind group.",
            place.group, place.base
        ));
    }
    let infos = node_infos(nodes);
    if nodes.len() > 1 {
        notes.push(format!(
            "The payload holds {} nodes, each at its offset: {}.",
            nodes.len(),
            infos
                .iter()
                .map(|i| format!("node {} at {}", i.id, i.offset))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Manifest {
        schema: "reproj.manifest".into(),
        version: MANIFEST_VERSION,
        shader: shader.path.file_name().map_or_else(
            || shader.path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        ),
        entry: norm.entry.clone(),
        shader_ir_hash: Some(crate::manifest::ir_hash(shader)),
        node: infos[0].clone(),
        also: infos[1..].to_vec(),
        strategy: opts.strategy,
        reconstruct: opts.reconstruct,
        cache_format,
        depth_channel,
        required_features: if !cache_format.is_half() && opts.reconstruct.filters() {
            vec!["float32-filterable".into()]
        } else {
            Vec::new()
        },
        group: place.group,
        binding_base: place.base,
        conventions: Conventions::default(),
        reprojection: opts.reprojection,
        vertex: vertex_contract(prev_clip_location),
        params: params(opts),
        textures: textures(cache_format, depth_channel),
        bytes_per_pixel: Some(bytes_per_pixel(cache_format, depth_channel)),
        samplers: vec![SamplerDesc {
            name: SAMPLER_LINEAR.into(),
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mipmap_filter: Filter::Nearest,
            address_mode: "clamp-to-edge".into(),
        }],
        frames: FramePlan {
            ping_pong: vec![
                ping_pong("0", "1", depth_channel),
                ping_pong("1", "0", depth_channel),
            ],
        },
        passes: passes
            .iter()
            .map(|p| pass(p, opts, cache_format, depth_channel, place))
            .collect(),
        notes,
        immediates: immediates(passes),
        languages: Vec::new(),
    }
}

/// The shader's push constants, as the first pass that reads them declares them.
fn immediates(passes: &[PassModule]) -> Option<crate::manifest::Immediates> {
    passes.iter().find_map(|p| {
        let var = crate::backends::immediates::global(&p.module)?;
        let global = &p.module.global_variables[var];
        Some(crate::manifest::Immediates {
            name: global.name.clone().unwrap_or_default(),
            ty: type_name(&p.module, global.ty),
            size: crate::backends::immediates::size(&p.module, var),
        })
    })
}

/// What a host must know beyond the data: how the passes draw, the vertex stage's extra output,
/// the depth copy, the ping-pong, the first frame, the debug entry, the frame target's load.
fn host_notes(
    opts: &InstanceOptions,
    prev_clip_location: Option<u32>,
    depth_channel: Option<u32>,
    place: contract::AddedPlace,
) -> Vec<String> {
    let draw = match opts.strategy {
        Strategy::ThreePass => "All three passes draw",
        Strategy::TwoPass => "Both passes draw",
        Strategy::Fused => "The pass draws",
    };
    let previous = match prev_clip_location {
        Some(location) => format!(
            "The vertex stage also writes @location({location}) prev_clip: vec4<f32> = previous frame's view_proj * previous model * position (the manifest's vertex.wgsl)."
        ),
        None => format!(
            "The passes that look up the cache read the engine's motion vectors (binding {} of the group, resource \"motion\"): .xy = uv_current - uv_previous in texture UV (0 to 1, y down), one texel per frame pixel, written before the first pass. The vertex stage writes nothing extra.",
            place.binding(contract::MOTION_BINDING)
        ),
    };
    let depth = match depth_channel {
        None => "The passes that write the frame color also write the fragment's depth to the \"current depth copy\" target (r32float, cleared to 1.0): the depth the next frame's lookup reads. The depth buffer itself is not read, nor kept from one frame to the next.".to_string(),
        Some(c) => format!("The passes that write the cache also write the fragment's depth to its channel {c} (cleared to 1.0 there): the depth the next frame's lookup reads, in the same filtered fetch as the payload. The depth buffer itself is not read, nor kept from one frame to the next."),
    };
    let mut notes = vec![
        format!("{draw} the scene's geometry with the same vertex stage, whose clip position is @invariant."),
        previous,
        depth,
        "Frame i binds the textures of frames.ping_pong[i % 2]: what it writes as cur_* it reads as prev_* next frame.".into(),
        "On the first frame, or after a cut, set delta_n = 1: every pixel is recomputed.".into(),
    ];
    if opts.frame_load == FrameLoad::Load {
        notes.push("The frame target is loaded, not cleared: clear it (or draw what lies behind) before the first pass.".into());
    }
    if opts.depth_load == DepthLoad::Load {
        notes.push("The first pass keeps what the depth target holds: clear it and draw the engine's opaque geometry into it before the first pass; the variant's fragments behind it are neither drawn nor cached.".into());
    }
    notes
}

/// The payload's nodes in order, each at the component offset after the ones before it.
fn node_infos(nodes: &[&Node]) -> Vec<NodeInfo> {
    let mut offset = 0;
    nodes
        .iter()
        .map(|node| {
            let info = NodeInfo {
                id: node_id(node),
                text: node.text.clone(),
                line: node.line,
                col: node.col,
                ty: node.ty.clone(),
                components: node.components,
                offset,
            };
            offset += node.components;
            info
        })
        .collect()
}

/// One pass of the manifest: its file, entry point, bindings, and the targets and depth state of
/// its kind.
fn pass(
    p: &PassModule,
    opts: &InstanceOptions,
    cache_format: CacheFormat,
    depth_channel: Option<u32>,
    place: contract::AddedPlace,
) -> Pass {
    let (colors, depth) = pass_targets(p, opts, cache_format, depth_channel);
    Pass {
        kind: p.kind,
        file: pass_file(p.kind).into(),
        entry: p
            .module
            .entry_points
            .iter()
            .find(|e| e.name != contract::CLASSIFY_ENTRY)
            .map_or_else(String::new, |e| e.name.clone()),
        bindings: bindings(&p.module, place, opts.reconstruct),
        colors,
        depth,
    }
}

/// The color targets and the depth state of a pass, by its kind: which pass clears the cache,
/// the frame, the depth and its copy, and which load what an earlier pass wrote. With the depth
/// in the payload's `depth_channel` there is no depth copy target, and the cache clears to the far
/// plane there.
fn pass_targets(
    p: &PassModule,
    opts: &InstanceOptions,
    cache_format: CacheFormat,
    depth_channel: Option<u32>,
) -> (Vec<ColorTarget>, DepthState) {
    let clear_cache = || LoadOp::Clear {
        value: Some(payload_clear(depth_channel).to_vec()),
    };
    let cache = |location: u32, load: LoadOp| ColorTarget {
        location,
        attachment: ROLE_CUR_PAYLOAD.into(),
        format: Some(cache_format.name().into()),
        load,
        store: true,
        blend: None,
    };
    let frame_first = || match opts.frame_load {
        FrameLoad::Clear => LoadOp::Clear { value: None },
        FrameLoad::Load => LoadOp::Load,
    };
    let frame = |load: LoadOp| ColorTarget {
        location: 0,
        attachment: ATTACHMENT_FRAME.into(),
        format: None,
        load,
        store: true,
        blend: None,
    };
    let clear_depth = || match opts.depth_load {
        DepthLoad::Clear => LoadOp::Clear {
            value: Some(vec![1.0]),
        },
        DepthLoad::Load => LoadOp::Load,
    };
    let depth = |compare: &str, write: bool, load: LoadOp| DepthState {
        attachment: ROLE_CUR_DEPTH.into(),
        format: "depth32float".into(),
        compare: compare.into(),
        write,
        load,
        store: true,
        stencil: None,
    };
    let depth_copy = |location: u32, load: LoadOp| ColorTarget {
        location,
        attachment: ROLE_CUR_DEPTH_COPY.into(),
        format: Some("r32float".into()),
        load,
        store: true,
        blend: None,
    };
    let clear_depth_copy = || LoadOp::Clear {
        value: Some(vec![1.0, 0.0, 0.0, 0.0]),
    };
    let cache_at = output_location(p, strategy::CACHE_MEMBER);
    let depth_at = output_location(p, strategy::DEPTH_MEMBER);
    match p.kind {
        PassKind::Reproject => (
            vec![cache(0, clear_cache())],
            depth("less", true, clear_depth()),
        ),
        PassKind::Recompute => (
            vec![cache(0, LoadOp::Load)],
            depth("less", true, LoadOp::Load),
        ),
        PassKind::Shade => (
            vec![
                frame(frame_first()),
                depth_copy(depth_at, clear_depth_copy()),
            ],
            depth("equal", false, LoadOp::Load),
        ),
        PassKind::Fused | PassKind::ShadeHits => (
            [frame(frame_first()), cache(cache_at, clear_cache())]
                .into_iter()
                .chain(
                    depth_channel
                        .is_none()
                        .then(|| depth_copy(depth_at, clear_depth_copy())),
                )
                .collect(),
            depth("less", true, clear_depth()),
        ),
        PassKind::ShadeMisses => (
            [frame(LoadOp::Load), cache(cache_at, LoadOp::Load)]
                .into_iter()
                .chain(
                    depth_channel
                        .is_none()
                        .then(|| depth_copy(depth_at, LoadOp::Load)),
                )
                .collect(),
            depth("less", true, LoadOp::Load),
        ),
    }
}

/// What the cache is cleared to: 0, and the far plane (1.0) in the depth channel if it has one,
/// so that nothing matches it as the previous frame's surface.
pub fn payload_clear(depth_channel: Option<u32>) -> [f64; 4] {
    let mut v = [0.0; 4];
    if let Some(c) = depth_channel {
        v[c as usize] = 1.0;
    }
    v
}

/// The location of the pass's output struct member `name` (the cache and the depth copy follow
/// the shader's outputs); 1 where there is none.
fn output_location(p: &PassModule, name: &str) -> u32 {
    let ep = &p.module.entry_points[0];
    let ty = ep
        .function
        .result
        .as_ref()
        .map(|r| &p.module.types[r.ty].inner);
    match ty {
        Some(naga::TypeInner::Struct { members, .. }) => members
            .iter()
            .find(|m| m.name.as_deref() == Some(name))
            .and_then(|m| match m.binding {
                Some(naga::Binding::Location { location, .. }) => Some(location),
                _ => None,
            })
            .unwrap_or(1),
        _ => 1,
    }
}

/// The vertex stage's contract: an @invariant position and the previous clip position at
/// `prev_clip_location`, from the inputs the helper [`VERTEX_CONTRACT_WGSL`] takes; with the
/// engine's motion vectors (`None`), the position alone.
fn vertex_contract(prev_clip_location: Option<u32>) -> VertexContract {
    if prev_clip_location.is_none() {
        return VertexContract {
            invariant_position: true,
            prev_clip_location: None,
            inputs: Vec::new(),
            wgsl: String::new(),
        };
    }
    VertexContract {
        invariant_position: true,
        prev_clip_location,
        inputs: vec![
            VertexInput {
                name: "prev_view_proj".into(),
                ty: "mat4x4<f32>".into(),
                meaning:
                    "the previous frame's view-projection matrix (this frame's on the first frame)"
                        .into(),
            },
            VertexInput {
                name: "prev_model".into(),
                ty: "mat4x4<f32>".into(),
                meaning: "the object's model matrix in the previous frame".into(),
            },
            VertexInput {
                name: "position".into(),
                ty: "vec3<f32>".into(),
                meaning: "the vertex's object-space position".into(),
            },
        ],
        wgsl: VERTEX_CONTRACT_WGSL.into(),
    }
}

/// The params uniform's layout, its fields at the contract's [`ReprojParams`] offsets, and their
/// values (Δn steady after a first frame of 1, the frame index, the constants).
fn params(opts: &InstanceOptions) -> Params {
    let field = |name: &str, offset: usize, ty: ScalarType, value: ParamValue| ParamField {
        name: name.into(),
        offset: offset as u32,
        ty,
        value,
    };
    Params {
        delta_n: opts.delta_n,
        block: opts.block,
        depth_epsilon: opts.depth_epsilon,
        size: contract::PARAMS_SIZE,
        fields: vec![
            field(
                "delta_n",
                offset_of!(ReprojParams, delta_n),
                ScalarType::U32,
                ParamValue::Steady {
                    value: f64::from(opts.delta_n),
                    first: 1.0,
                },
            ),
            field(
                "clock",
                offset_of!(ReprojParams, clock),
                ScalarType::U32,
                ParamValue::FrameIndex,
            ),
            field(
                "block",
                offset_of!(ReprojParams, block),
                ScalarType::U32,
                ParamValue::Constant {
                    value: f64::from(opts.block),
                },
            ),
            field(
                "depth_epsilon",
                offset_of!(ReprojParams, depth_epsilon),
                ScalarType::F32,
                ParamValue::Constant {
                    // The f32's shortest decimal (0.01, not 0.009999999776482582).
                    value: opts.depth_epsilon.to_string().parse().unwrap_or_default(),
                },
            ),
        ],
        // `emit` sets it from the error model at each motion band.
        schedule: Vec::new(),
    }
}

/// The textures a host allocates: two payloads and two depth copies (ping-pong; no depth copies
/// where the payload holds the depth) and the depth attachment, all frame-sized.
fn textures(cache_format: CacheFormat, depth_channel: Option<u32>) -> Vec<TextureDesc> {
    let texture = |name: &str, format: &str| TextureDesc {
        name: name.into(),
        format: format.into(),
        size: TextureSize::Frame,
        usage: vec![TextureUsage::RenderAttachment, TextureUsage::TextureBinding],
        mip_levels: 1,
        sample_count: 1,
    };
    let mut t = vec![
        texture("payload_0", cache_format.name()),
        texture("payload_1", cache_format.name()),
    ];
    if depth_channel.is_none() {
        t.push(texture("depth_copy_0", "r32float"));
        t.push(texture("depth_copy_1", "r32float"));
    }
    t.push(TextureDesc {
        usage: vec![TextureUsage::RenderAttachment],
        ..texture("depth", "depth32float")
    });
    t
}

/// Bytes per frame pixel of [`textures`] apart from the depth attachment: two payloads and two
/// depth copies (none where the payload holds the depth).
fn bytes_per_pixel(cache_format: CacheFormat, depth_channel: Option<u32>) -> u32 {
    let payload = cache_format.channels() * if cache_format.is_half() { 2 } else { 4 };
    let depth_copy = if depth_channel.is_none() { 4 } else { 0 };
    2 * payload + 2 * depth_copy
}

/// One frame's roles: the current payload and depth copy are textures `a`, the previous `b` (no
/// depth copy roles where the payload holds the depth).
fn ping_pong(
    a: &str,
    b: &str,
    depth_channel: Option<u32>,
) -> std::collections::BTreeMap<String, String> {
    let mut roles = vec![
        (ROLE_CUR_PAYLOAD, format!("payload_{a}")),
        (ROLE_PREV_PAYLOAD, format!("payload_{b}")),
    ];
    if depth_channel.is_none() {
        roles.push((ROLE_CUR_DEPTH_COPY, format!("depth_copy_{a}")));
        roles.push((ROLE_PREV_DEPTH_COPY, format!("depth_copy_{b}")));
    }
    roles.push((ROLE_CUR_DEPTH, "depth".to_string()));
    roles.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
}
