//! `merge`: join the profiles of `analyze --shard i/N` runs into the profile one unsharded run
//! writes. Shards are refused unless they profiled the same shader and session with the same
//! settings on the same adapter, and together cover every shard index exactly once.
//!
//! The nodes, their fits and the strategy probes are per node and carry over; the hit-rate model is
//! fitted once per shader and session, so it is fitted again over every shard's measurements, and
//! the held-out frame-time predictions (which use it) are recomputed. The original's record is shard
//! 0's; the analysis times add up (machine time spent).

use std::path::PathBuf;

use reproj_models::profile::AnalysisTime;
use reproj_models::{Profile, predicted_frame_ms};

use crate::AnalyzeError;

/// Join shard profiles (with the files they came from, for messages).
pub fn merge(shards: &[(PathBuf, Profile)]) -> Result<Profile, AnalyzeError> {
    let refuse = |message: String| Err(AnalyzeError::Options(message));
    let Some((first_path, first)) = shards.first() else {
        return refuse("merge needs the shard profiles to join".into());
    };
    let Some(count) = first.shard.map(|s| s.count) else {
        return refuse(format!(
            "{} is not a shard (it was not written by `analyze --shard i/N`)",
            first_path.display()
        ));
    };
    // Everything that must agree, by field name.
    let identity = |p: &Profile| -> Vec<(&'static str, String)> {
        vec![
            ("version", p.version.to_string()),
            ("shader.hash", p.shader.hash.clone()),
            ("entry", p.entry.clone()),
            ("unroll", p.unroll.to_string()),
            ("shader_input", format!("{:?}", p.shader_input)),
            ("session.hash", p.session.hash.clone()),
            ("machine.adapter", p.machine.adapter.clone()),
            ("machine.driver", format!("{:?}", p.machine.driver)),
            ("machine.timing_method", p.machine.timing_method.clone()),
            ("resolution", format!("{:?}", p.resolution)),
            ("frames", p.frames.to_string()),
            ("delta_n_train", format!("{:?}", p.delta_n_train)),
            ("delta_n_holdout", format!("{:?}", p.delta_n_holdout)),
            ("block", p.block.to_string()),
            ("perceptual_stride", format!("{:?}", p.perceptual_stride)),
            ("depth_epsilon", p.depth_epsilon.to_string()),
            (
                "shard.count",
                p.shard.map_or("none".into(), |s| s.count.to_string()),
            ),
        ]
    };
    let reference = identity(first);
    let mut seen = vec![None::<&PathBuf>; count as usize];
    for (path, p) in shards {
        for ((field, a), (_, b)) in reference.iter().zip(identity(p)) {
            if *a != b {
                return refuse(format!(
                    "cannot merge {} with {}: they differ in `{field}` ({a} vs {b}); shards must profile the same shader and session with the same settings on the same adapter",
                    first_path.display(),
                    path.display()
                ));
            }
        }
        let index = p.shard.expect("shard.count agreed").index as usize;
        // A hand-edited or corrupt profile may name a shard past the count: refused, not indexed.
        if index >= seen.len() {
            return refuse(format!(
                "{}: field `shard.index`: {index} is not below `shard.count` {count} (shards are numbered 0 to count - 1)",
                path.display()
            ));
        }
        if let Some(other) = seen[index] {
            return refuse(format!(
                "{} and {} are both shard {index}/{count}",
                other.display(),
                path.display()
            ));
        }
        seen[index] = Some(path);
    }
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(i, _)| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        return refuse(format!("missing shard(s) {}", missing.join(", ")));
    }

    let mut sorted: Vec<&Profile> = shards.iter().map(|(_, p)| p).collect();
    sorted.sort_by_key(|p| p.shard.map(|s| s.index));
    let mut merged = sorted[0].clone();
    merged.shard = None;
    merged.nodes = sorted
        .iter()
        .flat_map(|p| p.nodes.iter().cloned())
        .collect();
    merged.nodes.sort_by_key(|n| n.id);
    if let Some(w) = merged.nodes.windows(2).find(|w| w[0].id == w[1].id) {
        return refuse(format!("node {} is in two shards", w[0].id));
    }
    merged.strategy_probes = sorted
        .iter()
        .flat_map(|p| p.strategy_probes.iter().cloned())
        .collect();
    merged.strategy_probes.sort_by_key(|p| p.node);
    merged.filter_probes = sorted
        .iter()
        .flat_map(|p| p.filter_probes.iter().cloned())
        .collect();
    merged.filter_probes.sort_by_key(|p| p.node);
    merged.block_probes = sorted
        .iter()
        .flat_map(|p| p.block_probes.iter().cloned())
        .collect();
    merged.block_probes.sort_by_key(|p| p.node);
    merged.time = sorted
        .iter()
        .fold(AnalysisTime::default(), |t, p| AnalysisTime {
            total_s: t.total_s + p.time.total_s,
            reference_s: t.reference_s + p.time.reference_s,
            rendering_s: t.rendering_s + p.time.rendering_s,
            readback_and_error_s: t.readback_and_error_s + p.time.readback_and_error_s,
            fitting_s: t.fitting_s + p.time.fitting_s,
            instancing_s: t.instancing_s + p.time.instancing_s,
            timing_s: t.timing_s + p.time.timing_s,
        });
    merged.hit_rate = crate::replayer::fit_session_hit_rate(
        merged.nodes.iter().flat_map(|n| &n.measurements),
        &merged.delta_n_train,
    );
    let mean_pixels = merged.original.mean_pixels;
    for n in &mut merged.nodes {
        for h in &mut n.holdout {
            h.predicted_ms = predicted_frame_ms(
                &n.timing_fit,
                &merged.hit_rate,
                h.delta_n as f64,
                mean_pixels,
            )
            .filter(|v| v.is_finite());
        }
    }
    Ok(merged)
}
