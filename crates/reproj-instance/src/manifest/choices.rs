//! The choices a variant is made with, as the manifest names them: the cache format, where the
//! previous position comes from, the pass layout, the reconstruction filter, and which pass is
//! which.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Cache payload texel format (WebGPU names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema, Default)]
#[serde(rename_all = "lowercase")]
pub enum CacheFormat {
    /// Exact: 32-bit float per channel (default for 3- and 4-float payloads).
    #[default]
    Rgba32float,
    /// Two exact floats.
    Rg32float,
    /// One exact float.
    R32float,
    /// The paper's 16 bits per channel.
    Rgba16float,
    Rg16float,
    R16float,
}

impl CacheFormat {
    /// The narrowest format of the given precision that holds `components` floats (there is no
    /// renderable three-channel format, so 3 takes 4).
    pub fn narrowest(components: u32, half: bool) -> CacheFormat {
        match (components, half) {
            (1, false) => CacheFormat::R32float,
            (2, false) => CacheFormat::Rg32float,
            (_, false) => CacheFormat::Rgba32float,
            (1, true) => CacheFormat::R16float,
            (2, true) => CacheFormat::Rg16float,
            (_, true) => CacheFormat::Rgba16float,
        }
    }

    /// Floats per texel.
    pub fn channels(self) -> u32 {
        match self {
            CacheFormat::R32float | CacheFormat::R16float => 1,
            CacheFormat::Rg32float | CacheFormat::Rg16float => 2,
            CacheFormat::Rgba32float | CacheFormat::Rgba16float => 4,
        }
    }

    /// 16-bit floats (filterable everywhere; 32-bit floats need `float32-filterable`).
    pub fn is_half(self) -> bool {
        matches!(
            self,
            CacheFormat::R16float | CacheFormat::Rg16float | CacheFormat::Rgba16float
        )
    }

    /// The WebGPU format name.
    pub fn name(self) -> &'static str {
        match self {
            CacheFormat::Rgba32float => "rgba32float",
            CacheFormat::Rg32float => "rg32float",
            CacheFormat::R32float => "r32float",
            CacheFormat::Rgba16float => "rgba16float",
            CacheFormat::Rg16float => "rg16float",
            CacheFormat::R16float => "r16float",
        }
    }
}

/// Where the lookup finds a fragment's surface point in the previous frame (`docs/PASSES.md`,
/// "Reprojection").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema, Default)]
#[serde(rename_all = "snake_case")]
pub enum Reprojection {
    /// The host's vertex stage writes the vertex's previous clip position
    /// (`vertex.prev_clip_location`): exact, and the hit test compares the previous depth with
    /// the point's own depth in the previous frame.
    #[default]
    Vertex,
    /// The engine's motion-vector texture, bound as `reproj_motion` (resource `motion`): `.xy` is
    /// `uv_current - uv_previous` in texture UV units (0 to 1 across the frame, origin top left,
    /// y down: Bevy's and Unity's convention), one texel per frame pixel, read at the fragment's
    /// pixel with `textureLoad`. The vertex stage writes no previous clip position; the hit test
    /// compares the previous depth at the reprojected position with this fragment's depth.
    MotionVectors,
}

impl Reprojection {
    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Reprojection::Vertex => "vertex",
            Reprojection::MotionVectors => "motion_vectors",
        }
    }

    pub fn is_vertex(&self) -> bool {
        *self == Reprojection::Vertex
    }
}

/// How a variant's passes are laid out (`docs/PASSES.md`).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    JsonSchema,
    Default,
)]
pub enum Strategy {
    /// The paper's three passes: reproject, recompute (through the depth test), shade. One color
    /// target per pass, no branch.
    #[default]
    #[serde(rename = "3pass")]
    ThreePass,
    /// Two passes: reproject and shade the hits (discarding misses), then the whole shader where
    /// pass 1 left the pixel open (through the depth test). Two color targets, no branch.
    #[serde(rename = "2pass")]
    TwoPass,
    /// One pass: reproject; on a miss or refresh compute the node inline (a branch); shade; write
    /// color and cache (two color targets).
    #[serde(rename = "fused")]
    Fused,
}

impl Strategy {
    pub const ALL: [Strategy; 3] = [Strategy::ThreePass, Strategy::TwoPass, Strategy::Fused];

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::ThreePass => "3pass",
            Strategy::TwoPass => "2pass",
            Strategy::Fused => "fused",
        }
    }

    /// Default refresh block size k: the fused pass branches per pixel, so its refresh blocks are
    /// as large as a GPU's execution group (8×8 = 64 lanes) to keep the branch coherent.
    pub fn default_block(self) -> u32 {
        match self {
            Strategy::Fused => 8,
            _ => 4,
        }
    }
}

impl std::fmt::Display for Strategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Strategy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Strategy::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown strategy `{s}` (expected 3pass, 2pass or fused)"))
    }
}

/// How pass 1 reconstructs the previous payload at the reprojected position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema, Default)]
#[serde(rename_all = "lowercase")]
pub enum Reconstruct {
    /// One filtered fetch (linear sampler): the paper's bilinear reconstruction.
    #[default]
    Bilinear,
    /// One `textureLoad` of the nearest texel: cheaper, needs no filtering, blockier.
    Nearest,
    /// Catmull-Rom (bicubic) in five filtered fetches (the 4×4 kernel's corners dropped), clamped
    /// to the range of the 2×2 nearest texels (four loads) so it cannot ring: sharper than
    /// bilinear, so a value carried over many frames blurs less (docs/PASSES.md).
    #[serde(rename = "catmull-rom")]
    CatmullRom,
}

impl Reconstruct {
    /// Whether the payload is read through the linear sampler (a 32-bit float cache then needs
    /// the `float32-filterable` feature).
    pub fn filters(self) -> bool {
        matches!(self, Reconstruct::Bilinear | Reconstruct::CatmullRom)
    }

    /// The reconstruction [`name`](Self::name) writes, or `None`.
    pub fn from_name(name: &str) -> Option<Reconstruct> {
        [
            Reconstruct::Bilinear,
            Reconstruct::Nearest,
            Reconstruct::CatmullRom,
        ]
        .into_iter()
        .find(|r| r.name() == name)
    }

    /// The name on the command line and in the manifest.
    pub fn name(self) -> &'static str {
        match self {
            Reconstruct::Bilinear => "bilinear",
            Reconstruct::Nearest => "nearest",
            Reconstruct::CatmullRom => "catmull-rom",
        }
    }
}

impl std::fmt::Display for Reconstruct {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Which pass of a variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PassKind {
    /// 3pass, pass 1: keep the reprojected payload at hits.
    Reproject,
    /// 3pass, pass 2: compute the node where pass 1 left the pixel open.
    Recompute,
    /// 3pass, pass 3: the shader with the node read from the cache.
    Shade,
    /// fused: the whole variant in one pass.
    Fused,
    /// 2pass, pass 1: reproject and shade the hits.
    ShadeHits,
    /// 2pass, pass 2: the whole shader where pass 1 left the pixel open.
    ShadeMisses,
}
