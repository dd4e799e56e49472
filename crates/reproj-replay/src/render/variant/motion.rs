//! The engine's motion vectors, for a variant written with `--reproject motion-vectors`: a pass
//! before the variant's that draws the scene with the replay's vertex stage and writes, per
//! pixel, `uv_current - uv_previous` (texture UV, y down) of the nearest surface, as an engine's
//! velocity pass does. It stands for work the engine does anyway (for its temporal
//! antialiasing or motion blur), so it is not among the passes timed.

use super::*;

/// Format of the motion-vector texture: two exact floats.
const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

/// The motion pass's fragment stage: the previous clip position (a vertex output at
/// `PREV_CLIP`) to a motion in UV. A point behind the previous camera gets a motion that puts
/// it far off screen, so the lookup misses.
const MOTION_WGSL: &str = "@fragment
fn replay_motion(@builtin(position) position: vec4<f32>, @location(PREV_CLIP) prev_clip: vec4<f32>) -> @location(0) vec4<f32> {
    let uv = position.xy / vec2<f32>(WIDTH, HEIGHT);
    if prev_clip.w <= 0.0 {
        return vec4<f32>(uv + vec2<f32>(16.0), 0.0, 0.0);
    }
    let ndc = prev_clip.xy / prev_clip.w;
    let previous = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    return vec4<f32>(uv - previous, 0.0, 0.0);
}
";

/// The motion-vector texture, its depth buffer and the pass's pipeline.
pub(in crate::render) struct MotionGpu {
    pub(in crate::render) view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    pipe: Pipe,
    none: Bindings,
}

/// The vertex output the motion pass reads, when the variant's own passes read none: the
/// previous clip position, one location past the highest fragment input.
pub(in crate::render) fn prev_clip_input(inputs: &[reflect::FragInput]) -> reflect::FragInput {
    reflect::FragInput {
        location: inputs.iter().map(|i| i.location + 1).max().unwrap_or(0),
        components: 4,
        scalar: reflect::InputScalar::F32,
        interpolation: None,
        sampling: None,
        name: "prev_clip".into(),
    }
}

impl Renderer {
    /// The motion pass's texture, depth and pipeline, for frames of `size`.
    pub(in crate::render) fn motion_gpu(
        &self,
        size: [u32; 2],
        vs: &wgpu::ShaderModule,
        vs_src: &str,
        scene: &Scene,
        vgroup: u32,
        prev_clip_location: u32,
    ) -> Result<MotionGpu, ReplayError> {
        let [w, h] = size;
        let src = MOTION_WGSL
            .replace("PREV_CLIP", &prev_clip_location.to_string())
            .replace("WIDTH", &format!("{w}.0"))
            .replace("HEIGHT", &format!("{h}.0"));
        let fs = self.shader_module("replay motion vectors", &src)?;
        let none = Bindings::empty();
        let pipe = self.pipeline(
            &PipelineSpec {
                label: "motion vectors",
                sources: [vs_src, &src],
                vs,
                fs: &fs,
                entry: "replay_motion",
                formats: &[Some(MOTION_FORMAT)],
                compare: wgpu::CompareFunction::Less,
                depth_write: true,
            },
            &none,
            scene,
            vgroup,
        )?;
        let view = self
            .target("motion vectors", w, h, MOTION_FORMAT, true)
            .create_view(&Default::default());
        let depth_view = self
            .target("motion vectors depth", w, h, DEPTH_FORMAT, false)
            .create_view(&Default::default());
        Ok(MotionGpu {
            view,
            depth_view,
            pipe,
            none,
        })
    }

    /// Record the motion pass: the texture cleared to no motion, then the scene's surfaces.
    pub(in crate::render) fn encode_motion(
        &self,
        enc: &mut wgpu::CommandEncoder,
        mg: &MotionGpu,
        scene: &Scene,
        vgroup: u32,
    ) {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("motion vectors"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &mg.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &mg.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        self.draw(&mut pass, &mg.pipe, &mg.none, scene, vgroup);
    }
}
