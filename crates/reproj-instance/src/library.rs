//! The lookup library's text: `lookup.wgsl` with its group, its input (the vertex stage's
//! previous clip position or the engine's motion vectors), its reconstruction filter and its
//! debug entry filled in, and the three-pass strategy's pass-1 entry. Parsed and imported by the
//! passes that fetch (lib.rs); the names it declares are the [`crate::contract`]'s.

use crate::contract;
use crate::{InstanceError, PassKind, Reconstruct};

/// The lookup library; `REPROJ_GROUP`, the bindings' numbers (`REPROJ_AT_NAME`, from
/// [`contract::AddedPlace`]), `REPROJ_RECONSTRUCT`, `// REPROJ_FILTERS`,
/// `// REPROJ_INPUT` and the depth's binding, texture and read are substituted. The debug entry [`classify_wgsl`] is not in what the
/// passes ship: a replay that counts hits with it appends it to pass 1.
const LOOKUP_LIBRARY: &str = include_str!("lookup.wgsl");
/// The three-pass strategy's pass-1 entry, appended to the library.
const REPROJECT_ENTRY: &str = include_str!("reproject.wgsl");

/// Where the entry points take a fragment's previous clip position from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PrevClip {
    /// An extra vertex output at this `@location` (`reprojection: vertex`).
    Location(u32),
    /// [`contract::MOTION_CLIP`] of the fragment position: the engine's motion vectors
    /// (`reprojection: motion_vectors`).
    Motion,
}

impl PrevClip {
    /// The vertex output's location, if the vertex stage delivers it.
    pub(crate) fn location(self) -> Option<u32> {
        match self {
            PrevClip::Location(l) => Some(l),
            PrevClip::Motion => None,
        }
    }
}

/// `ReprojInput` as the vertex stage delivers it: an entry-point input.
const VERTEX_INPUT: &str = "struct ReprojInput {
    @builtin(position) position: vec4<f32>,
    @location(REPROJ_PREV_CLIP) prev_clip: vec4<f32>,
};
";

/// `ReprojInput` made from the engine's motion vectors: a plain struct, filled by
/// `reproj_motion_clip`. The previous UV is the pixel's UV minus its motion; the depth is this
/// fragment's, so the hit test compares the previous depth there with this one (relative
/// tolerance `depth_epsilon`: a surface whose view depth changed more than that in a frame
/// misses, and is recomputed).
const MOTION_INPUT: &str = "struct ReprojInput {
    position: vec4<f32>,
    prev_clip: vec4<f32>,
};

// The engine's motion vectors: .xy = uv_current - uv_previous (texture UV, y down), one texel per
// frame pixel.
@group(REPROJ_GROUP) @binding(REPROJ_AT_MOTION) var reproj_motion: texture_2d<f32>;

// The previous clip position (w = 1) of the fragment at `position`.
fn reproj_motion_clip(position: vec4<f32>) -> vec4<f32> {
    let dims = textureDimensions(reproj_motion);
    let pixel = min(vec2<u32>(position.xy), dims - vec2<u32>(1u));
    let motion = textureLoad(reproj_motion, pixel, 0).xy;
    let uv = position.xy / vec2<f32>(dims) - motion;
    return vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, position.z, 1.0);
}
";

/// The debug entry point: the hit map (green hit, red miss, blue refresh), without discarding.
const CLASSIFY: &str = "@fragment
fn reproj_classify(REPROJ_ENTRY_INPUT) -> @location(0) vec4<f32> {
    REPROJ_MAKE_INPUT
    let r = reproj_lookup(in);
    var c = vec4<f32>(1.0, 0.0, 0.0, 1.0);
    if r.status == 0u {
        c = vec4<f32>(0.0, 1.0, 0.0, 1.0);
    } else if r.status == 2u {
        c = vec4<f32>(0.0, 0.0, 1.0, 1.0);
    }
    return c;
}
";

