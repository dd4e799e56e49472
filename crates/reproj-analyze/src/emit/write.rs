//! The last phase of `emit`: write the chosen variant (a set of nodes, one node) or the original
//! shader into the staged output folder, and fill the report from the choice.

use std::path::Path;

use reproj_front::{Loaded, Shader};
use reproj_instance::{
    CacheFormatChoice, DeltaNBand, InstanceOptions, NodeSelector, Reconstruct, Strategy, Variant,
    instance, instance_nodes, variant_files,
};
use reproj_metrics::psnr;
use reproj_models::Profile;
use reproj_models::profile::{NodeProfile, SetProfile};
use reproj_select::Choice;

use super::{EmitOptions, EmitReport, profile_variant_settings};
use crate::AnalyzeError;

/// What writing the choice needs from [`super::emit`].
pub(super) struct Writer<'a> {
    pub(super) profile: &'a Profile,
    pub(super) profile_path: &'a Path,
    pub(super) opts: &'a EmitOptions,
    pub(super) shader_path: &'a Path,
    /// The WGSL `analyze` profiled, and its normalised IR and node table.
    pub(super) shader: &'a Shader,
    pub(super) loaded: &'a Loaded,
    pub(super) cache_format: CacheFormatChoice,
    pub(super) staging: &'a reproj_io::StagedDir,
}

impl Writer<'_> {
    /// Write the set `set` at the choice's Δn (its filter `reconstruct`, its run-time `schedule`).
    pub(super) fn set(
        &self,
        choice: &Choice,
        set: &SetProfile,
        reconstruct: Reconstruct,
        schedule: Vec<DeltaNBand>,
        report: &mut EmitReport,
    ) -> Result<Variant, AnalyzeError> {
        let strategy = self.strategy(&set.strategy, &format!("set {}", set.name()))?;
        let sels: Vec<NodeSelector> = set.members.iter().map(|&id| NodeSelector::Id(id)).collect();
        let mut variant = instance_nodes(
            self.shader,
            &self.loaded.norm,
            &self.loaded.table,
            &sels,
            &InstanceOptions {
                strategy,
                reconstruct,
                cache_format: self.cache_format,
                delta_n: choice.delta_n,
                block: set.block,
                depth_epsilon: self.profile.depth_epsilon,
                group: self.opts.integration.group,
                frame_load: self.opts.integration.frame_load,
                depth_load: self.opts.integration.depth_load,
                reprojection: self.opts.integration.reprojection,
            },
        )?;
        variant.manifest.params.schedule = schedule;
        self.write_variant(&variant, report)?;
        let first = self.profile.nodes.iter().find(|n| n.id == set.members[0]);
        report.node = Some(set.name());
        report.strategy = Some(set.strategy.clone());
        report.reconstruct = Some(reconstruct.name().into());
        report.line = first.map(|n| n.line);
        report.col = first.map(|n| n.col);
        report.predicted_psnr = set.mse_at(choice.delta_n).map(psnr);
        fill_choice(report, choice);
        Ok(variant)
    }

    /// Write the node `node` at the choice's Δn (its own filter, its run-time `schedule`).
    pub(super) fn node(
        &self,
        choice: &Choice,
        node: &NodeProfile,
        schedule: Vec<DeltaNBand>,
        report: &mut EmitReport,
    ) -> Result<Variant, AnalyzeError> {
        let (mut variant, reconstruct) = node_variant(
            self.profile,
            self.profile_path,
            self.opts,
            (self.shader, self.loaded),
            self.cache_format,
            choice.delta_n,
            node,
        )?;
        variant.manifest.params.schedule = schedule;
        self.write_variant(&variant, report)?;
        report.node = Some(if node.root {
            "root".into()
        } else {
            node.id.to_string()
        });
        report.strategy = Some(node.strategy.clone());
        report.reconstruct = Some(reconstruct.name().into());
        report.line = Some(node.line);
        report.col = Some(node.col);
        report.predicted_psnr = node.mse_at(choice.delta_n).map(psnr);
        fill_choice(report, choice);
        Ok(variant)
    }

    /// Nothing pays under the budget: write the shader as it was given (GLSL or SPIR-V stay what
    /// they were), and why.
    pub(super) fn original(
        &self,
        reason: &str,
        report: &mut EmitReport,
    ) -> Result<(), AnalyzeError> {
        let name = self
            .shader_path
            .file_name()
            .map_or_else(|| "original.wgsl".into(), |n| n.to_owned());
        let original = std::fs::read(self.shader_path).map_err(|source| {
            AnalyzeError::Front(reproj_front::FrontError::Io {
                path: self.shader_path.to_owned(),
                source,
            })
        })?;
        self.staging.write(&name, &original)?;
        report
            .files
            .push(self.opts.out.join(&name).display().to_string());
        report.reason = Some(reason.to_owned());
        Ok(())
    }

    /// The profile's strategy name of `what`, parsed.
    fn strategy(&self, name: &str, what: &str) -> Result<Strategy, AnalyzeError> {
        parse_strategy(self.profile_path, name, what)
    }

    /// Stage the variant's files (passes in every language, manifest) and list them in the report.
    fn write_variant(
        &self,
        variant: &Variant,
        report: &mut EmitReport,
    ) -> Result<(), AnalyzeError> {
        for (name, bytes) in variant_files(variant, &self.opts.outputs)? {
            self.staging.write(name, &bytes)?;
        }
        let out = &self.opts.out;
        for p in &variant.manifest.passes {
            report.files.push(out.join(&p.file).display().to_string());
        }
        report
            .files
            .push(out.join("manifest.json").display().to_string());
        Ok(())
    }
}

