//! Arbitrary text as a profile (`NAME.profile.json`): the versioned-JSON reader, the numbers
//! checked as data (`Profile::check`), then what `emit`, `report` and `compare` do with a profile
//! without a GPU: the selector's records per node and metric, the selection (with the measured
//! sets), the Pareto frontier, set predictions over pairs of nodes, the MSE interpolation, and a
//! write → read round trip. Errors are fine; a panic is a bug.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use reproj_models::profile::NodeStatus;
use reproj_models::{Metric, PROFILE_KIND, Profile};
use reproj_select::{
    NodeRecord, SelectOptions, SetRecord, best_set, candidates, pareto, select, select_with_sets,
};

/// Δn ranges `emit` accepts (the default, the extremes, an empty one).
const RANGES: [(u32, u32); 4] = [(2, 50), (1, 1), (1, 200), (7, 3)];

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let profile = match reproj_io::parse_json::<Profile>(text, Path::new("p.json"), &PROFILE_KIND) {
        Ok(p) => p,
        Err(e) => {
            let _ = e.to_string();
            return;
        }
    };
    if let Err((field, message)) = profile.check() {
        let _ = format!("{field}: {message}");
        return;
    }

    // A profile `reproj` writes reads back as the same profile.
    let written = serde_json::to_string_pretty(&profile).expect("a profile serializes");
    let again: Profile = reproj_io::parse_json(&written, Path::new("p.json"), &PROFILE_KIND)
        .unwrap_or_else(|e| panic!("a written profile does not read back: {e}\n{written}"));
    assert!(
        again == profile,
        "a profile changes through a write and a read\n{written}"
    );

    for metric in Metric::ALL {
        let usable: Vec<_> = profile
            .nodes
            .iter()
            .filter(|n| n.status == NodeStatus::Ok)
            .collect();
        let records: Vec<NodeRecord> = profile
            .nodes
            .iter()
            .filter_map(|n| NodeRecord::from_profile(&profile, n, metric))
            .collect();
        let sets: Vec<SetRecord> = profile
            .sets
            .iter()
            .filter_map(|s| {
                Some(SetRecord {
                    members: s.members.clone(),
                    texts: s.texts.clone(),
                    strategy: s.strategy.clone(),
                    error: s.fit(metric)?.clone(),
                    timing: s.timing_fit.clone(),
                    mean_pixels: profile.original.mean_pixels,
                    measured_errors: reproj_select::measured_errors(&s.measurements, metric),
                })
            })
            .collect();
        for n in &usable {
            for dn in [0, 1, 2, 5, 50, u32::MAX] {
                let _ = n.mse_at(dn);
            }
            let _ = n.fit(metric);
        }
        for s in &profile.sets {
            let _ = s.name();
            let _ = s.mse_at(4);
        }
        for &(min, max) in &RANGES {
            for max_error in [0.0, 0.01, 1.0, f64::MAX] {
                let max_error = reproj_select::Budget::new(max_error).expect("a valid budget");
                let opts = SelectOptions {
                    max_error,
                    min_delta_n: min,
                    max_delta_n: max,
                };
                let _ = select(
                    &records,
                    &profile.hit_rate,
                    profile.original.frame_ms,
                    &opts,
                );
                let _ = select_with_sets(
                    &records,
                    &sets,
                    &profile.hit_rate,
                    profile.original.frame_ms,
                    &opts,
                );
            }
            let _ = pareto(&records, &profile.hit_rate, min, max);
            let _ = candidates(&records, &profile.hit_rate, min, max);
        }
        // What the set search predicts for pairs of nodes (bounded: the first few).
        let first: Vec<&NodeRecord> = records.iter().take(6).collect();
        for (i, a) in first.iter().enumerate() {
            for b in &first[i + 1..] {
                let _ = best_set(
                    &[a, b],
                    &profile.hit_rate,
                    profile.original.frame_ms,
                    0.05,
                    (2, 50),
                );
            }
        }
    }
});