/// Catmull-Rom reconstruction for [`Reconstruct::CatmullRom`], inserted into the lookup library.
const CATMULL_ROM: &str = r#"// Catmull-Rom at `uv` in five filtered fetches: the 4×4 kernel's inner 2×2 as one bilinear fetch
// at the weighted offset, its four edge pairs as one fetch each, the corners (weights ≈ 0.01)
// dropped and the rest renormalized. Then clamped to the range of the 2×2 texels around `uv`
// (`p0`, `p1`, clamped to the edge, as the depth test reads them): a cubic overshoots at edges,
// and a value carried over many frames would ring further each time.
fn reproj_catmull_rom(uv: vec2<f32>, size: vec2<f32>, p0: vec2<i32>, p1: vec2<i32>) -> vec4<f32> {
    let pos = uv * size;
    let c1 = floor(pos - vec2<f32>(0.5)) + vec2<f32>(0.5);
    let f = pos - c1;
    let w0 = f * (vec2<f32>(-0.5) + f * (vec2<f32>(1.0) - 0.5 * f));
    let w1 = vec2<f32>(1.0) + f * f * (vec2<f32>(-2.5) + 1.5 * f);
    let w2 = f * (vec2<f32>(0.5) + f * (vec2<f32>(2.0) - 1.5 * f));
    let w3 = f * f * (vec2<f32>(-0.5) + 0.5 * f);
    let w12 = w1 + w2;
    let t0 = (c1 - vec2<f32>(1.0)) / size;
    let t3 = (c1 + vec2<f32>(2.0)) / size;
    let t12 = (c1 + w2 / w12) / size;
    let a = textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, vec2<f32>(t12.x, t0.y), 0.0) * (w12.x * w0.y);
    let b = textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, vec2<f32>(t0.x, t12.y), 0.0) * (w0.x * w12.y);
    let c = textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, t12, 0.0) * (w12.x * w12.y);
    let d = textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, vec2<f32>(t3.x, t12.y), 0.0) * (w3.x * w12.y);
    let e = textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, vec2<f32>(t12.x, t3.y), 0.0) * (w12.x * w3.y);
    let total = w12.x * w0.y + w0.x * w12.y + w12.x * w12.y + w3.x * w12.y + w12.x * w3.y;
    let v = (a + b + c + d + e) / total;
    let q00 = textureLoad(reproj_prev_payload, p0, 0);
    let q10 = textureLoad(reproj_prev_payload, vec2<i32>(p1.x, p0.y), 0);
    let q01 = textureLoad(reproj_prev_payload, vec2<i32>(p0.x, p1.y), 0);
    let q11 = textureLoad(reproj_prev_payload, p1, 0);
    return clamp(v, min(min(q00, q10), min(q01, q11)), max(max(q00, q10), max(q01, q11)));
}
"#;

/// The depth copy's binding: the previous frame's depth as a plain float texture (r32float, read
/// with textureLoad): a depth texture would be a shadow sampler in GLSL, which compares instead of
/// reading.
const DEPTH_COPY_BINDING: &str =
    "@group(REPROJ_GROUP) @binding(REPROJ_AT_PREV_DEPTH) var reproj_prev_depth: texture_2d<f32>;\n";

/// The frame size and the 2×2 texels of `REPROJ_DEPTH_TEXTURE` around uv, clamped to the edge
/// (what a gather with a clamp-to-edge sampler reads): the depth copy's four loads, the nearest
/// reconstruction and the Catmull-Rom clamp use them.
const FOOTPRINT: &str = "    let dims = vec2<i32>(textureDimensions(REPROJ_DEPTH_TEXTURE));
    let size = vec2<f32>(dims);
    let t = uv * size - vec2<f32>(0.5);
    let f = fract(t);
    let last = dims - vec2<i32>(1);
    let i = vec2<i32>(floor(t));
    let p0 = clamp(i, vec2<i32>(0), last);
    let p1 = clamp(i + vec2<i32>(1), vec2<i32>(0), last);
";

/// The previous depth from the depth copy: its 2×2 texels around uv blended bilinearly. Four
/// loads rather than one gather: GLSL ES 3.0 has no gather.
const DEPTH_COPY_READ: &str = "    let d00 = textureLoad(reproj_prev_depth, p0, 0).x;
    let d10 = textureLoad(reproj_prev_depth, vec2<i32>(p1.x, p0.y), 0).x;
    let d01 = textureLoad(reproj_prev_depth, vec2<i32>(p0.x, p1.y), 0).x;
    let d11 = textureLoad(reproj_prev_depth, p1, 0).x;
    let d = mix(mix(d00, d10, f.x), mix(d01, d11, f.x), f.y);
";

/// The previous depth from the payload's channel `REPROJ_DEPTH_CHANNEL`: the bilinear fetch
/// (the same blend as the depth copy's four loads) that the bilinear reconstruction reuses.
const PAYLOAD_DEPTH_READ: &str = "    let reproj_texel = textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, uv, 0.0);
    let d = reproj_texel[REPROJ_DEPTH_CHANNEL];
";

