//! The contract between the instancer and whoever runs its passes (the replay, a host): the names
//! and binding numbers of the bindings the instancer adds to the variant's group, the layout of the
//! `reproj_params` uniform buffer as a `#[repr(C)]` struct, the debug classification entry point
//! and the bind group limit. Both sides use these items, so a renamed binding or a moved field is a
//! compile error or a failing test (`contract_matches_library`, `params_struct_matches_wgsl`)
//! instead of a run-time failure on a GPU.

use bytemuck::{Pod, Zeroable};

/// The output struct member of a pass that writes the new cache payload (a `vec4<f32>` at a
/// location above 0).
pub const CACHE_OUTPUT: &str = "reproj_cache";
/// The output struct member of a pass that writes the depth copy (an `f32` at a location above 0).
pub const DEPTH_OUTPUT: &str = "reproj_depth";

/// Bind groups a variant may use: indices `0..MAX_BIND_GROUPS` (WebGPU's default `maxBindGroups`).
pub const MAX_BIND_GROUPS: u32 = 4;

/// Where the bindings the instancer adds go. A group of their own (`base` 0: the lowest group the
/// shader leaves free), or, where the shader uses all [`MAX_BIND_GROUPS`] groups, one of the
/// shader's groups past its own bindings (`base` one past its highest): the variant's group is
/// then shared, and a host binds its own resources of that group beside the added ones. The
/// `*_BINDING` constants are offsets from `base`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AddedPlace {
    pub group: u32,
    pub base: u32,
}

impl AddedPlace {
    /// A group of the variant's own.
    pub fn own(group: u32) -> AddedPlace {
        AddedPlace { group, base: 0 }
    }

    /// The binding number of the added binding at `offset` (a `*_BINDING` constant).
    pub fn binding(self, offset: u32) -> u32 {
        self.base + offset
    }

    /// Whether `@group(group) @binding(binding)` is one of the added bindings' slots.
    pub fn holds(self, group: u32, binding: u32) -> bool {
        group == self.group && binding >= self.base
    }

    /// Whether the group also holds the shader's own bindings.
    pub fn shared(self) -> bool {
        self.base > 0
    }
}

/// The debug entry point a replay appends to the first pass's module ([`crate::classify_wgsl`]):
/// green hit, red miss, blue refresh (rgba8unorm target, no discard).
pub const CLASSIFY_ENTRY: &str = "reproj_classify";

/// The `reproj_params` uniform buffer ([`ReprojParams`]).
pub const PARAMS: &str = "reproj_params";
/// Binding number of [`PARAMS`] in the variant's group.
pub const PARAMS_BINDING: u32 = 0;
/// The previous frame's payload texture.
pub const PREV_PAYLOAD: &str = "reproj_prev_payload";
/// Binding number of [`PREV_PAYLOAD`].
pub const PREV_PAYLOAD_BINDING: u32 = 1;
/// The previous frame's depth copy (r32float, read as a float texture).
pub const PREV_DEPTH: &str = "reproj_prev_depth";
/// Binding number of [`PREV_DEPTH`].
pub const PREV_DEPTH_BINDING: u32 = 2;
/// The current frame's payload, read by the passes after the one that writes it.
pub const CUR_PAYLOAD: &str = "reproj_cur_payload";
/// Binding number of [`CUR_PAYLOAD`].
pub const CUR_PAYLOAD_BINDING: u32 = 3;
/// Linear clamp-to-edge sampler: bilinear reconstruction of the payload.
pub const LINEAR_SAMPLER: &str = "reproj_linear_sampler";
/// Binding number of [`LINEAR_SAMPLER`].
pub const LINEAR_SAMPLER_BINDING: u32 = 5;
/// The engine's motion-vector texture (`reprojection: motion_vectors`): `.xy` = `uv_current -
/// uv_previous` per frame pixel.
pub const MOTION: &str = "reproj_motion";
/// Binding number of [`MOTION`].
pub const MOTION_BINDING: u32 = 6;
/// The function of the motion-vector library that turns a fragment position into its previous
/// clip position.
pub const MOTION_CLIP: &str = "reproj_motion_clip";
/// Nearest clamp-to-edge sampler, declared by variants written by earlier versions (the replay
/// still binds it; this instancer no longer declares it).
pub const POINT_SAMPLER: &str = "reproj_point_sampler";

/// Every binding this instancer adds to the variant's group: (name, binding number).
pub const ADDED_BINDINGS: [(&str, u32); 6] = [
    (PARAMS, PARAMS_BINDING),
    (PREV_PAYLOAD, PREV_PAYLOAD_BINDING),
    (PREV_DEPTH, PREV_DEPTH_BINDING),
    (CUR_PAYLOAD, CUR_PAYLOAD_BINDING),
    (LINEAR_SAMPLER, LINEAR_SAMPLER_BINDING),
    (MOTION, MOTION_BINDING),
];

