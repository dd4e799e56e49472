//! Phase 1 of a variant render: check it against its reference and the adapter, and make its
//! passes' stages. Nothing on the GPU yet.

use super::*;
impl Renderer {
    /// Check a variant render against its reference (where it is scored) and the adapter, and make its passes'
    /// stages (their interfaces with the shader's own names): everything before a GPU object.
    pub(in crate::render) fn plan_variant(
        &self,
        shader: &Shader,
        session: &Session,
        variant: &VariantInput,
        reference: Option<&Reference>,
        opts: &RenderOptions,
    ) -> Result<VariantPlan, ReplayError> {
        session.validate()?;
        let m = &variant.manifest;
        let [w, h] = session.resolution;
        let frames = Self::frame_count(session, opts);
        let first = Self::first_frame(session, opts)?;
        if let Some(reference) = reference {
            reference.covers([w, h], first + frames)?;
        }
        if variant.delta_n == 0
            || variant.block == 0
            || variant.delta_n_per_frame.iter().flatten().any(|&d| d == 0)
        {
            return Err(ReplayError::Variant {
                message: "Δn and k must be at least 1".into(),
            });
        }
        let specs = pass_specs(m)?;
        if variant.sources.len() != m.passes.len() {
            return Err(ReplayError::Variant {
                message: format!(
                    "the manifest lists {} passes and {} modules were given",
                    m.passes.len(),
                    variant.sources.len()
                ),
            });
        }
        // The fused pass cannot count its hits with an occlusion query: classify every frame,
        // with the debug entry appended to pass 1 where the variant does not ship it.
        let classify = opts.classify || m.strategy == reproj_instance::Strategy::Fused;
        let mut stages = Vec::new();
        for (i, (p, src)) in m.passes.iter().zip(&variant.sources).enumerate() {
            let mut stage = self.make_stage(Path::new(&p.file), src.clone(), &p.entry)?;
            if i == 0
                && classify
                && reflect::fragment_entry_index(&stage.shader.module, CLASSIFY_ENTRY).is_none()
            {
                let with = format!("{src}{}", reproj_instance::classify_wgsl(m.reprojection));
                stage = self.make_stage(Path::new(&p.file), with, &p.entry)?;
            }
            stages.push(stage);
        }
        // naga's WGSL writer renames identifiers that end in a digit (`sh0` becomes `sh0_`): take
        // the shader's own names back from the original module, by group/binding and field order.
        let original = reflect::reflect(
            &shader.module,
            &shader.info,
            shader
                .fragment_entry(Some(&m.entry))
                .map_err(|e| ReplayError::Variant {
                    message: e.to_string(),
                })?,
        )?;
        for st in &mut stages {
            restore_names(&mut st.iface, &original);
        }
        let classify_stage = if classify {
            let s1 = &stages[0].shader;
            match reflect::fragment_entry_index(&s1.module, CLASSIFY_ENTRY) {
                Some(ci) => Some(reflect::reflect(&s1.module, &s1.info, ci)?),
                None => None,
            }
        } else {
            None
        };
        if !m.cache_format.is_half()
            && m.reconstruct.filters()
            && !self
                .device
                .features()
                .contains(wgpu::Features::FLOAT32_FILTERABLE)
        {
            return Err(ReplayError::Unsupported {
                what: format!(
                    "{} has no float32-filterable feature, needed to filter a {} cache; use a 16-bit cache format or nearest reconstruction",
                    self.adapter_info.name,
                    m.cache_format.name()
                ),
            });
        }
        let render_passes = render_passes(&specs, variant.pass_times);
        Ok(VariantPlan {
            frames,
            first,
            specs,
            render_passes,
            stages,
            classify_stage,
        })
    }
}

/// What a variant render needs before any GPU object ([`Renderer::plan_variant`]).
pub(in crate::render) struct VariantPlan {
    pub(in crate::render) frames: u32,
    pub(in crate::render) first: u32,
    /// Each pass's targets and depth state, in the manifest's order.
    pub(in crate::render) specs: Vec<PassSpec>,
    /// The render passes they are drawn in ([`render_passes`]): ranges of `specs`.
    pub(in crate::render) render_passes: Vec<std::ops::Range<usize>>,
    /// Each pass's module and interface, in the same order.
    pub(in crate::render) stages: Vec<Stage>,
    /// The first pass's classification entry point, when it is rendered each frame.
    pub(in crate::render) classify_stage: Option<Interface>,
}
