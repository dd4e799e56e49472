//! Run a variant reproj emitted inside your own wgpu application.
//!
//! `reproj emit` (or `reproj instance`) writes a directory: `manifest.json` and one to three WGSL
//! passes that replace your fragment shader with a reprojection cache. This crate is the host side
//! of that contract, so that you do not copy one: [`Variant::load`] reads and checks the manifest
//! (errors name the file and the field), [`Variant::create`] builds the textures (payload and
//! depth-copy ping-pong), samplers, params buffer, bind groups and one pipeline per pass, and
//! [`VariantResources::record`] records a frame's passes into your command encoder, against your
//! color target and your depth target, with your geometry drawn by your callback — passes that
//! draw into the same targets in one render pass ([`Variant::render_passes`]: a `2pass` variant
//! is one render pass of two draws), which saves a store and reload of every target.
//!
//! What stays yours: the device (with [`Variant::required_features`]), the vertex stage (which
//! adds the manifest's previous-clip-position output, [`Variant::vertex`]), the bind groups of the
//! original shader's resources (passed by group index: the runtime owns only the group reproj
//! added, [`Variant::group`]; where that group is also the shader's, a shader on all four groups,
//! your bindings of it are given as [`Setup::shared`] and bound beside reproj's), and the draw
//! calls. The runtime reads nothing of reproj but the
//! manifest and the passes, and depends on wgpu, serde, thiserror and pollster only.
//!
//! What a frame did: [`FrameInputs::occlusion`] counts each pass's samples (a `3pass` variant's
//! hits, recomputes and covered pixels: the hit rate where the frame is drawn), and a variant
//! built with [`Setup::classification`] draws a debug hit map
//! ([`VariantResources::record_classification`]). [`Variant::from_sources`] builds a variant
//! held in memory; reproj's own replay draws every variant it measures through this crate.
//!
//! [`SessionCapture`] records the motion the app draws (camera, model matrices, light, uniform
//! values per frame) as a session file, so `reproj analyze` measures the shader over it.
//!
//! Memory: the textures it allocates take [`Variant::bytes_per_pixel`] bytes per frame pixel: two
//! payloads (2 to 16 bytes each, `r16float` to `rgba32float` by the cached value's width and
//! precision) and two `r32float` depth copies, 12 to 40 bytes in all (the manifest's
//! `bytes_per_pixel`; about 166 MB at 3840×2160 for the widest). Depth: every pass draws into
//! your depth target, which the first pass clears, or, for a variant written with `--depth-load
//! load` ([`Variant::loads_depth_first`]), keeps: then the variant is depth-tested against what
//! you drew before (clear it at the frame's start yourself); either way it holds the scene's
//! depth afterwards. Motion: a variant written with `--reproject motion-vectors`
//! ([`Variant::reads_motion_vectors`]) reads your motion-vector texture ([`Setup::motion`]:
//! `.xy` = `uv_current - uv_previous`, texture UV, y down) instead of a previous clip position
//! from your vertex stage. Sizes: [`VariantResources::resize`] reallocates for a new frame size;
//! multisampled targets are not supported (every texture and pipeline has one sample: resolve
//! first, or draw the variant into a single-sampled target). Color: the first pass clears your color target to
//! [`FrameTargets::clear_color`], unless the variant was written with `--frame-load load`
//! ([`Variant::loads_frame_first`]): then it draws over what the target holds. Each
//! [`VariantResources::record`] writes the params through the queue: submit a frame's encoder
//! before recording the next.
//!
//! # Add to your wgpu app
//!
//! ```no_run
//! use reproj_runtime::{FrameInputs, FrameTargets, RuntimeError, Setup, Variant, VertexStage};
//!
//! /// Your renderer's pieces: device, queue, frame, depth, vertex stage, the original shader's
//! /// bind group (group 0 here) and the per-object transforms (group 2: `reproj instance` put
//! /// the variant's own group at 1, the lowest the shader left free).
//! struct App {
//!     device: wgpu::Device,
//!     queue: wgpu::Queue,
//!     frame: wgpu::TextureView,
//!     depth: wgpu::TextureView,
//!     vertex_module: wgpu::ShaderModule,
//!     scene_layout: wgpu::BindGroupLayout,
//!     scene_group: wgpu::BindGroup,
//!     object_layout: wgpu::BindGroupLayout,
//!     objects: Vec<(wgpu::BindGroup, wgpu::Buffer, wgpu::Buffer, u32)>,
//! }
//!
//! fn run(app: &App, frames: u32) -> Result<(), RuntimeError> {
//!     let variant = Variant::load("out/marble")?;
//!     let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
//!     let buffers = [Some(wgpu::VertexBufferLayout {
//!         array_stride: 24,
//!         step_mode: wgpu::VertexStepMode::Vertex,
//!         attributes: &attributes,
//!     })];
//!     let vertex = [VertexStage {
//!         module: &app.vertex_module,
//!         entry_point: "vs_main",
//!         buffers: &buffers,
//!         primitive: wgpu::PrimitiveState::default(),
//!     }];
//!     let mut gpu = variant.create(
//!         &app.device,
//!         &Setup {
//!             size: [1920, 1080],
//!             color_format: wgpu::TextureFormat::Rgba16Float,
//!             vertex: &vertex,
//!             bind_group_layouts: &[(0, &app.scene_layout), (2, &app.object_layout)],
//!             classification: None,
//!             motion: None,
//!             shared: None,
//!         },
//!     )?;
//!     for _ in 0..frames {
//!         // ... write this frame's uniforms and transforms ...
//!         let mut encoder = app.device.create_command_encoder(&Default::default());
//!         let targets = FrameTargets {
//!             color: &app.frame,
//!             depth: &app.depth,
//!             clear_color: wgpu::Color::BLACK,
//!         };
//!         let inputs = FrameInputs {
//!             bind_groups: &[(0, &app.scene_group)],
//!             ..Default::default()
//!         };
//!         gpu.record(&app.queue, &mut encoder, &targets, &inputs, |pass, pipelines| {
//!             pass.set_pipeline(&pipelines[0]);
//!             for (group, vertices, indices, count) in &app.objects {
//!                 pass.set_bind_group(2, group, &[]);
//!                 pass.set_vertex_buffer(0, vertices.slice(..));
//!                 pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
//!                 pass.draw_indexed(0..*count, 0, 0..1);
//!             }
//!         })?;
//!         app.queue.submit([encoder.finish()]);
//!     }
//!     Ok(())
//! }
//! ```

mod build;
pub mod capture;
mod error;
mod files;
pub mod manifest;
mod plan;
mod resources;
mod setup;
mod shared;
mod variant;
mod webgpu;

pub use capture::{CaptureError, CapturedCamera, CapturedFrame, SessionCapture};
pub use error::RuntimeError;
pub use files::{FileError, ReadLimits};
pub use resources::{FrameInputs, FrameTargets, Setup, VariantResources, VertexStage};
pub use shared::SharedGroup;
pub use variant::Variant;
