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
        check_pass_kinds(m)?;
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
        // The variant as the runtime reads it: the manifest with the render's refresh block and
        // depth tolerance, and the passes as drawn (the classification entry appended).
        let manifest_json = manifest_for(m, variant.block, variant.depth_epsilon)?;
        let sources: Vec<String> = stages.iter().map(|s| s.shader.source.clone()).collect();
        let runtime = reproj_runtime::Variant::from_sources(
            Path::new(&variant.label),
            &manifest_json,
            &sources,
        )
        .map_err(|e| ReplayError::Variant {
            message: e.to_string(),
        })?;
        let render_pass_count = if variant.pass_times {
            runtime.pass_count()
        } else {
            runtime.render_pass_count()
        } as u32;
        Ok(VariantPlan {
            frames,
            first,
            render_pass_count,
            stages,
            classify_stage,
            label: variant.label.clone(),
            manifest_json,
            sources,
            runtime,
        })
    }
}

/// What a variant render needs before any GPU object ([`Renderer::plan_variant`]).
pub(in crate::render) struct VariantPlan {
    pub(in crate::render) frames: u32,
    pub(in crate::render) first: u32,
    /// The render passes a frame records: the runtime's
    /// ([`reproj_runtime::Variant::render_passes`]), or one per pass where each is timed
    /// ([`VariantInput::pass_times`]).
    pub(in crate::render) render_pass_count: u32,
    /// Each pass's module and interface, in the same order.
    pub(in crate::render) stages: Vec<Stage>,
    /// The first pass's classification entry point, when it is rendered each frame.
    pub(in crate::render) classify_stage: Option<Interface>,
    /// The variant's label, for messages.
    pub(in crate::render) label: String,
    /// The manifest and the passes' WGSL the runtime was given (the key of the built variant).
    pub(in crate::render) manifest_json: String,
    pub(in crate::render) sources: Vec<String>,
    /// The variant as `reproj-runtime` reads it, checked: what draws it.
    pub(in crate::render) runtime: reproj_runtime::Variant,
}

impl VariantPlan {
    /// The interfaces of the passes and of the classification entry where it is rendered.
    pub(in crate::render) fn interfaces(&self) -> impl Iterator<Item = &Interface> {
        self.stages
            .iter()
            .map(|s| &s.iface)
            .chain(self.classify_stage.as_ref())
    }
}

/// The passes a strategy has, in order: a manifest listing others is refused by name.
fn check_pass_kinds(m: &reproj_instance::Manifest) -> Result<(), ReplayError> {
    use reproj_instance::{PassKind, Strategy};
    let expected: &[PassKind] = match m.strategy {
        Strategy::ThreePass => &[PassKind::Reproject, PassKind::Recompute, PassKind::Shade],
        Strategy::TwoPass => &[PassKind::ShadeHits, PassKind::ShadeMisses],
        Strategy::Fused => &[PassKind::Fused],
    };
    let kinds: Vec<PassKind> = m.passes.iter().map(|p| p.kind).collect();
    if kinds != expected {
        return Err(ReplayError::Variant {
            message: format!(
                "a {} variant has the passes {expected:?}, the manifest lists {kinds:?}",
                m.strategy
            ),
        });
    }
    Ok(())
}

/// `m` as JSON, its `block` and `depth_epsilon` parameters set to the render's.
fn manifest_for(
    m: &reproj_instance::Manifest,
    block: u32,
    depth_epsilon: f32,
) -> Result<String, ReplayError> {
    let bad = |e: serde_json::Error| ReplayError::Variant {
        message: format!("the manifest does not serialize: {e}"),
    };
    let mut json = serde_json::to_value(m).map_err(bad)?;
    if let Some(fields) = json
        .pointer_mut("/params/fields")
        .and_then(|f| f.as_array_mut())
    {
        for f in fields {
            let value = match f.get("name").and_then(|n| n.as_str()) {
                Some("block") => f64::from(block),
                Some("depth_epsilon") => f64::from(depth_epsilon),
                _ => continue,
            };
            if let Some(v) = f.pointer_mut("/value/value") {
                *v = serde_json::json!(value);
            }
        }
    }
    serde_json::to_string(&json).map_err(bad)
}