/// The profile's strategy name of `what`, parsed (a bad name is a bad profile at `profile_path`).
fn parse_strategy(profile_path: &Path, name: &str, what: &str) -> Result<Strategy, AnalyzeError> {
    name.parse().map_err(|e: String| AnalyzeError::BadProfile {
        path: profile_path.to_owned(),
        message: format!("{what}: {e}"),
    })
}

/// The variant of `node` at `delta_n` as `emit` writes it, in memory: the node's profiled
/// strategy, filter and block, the profile's ε, `opts`' cache format and host integration;
/// with its filter. `shader` is the profiled WGSL and its loaded IR and node table.
pub(super) fn node_variant(
    profile: &Profile,
    profile_path: &Path,
    opts: &EmitOptions,
    shader: (&Shader, &Loaded),
    cache_format: CacheFormatChoice,
    delta_n: u32,
    node: &NodeProfile,
) -> Result<(Variant, Reconstruct), AnalyzeError> {
    let strategy = parse_strategy(profile_path, &node.strategy, &format!("node {}", node.id))?;
    let sel = if node.root {
        NodeSelector::Root
    } else {
        NodeSelector::Id(node.id)
    };
    let (reconstruct, _) = profile_variant_settings(profile, Some(node), profile_path)?;
    let (shader, loaded) = shader;
    let variant = instance(
        shader,
        &loaded.norm,
        &loaded.table,
        sel,
        &InstanceOptions {
            strategy,
            reconstruct,
            cache_format,
            delta_n,
            block: node.block.unwrap_or(profile.block),
            depth_epsilon: profile.depth_epsilon,
            group: opts.integration.group,
            frame_load: opts.integration.frame_load,
            depth_load: opts.integration.depth_load,
            reprojection: opts.integration.reprojection,
        },
    )?;
    Ok((variant, reconstruct))
}

/// The choice's own figures into the report (a node's or a set's alike).
fn fill_choice(report: &mut EmitReport, choice: &Choice) {
    report.node_text = Some(choice.node_text.clone());
    report.delta_n = Some(choice.delta_n);
    report.predicted_error = Some(choice.predicted_error);
    report.predicted_ms = Some(choice.predicted_ms);
    // The session whose speedup is the lowest (the profile's own with one session).
    report.original_ms = choice.original_ms;
    report.predicted_speedup = Some(choice.predicted_speedup);
    report.predicted_speedup_ci95 = choice.predicted_speedup_ci95;
}
