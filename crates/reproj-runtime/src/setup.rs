//! What the application gives to build a variant: its frame, vertex stages and bind group
//! layouts. Below the pass builder and the resources, which both read it.

use crate::shared::SharedGroup;

/// How the application builds the variant: its frame, its vertex stages and its bind group layouts.
#[derive(Debug, Clone, Copy)]
pub struct Setup<'a> {
    /// The frame's width and height in pixels (the textures' size;
    /// [`crate::VariantResources::resize`] changes it).
    pub size: [u32; 2],
    /// The format of the application's color target: what the manifest's `frame` is.
    pub color_format: wgpu::TextureFormat,
    /// The application's vertex stages (one per pipeline state it draws with, such as its culling
    /// modes). Each pass gets one pipeline per stage, in this order: the draw callback of
    /// [`crate::VariantResources::record`] receives them as a slice.
    pub vertex: &'a [VertexStage<'a>],
    /// The layouts of the application's bind groups, by group index: every group of
    /// [`crate::Variant::own_groups`] (the original shader's resources, as the application bound
    /// them for it) and the groups its vertex stage reads. The variant's own group
    /// ([`crate::Variant::group`]) may not be among them. An index below the highest that neither
    /// these nor a pass use gets an empty group from the runtime, so no pipeline layout has a gap
    /// (Vulkan drivers draw nothing when a set stays bound across such a gap).
    pub bind_group_layouts: &'a [(u32, &'a wgpu::BindGroupLayout)],
    /// The application's motion vectors, for a variant that reads them
    /// ([`crate::Variant::reads_motion_vectors`]; `None` for any other): a float texture of the
    /// frame's size with `TEXTURE_BINDING` usage, `.xy` = `uv_current - uv_previous` (texture UV,
    /// y down), written before each frame's [`crate::VariantResources::record`]. After a resize
    /// give the new one with [`crate::VariantResources::set_motion`].
    pub motion: Option<&'a wgpu::TextureView>,
    /// The application's own bindings of the variant's group, for a variant that shares a group
    /// with the original shader ([`crate::Variant::shares_group`]: a shader that uses all four
    /// groups); `None` for any other. The runtime binds them beside its own in one bind group.
    pub shared: Option<SharedGroup<'a>>,
    /// Also build the first pass's debug entry point `reproj_classify` (the hit map: green where a
    /// pixel reused the cache, red where it recomputed, blue where it refreshed), drawn into a
    /// target of this format (`rgba8unorm`) by [`crate::VariantResources::record_classification`].
    /// The passes reproj writes leave that entry out: append reproj's `classify_wgsl` text to the
    /// first pass and build with [`crate::Variant::from_sources`]. `None` for what ships.
    pub classification: Option<wgpu::TextureFormat>,
}

/// One vertex stage of the application: its module (which writes the manifest's vertex contract,
/// [`crate::Variant::vertex`]), entry point, vertex buffers and primitive state.
#[derive(Debug, Clone)]
pub struct VertexStage<'a> {
    pub module: &'a wgpu::ShaderModule,
    pub entry_point: &'a str,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub primitive: wgpu::PrimitiveState,
}
