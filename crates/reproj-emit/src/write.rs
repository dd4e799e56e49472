//! The last phase of `emit`: write the chosen variant (a set of nodes, one node) or the original
//! shader into the staged output folder, and fill the report from the choice.

use std::path::Path;

use reproj_front::{Loaded, Shader};
use reproj_instance::{DeltaNBand, Variant, variant_files};
use reproj_metrics::psnr;
use reproj_models::Profile;
use reproj_select::Choice;

use crate::spec::{Profiled, VariantSpec};
use crate::{EmitError, EmitOptions, EmitReport};

/// What writing the choice needs from [`crate::emit`].
pub(super) struct Writer<'a> {
    pub(super) profile: &'a Profile,
    pub(super) profile_path: &'a Path,
    pub(super) opts: &'a EmitOptions,
    pub(super) shader_path: &'a Path,
    /// The WGSL `analyze` profiled, and its normalised IR and node table.
    pub(super) shader: &'a Shader,
    pub(super) loaded: &'a Loaded,
    pub(super) staging: &'a reproj_io::StagedDir,
}

impl Writer<'_> {
    /// Write the profiled node or set at the choice's Δn (a node's own filter, a set's the
    /// profile's), with its run-time `schedule`.
    pub(super) fn variant(
        &self,
        choice: &Choice,
        profiled: Profiled<'_>,
        schedule: Vec<DeltaNBand>,
        report: &mut EmitReport,
    ) -> Result<Variant, EmitError> {
        let spec = self.spec(profiled, choice.delta_n)?;
        let mut variant = spec.instance(self.shader, self.loaded, &self.opts.integration)?;
        variant.manifest.params.schedule = schedule;
        self.write_variant(&variant, report)?;
        report.node = Some(profiled.name());
        report.strategy = Some(profiled.strategy_name().to_owned());
        report.reconstruct = Some(spec.reconstruct.name().into());
        let (line, col, mse) = match profiled {
            Profiled::Node(n) => (Some(n.line), Some(n.col), n.mse_at(choice.delta_n)),
            Profiled::Set(s) => {
                let first = self.profile.nodes.iter().find(|n| n.id == s.members[0]);
                (
                    first.map(|n| n.line),
                    first.map(|n| n.col),
                    s.mse_at(choice.delta_n),
                )
            }
        };
        (report.line, report.col) = (line, col);
        report.predicted_psnr = mse.map(psnr);
        fill_choice(report, choice);
        Ok(variant)
    }

    /// The spec `emit` writes of `profiled` at `delta_n`: the profile's, in `opts`' cache format.
    pub(super) fn spec(
        &self,
        profiled: Profiled<'_>,
        delta_n: u32,
    ) -> Result<VariantSpec, EmitError> {
        Ok(
            VariantSpec::of(self.profile, self.profile_path, profiled, delta_n)?
                .in_format(self.opts.cache_format),
        )
    }

    /// Nothing pays under the budget: write the shader as it was given (GLSL or SPIR-V stay what
    /// they were), and why.
    pub(super) fn original(&self, reason: &str, report: &mut EmitReport) -> Result<(), EmitError> {
        original(
            self.staging,
            &self.opts.out,
            self.shader_path,
            reason,
            report,
        )
    }

    /// Stage the variant's files (passes in every language, manifest) and list them in the report.
    fn write_variant(&self, variant: &Variant, report: &mut EmitReport) -> Result<(), EmitError> {
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

/// Stage the shader at `shader_path` as it was given (GLSL or SPIR-V stay what they were) for
/// the folder `out`, list it in the report, and say why.
pub(super) fn original(
    staging: &reproj_io::StagedDir,
    out: &Path,
    shader_path: &Path,
    reason: &str,
    report: &mut EmitReport,
) -> Result<(), EmitError> {
    let name = shader_path
        .file_name()
        .map_or_else(|| "original.wgsl".into(), |n| n.to_owned());
    let original = std::fs::read(shader_path).map_err(|source| {
        EmitError::Front(reproj_front::FrontError::Io {
            path: shader_path.to_owned(),
            source,
        })
    })?;
    staging.write(&name, &original)?;
    report.files.push(out.join(&name).display().to_string());
    report.reason = Some(reason.to_owned());
    Ok(())
}
