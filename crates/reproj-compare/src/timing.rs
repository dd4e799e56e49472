//! The final timing: every method's chosen candidate raced against the original in one longer
//! interleaved run (the searches decided on short ones), whose speeds the table reports.

use std::path::Path;

use reproj_replay::Renderer;
use reproj_scene::Session;

use crate::{CompareError, CompareInput, CompareOptions, Ctx, MethodResult, Methods, temporal};

/// Every method's final candidate against the original, interleaved in one longer run: the
/// speeds the table reports (the searches decided on short interleaved runs). Takes reproj's
/// variant out of `m`.
pub(crate) fn time_final(
    ctx: &Ctx,
    input: &CompareInput,
    opts: &CompareOptions,
    m: &mut Methods,
) -> Result<reproj_bench::BenchReport, CompareError> {
    let small = {
        let mut small = input.session.clone();
        small.resolution = m.resize.tries[m.resize.chosen].resolution;
        small
    };
    let temporal = m
        .temporal
        .as_ref()
        .map(|t| reproj_replay::UpsampleSpec::at(t.tries[t.chosen].resolution));
    let composed = m
        .composed
        .as_ref()
        .map(|t| reproj_replay::UpsampleSpec::at(t.tries[t.chosen].resolution));
    time_methods(
        ctx.renderer,
        ctx.baseline,
        input.session,
        Finals {
            small,
            temporal,
            simplified_wgsl: &m.simplified.wgsl,
            composed,
            reproj: m.reproj_input.take(),
        },
        &opts.timing,
    )
}

/// Each method's speed from the final interleaved run (where it gave an estimate).
pub(crate) fn apply_timing(
    methods: &mut [MethodResult],
    timed: &reproj_bench::BenchReport,
    target: f64,
) {
    for m in methods.iter_mut() {
        // The edge-adaptive upscale is resize's render: its speed.
        let name = if m.method == "easu" {
            "resize"
        } else {
            &m.method
        };
        let at = timed.candidates.iter().position(|c| c.name == name);
        if let Some(e) = at.and_then(|i| timed.estimate(i)) {
            m.speedup = e.speedup;
            m.speedup_ci95 = Some(e.ci95);
            m.frame_ms = e.candidate_ms;
            m.reached_target = e.speedup >= target;
        }
    }
}

/// The methods' final candidates, in the table's order.
struct Finals<'a> {
    /// The session at the resized resolution.
    small: Session,
    /// The temporal upsampler at its chosen resolution, when compared.
    temporal: Option<reproj_replay::UpsampleSpec>,
    simplified_wgsl: &'a str,
    /// reproj's variant inside the upsampler at its chosen resolution, when compared.
    composed: Option<reproj_replay::UpsampleSpec>,
    reproj: Option<reproj_replay::VariantInput>,
}

/// Time the methods' final candidates — the original at the resized resolution, the temporal
/// upsampler, the simplified shader, reproj's variant — against the original in one interleaved
/// run, in the order of the table (each estimate is read by its index).
fn time_methods(
    renderer: &Renderer,
    baseline: reproj_bench::Baseline<'_>,
    session: &Session,
    finals: Finals<'_>,
    timing: &reproj_bench::BenchOptions,
) -> Result<reproj_bench::BenchReport, CompareError> {
    use reproj_bench::{Candidate, Subject};
    let Finals {
        small,
        temporal,
        simplified_wgsl,
        composed,
        reproj,
    } = finals;
    let mut candidates = vec![Candidate {
        name: "resize".into(),
        subject: Subject::Shader {
            shader: Box::new(baseline.shader.clone()),
            entry: baseline.entry,
            session: Some(Box::new(small)),
        },
    }];
    if let Some(spec) = temporal {
        candidates.push(Candidate {
            name: "temporal".into(),
            subject: Subject::Upsampled(spec),
        });
    }
    candidates.extend([Candidate {
        name: "simplify".into(),
        subject: Subject::Shader {
            shader: Box::new(reproj_front::parse_shader(
                Path::new("simplified.wgsl"),
                simplified_wgsl.to_string(),
            )?),
            entry: 0,
            session: None,
        },
    }]);
    if let Some(v) = reproj {
        if let Some(spec) = composed {
            candidates.push(Candidate {
                name: temporal::COMPOSED.into(),
                subject: Subject::UpsampledVariant(v.clone(), spec),
            });
        }
        candidates.push(Candidate {
            name: "reproj".into(),
            subject: Subject::Variant(v),
        });
    }
    Ok(reproj_bench::bench(
        renderer,
        baseline,
        session,
        &candidates,
        timing,
        &mut |_| {},
    )?)
}
