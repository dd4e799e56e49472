//! The debug hit map ([`crate::Setup::classification`]): the first pass's `reproj_classify` entry
//! drawn after a frame, with that frame's textures.

use super::VariantResources;
use crate::RuntimeError;

impl VariantResources {
    /// Draw the hit map of the frame [`VariantResources::record`] recorded last into `target`
    /// (cleared first; of [`crate::Setup::classification`]'s format and the frame's size), depth-tested
    /// in `depth` (cleared to the manifest's depth clear; the frame's size): the first pass's debug
    /// entry, with that frame's params and textures, the application's `bind_groups` and
    /// `draw`ing its geometry again as for `record`. Record it before the next frame's `record`.
    pub fn record_classification<F>(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (target, depth): (&wgpu::TextureView, &wgpu::TextureView),
        bind_groups: &[(u32, &wgpu::BindGroup)],
        mut draw: F,
    ) -> Result<(), RuntimeError>
    where
        F: FnMut(&mut wgpu::RenderPass<'_>, &[wgpu::RenderPipeline]),
    {
        let first = &self.passes[0];
        if first.classify.is_empty() {
            return Err(RuntimeError::usage(
                "record_classification",
                "the variant was built without `Setup::classification`",
            ));
        }
        // The clock counts frames recorded since the build, a resize or a restart (past
        // u32::MAX it stays at the entry's parity, never 0): the last one's entry is the one before.
        let Some(k) = self
            .frame
            .checked_sub(1)
            .map(|f| f as usize % self.plan.ping_pong)
        else {
            return Err(RuntimeError::usage(
                "record_classification",
                "no frame was recorded since the variant was built or resized",
            ));
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("reproj classification"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(self.plan.depth_clear),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        for (g, bg) in bind_groups {
            pass.set_bind_group(*g, *bg, &[]);
        }
        for (g, bg) in &first.groups[k] {
            pass.set_bind_group(*g, bg, &[]);
        }
        draw(&mut pass, &first.classify);
        Ok(())
    }
}