/// The `reproj_params` uniform buffer, byte for byte as the lookup library's `ReprojParams`
/// declares it (WGSL uniform layout: four 4-byte scalars, 16 bytes). Write it with
/// [`bytemuck::bytes_of`].
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct ReprojParams {
    /// Refresh period Δn: each k×k block is recomputed once every Δn frames (1 on the first frame).
    pub delta_n: u32,
    /// Frame counter.
    pub clock: u32,
    /// Refresh block size k in pixels.
    pub block: u32,
    /// Relative depth tolerance of the hit test.
    pub depth_epsilon: f32,
}

/// Size in bytes of the `reproj_params` buffer.
pub const PARAMS_SIZE: u32 = std::mem::size_of::<ReprojParams>() as u32;

impl ReprojParams {
    /// The values of frame `frame`: Δn is 1 on frame 0 (the previous frame's textures hold
    /// nothing), `delta_n` after; the clock is the frame index.
    pub fn for_frame(frame: u32, delta_n: u32, block: u32, depth_epsilon: f32) -> ReprojParams {
        ReprojParams {
            delta_n: if frame == 0 { 1 } else { delta_n },
            clock: frame,
            block,
            depth_epsilon,
        }
    }
}

/// Byte offsets of the fields of [`ReprojParams`], by WGSL member name.
pub const PARAMS_OFFSETS: [(&str, u32); 4] = [
    (
        "delta_n",
        std::mem::offset_of!(ReprojParams, delta_n) as u32,
    ),
    ("clock", std::mem::offset_of!(ReprojParams, clock) as u32),
    ("block", std::mem::offset_of!(ReprojParams, block) as u32),
    (
        "depth_epsilon",
        std::mem::offset_of!(ReprojParams, depth_epsilon) as u32,
    ),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Reconstruct;
    use crate::library::{PrevClip, library_text};

    fn library_with(prev_clip: PrevClip) -> naga::Module {
        let text = library_text(AddedPlace::own(1), prev_clip, Reconstruct::Bilinear, None);
        naga::front::wgsl::parse_str(&text).expect("the lookup library parses")
    }

    fn library() -> naga::Module {
        library_with(PrevClip::Location(7))
    }

    /// The lookup library declares exactly the contract's bindings, by name and number: the
    /// motion vectors only where it reads them.
    #[test]
    fn contract_matches_library() {
        for prev_clip in [PrevClip::Location(7), PrevClip::Motion] {
            let m = library_with(prev_clip);
            let declared: Vec<(String, u32)> = m
                .global_variables
                .iter()
                .filter_map(|(_, g)| Some((g.name.clone()?, g.binding.as_ref()?.binding)))
                .collect();
            for (name, binding) in &declared {
                assert!(
                    ADDED_BINDINGS.contains(&(name.as_str(), *binding)),
                    "the library declares {name} at binding {binding}, which the contract does not list"
                );
            }
            // The current payload is added by the instancer in code (not the library).
            let expected = ADDED_BINDINGS.iter().filter(|(n, _)| {
                *n != CUR_PAYLOAD && (*n != MOTION || prev_clip == PrevClip::Motion)
            });
            for (name, binding) in expected {
                assert!(
                    declared.contains(&(name.to_string(), *binding)),
                    "the contract lists {name} at binding {binding}, the library does not declare it"
                );
            }
            assert_eq!(
                m.functions
                    .iter()
                    .any(|(_, f)| f.name.as_deref() == Some(MOTION_CLIP)),
                prev_clip == PrevClip::Motion
            );
        }
    }

    /// The WGSL struct `ReprojParams` has the Rust struct's size and field offsets.
    #[test]
    fn params_struct_matches_wgsl() {
        let m = library();
        let (_, ty) = m
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("ReprojParams"))
            .expect("the library declares ReprojParams");
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("ReprojParams is not a struct");
        };
        assert_eq!(*span, PARAMS_SIZE);
        let wgsl: Vec<(String, u32)> = members
            .iter()
            .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
            .collect();
        let rust: Vec<(String, u32)> = PARAMS_OFFSETS
            .iter()
            .map(|(n, o)| (n.to_string(), *o))
            .collect();
        assert_eq!(wgsl, rust);
    }

    #[test]
    fn for_frame_refreshes_everything_on_frame_zero() {
        let p = ReprojParams::for_frame(0, 8, 4, 0.01);
        assert_eq!((p.delta_n, p.clock, p.block), (1, 0, 4));
        let p = ReprojParams::for_frame(3, 8, 4, 0.01);
        assert_eq!((p.delta_n, p.clock), (8, 3));
        let bytes = bytemuck::bytes_of(&p);
        assert_eq!(bytes.len(), PARAMS_SIZE as usize);
        assert_eq!(&bytes[0..4], &8u32.to_le_bytes());
        assert_eq!(&bytes[4..8], &3u32.to_le_bytes());
        assert_eq!(&bytes[12..16], &0.01f32.to_le_bytes());
    }
}