/// The lookup library's WGSL for this place of the added bindings, input and reconstruction; `depth_channel`: the
/// payload channel that holds the previous depth, `None` to read the depth copy.
pub(crate) fn library_text(
    place: contract::AddedPlace,
    prev_clip: PrevClip,
    reconstruct: Reconstruct,
    depth_channel: Option<u32>,
) -> String {
    let fetch = match (reconstruct, depth_channel) {
        (Reconstruct::Bilinear, Some(_)) => "reproj_texel",
        (Reconstruct::Bilinear, None) => {
            "textureSampleLevel(reproj_prev_payload, reproj_linear_sampler, uv, 0.0)"
        }
        (Reconstruct::Nearest, _) => {
            "textureLoad(reproj_prev_payload, vec2<i32>(min(uv * size, size - vec2<f32>(1.0))), 0)"
        }
        (Reconstruct::CatmullRom, _) => "reproj_catmull_rom(uv, size, p0, p1)",
    };
    let (binding, read) = match depth_channel {
        None => (
            DEPTH_COPY_BINDING,
            FOOTPRINT.replace("REPROJ_DEPTH_TEXTURE", contract::PREV_DEPTH) + DEPTH_COPY_READ,
        ),
        Some(c) => {
            // The bilinear reconstruction is the depth's own fetch: no footprint to compute.
            let footprint = match reconstruct {
                Reconstruct::Bilinear => String::new(),
                Reconstruct::Nearest | Reconstruct::CatmullRom => {
                    FOOTPRINT.replace("REPROJ_DEPTH_TEXTURE", contract::PREV_PAYLOAD)
                }
            };
            let depth = PAYLOAD_DEPTH_READ.replace("REPROJ_DEPTH_CHANNEL", &c.to_string());
            ("", footprint + &depth)
        }
    };
    let filters = match reconstruct {
        Reconstruct::CatmullRom => CATMULL_ROM,
        Reconstruct::Bilinear | Reconstruct::Nearest => "",
    };
    let input = match prev_clip {
        PrevClip::Location(location) => {
            VERTEX_INPUT.replace("REPROJ_PREV_CLIP", &location.to_string())
        }
        PrevClip::Motion => MOTION_INPUT.to_owned(),
    };
    let mut text = LOOKUP_LIBRARY
        .replace("// REPROJ_DEPTH_BINDING\n", binding)
        .replace("    // REPROJ_PREV_DEPTH\n", &read)
        .replace("// REPROJ_INPUT\n", &input)
        .replace("REPROJ_GROUP", &place.group.to_string());
    for (name, offset) in contract::ADDED_BINDINGS {
        let slot = format!(
            "REPROJ_AT_{}",
            name.trim_start_matches("reproj_").to_uppercase()
        );
        text = text.replace(&slot, &place.binding(offset).to_string());
    }
    text.replace("REPROJ_RECONSTRUCT", fetch)
        .replace("// REPROJ_FILTERS\n", filters)
}

/// An entry point's text with its input filled in: `in: ReprojInput` from the vertex stage, or
/// the fragment position, from which the motion vectors make `in`.
fn entry_input(text: &str, prev_clip: PrevClip) -> String {
    let (argument, make) = match prev_clip {
        PrevClip::Location(_) => ("in: ReprojInput", ""),
        PrevClip::Motion => (
            "@builtin(position) position: vec4<f32>",
            "let in = ReprojInput(position, reproj_motion_clip(position));",
        ),
    };
    let text = text.replace("REPROJ_ENTRY_INPUT", argument);
    if make.is_empty() {
        text.replace("    REPROJ_MAKE_INPUT\n", "")
    } else {
        text.replace("REPROJ_MAKE_INPUT", make)
    }
}

/// The debug entry point [`contract::CLASSIFY_ENTRY`] for a variant's pass 1 (the hit map: green
/// hit, red miss, blue refresh; an `rgba8unorm` target, no discard), WGSL to append to that pass's
/// module as written: it calls the pass's `reproj_lookup` with a `ReprojInput` made as the
/// variant's `reprojection` says. The passes reproj writes leave it out; `reproj render` appends
/// it to count the fused strategy's hits (no occlusion query can tell them apart) and for
/// `--classify`.
pub fn classify_wgsl(reprojection: crate::Reprojection) -> String {
    let prev_clip = match reprojection {
        // The location is that of the pass's own `ReprojInput`; this text does not name it.
        crate::Reprojection::Vertex => PrevClip::Location(0),
        crate::Reprojection::MotionVectors => PrevClip::Motion,
    };
    format!("\n{}", entry_input(CLASSIFY, prev_clip))
}

/// The three-pass strategy's pass 1: the library and its entry.
pub(crate) fn reproject_text(library: &str, prev_clip: PrevClip) -> String {
    format!("{library}{}", entry_input(REPROJECT_ENTRY, prev_clip))
}

/// Parse the library (or a pass made of it): a failure is a bug in reproj.
pub(crate) fn parse_library(text: &str, pass: PassKind) -> Result<naga::Module, InstanceError> {
    naga::front::wgsl::parse_str(text).map_err(|e| InstanceError::Internal {
        pass,
        what: e.emit_to_string(text),
    })
}
