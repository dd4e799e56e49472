//! What a caller chooses about a variant: the node to cache, its payload format, the strategy
//! and the frame plan's knobs ([`InstanceOptions`]), and their defaults.

use super::*;

/// Which node to cache.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeSelector {
    Id(u32),
    Root,
}

impl std::str::FromStr for NodeSelector {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "root" {
            Ok(NodeSelector::Root)
        } else {
            s.parse().map(NodeSelector::Id).map_err(|_| {
                format!("`{s}` is not a node id (a number from `reproj nodes`) or `root`")
            })
        }
    }
}

/// Which payload format a variant uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CacheFormatChoice {
    /// The narrowest 32-bit float format that holds the node (exact).
    #[default]
    Narrowest32,
    /// The narrowest 16-bit float format that holds the node (the paper's precision).
    Narrowest16,
    /// This format (it must hold the node's components).
    Exact(CacheFormat),
}

impl CacheFormatChoice {
    /// The name on the command line and in a profile: `f32`, `f16`, or the format's own name
    /// (`rgba16float`).
    pub fn name(self) -> String {
        match self {
            CacheFormatChoice::Narrowest32 => "f32".into(),
            CacheFormatChoice::Narrowest16 => "f16".into(),
            CacheFormatChoice::Exact(f) => serde_json::to_value(f)
                .ok()
                .and_then(|v| v.as_str().map(str::to_owned))
                .unwrap_or_default(),
        }
    }

    /// The choice [`name`](Self::name) writes, or `None`.
    pub fn from_name(name: &str) -> Option<CacheFormatChoice> {
        match name {
            "f32" => Some(CacheFormatChoice::Narrowest32),
            "f16" => Some(CacheFormatChoice::Narrowest16),
            _ => serde_json::from_value(serde_json::Value::String(name.into()))
                .ok()
                .map(CacheFormatChoice::Exact),
        }
    }

    /// The format for a node of `components` floats.
    pub fn resolve(self, components: u32) -> CacheFormat {
        match self {
            CacheFormatChoice::Narrowest32 => CacheFormat::narrowest(components, false),
            CacheFormatChoice::Narrowest16 => CacheFormat::narrowest(components, true),
            CacheFormatChoice::Exact(f) => f,
        }
    }
}

/// Options of [`instance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InstanceOptions {
    pub strategy: Strategy,
    pub reconstruct: Reconstruct,
    pub cache_format: CacheFormatChoice,
    /// Default refresh period written to the manifest (the modules take it at run time).
    pub delta_n: u32,
    /// Refresh block size k (1, or even so blocks align with 2×2 quads).
    pub block: u32,
    /// Relative depth tolerance of the hit test.
    pub depth_epsilon: f32,
    /// Bind group of the added bindings (`None`: the lowest one the shader does not use).
    pub group: Option<u32>,
    /// How the first pass that writes the frame color starts it.
    pub frame_load: FrameLoad,
    /// How the first pass starts the depth target.
    pub depth_load: DepthLoad,
    /// Where the lookup finds a fragment in the previous frame.
    pub reprojection: Reprojection,
}

/// How the variant's first frame-color write starts the frame target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrameLoad {
    /// Clear it to the host's clear color, as a standalone pass of the original shader would.
    #[default]
    Clear,
    /// Keep what the engine drew before (its other passes, a sky): the variant's passes only
    /// write the pixels of their geometry.
    Load,
}

/// How the variant's first pass starts the depth target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DepthLoad {
    /// Clear it: the variant is depth-tested against itself only, as a standalone pass of the
    /// original shader would be.
    #[default]
    Clear,
    /// Keep the engine's depth (its opaque geometry drawn before): the variant's fragments behind
    /// it are not drawn, nor cached. The host clears the depth at the frame's start.
    Load,
}

impl Default for InstanceOptions {
    fn default() -> Self {
        InstanceOptions {
            strategy: Strategy::ThreePass,
            reconstruct: Reconstruct::Bilinear,
            cache_format: CacheFormatChoice::Narrowest32,
            delta_n: 8,
            block: 4,
            depth_epsilon: 0.01,
            group: None,
            frame_load: FrameLoad::Clear,
            depth_load: DepthLoad::Clear,
            reprojection: Reprojection::Vertex,
        }
    }
}
