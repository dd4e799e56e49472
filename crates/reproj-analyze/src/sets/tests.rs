use std::cell::RefCell;

use reproj_models::{ErrorFit, ErrorFitStatus, TimingFit};
use reproj_select::combined_timing;

use super::*;

const M: f64 = 500_000.0;
/// The original: 10 ms per frame (0.5 ms overhead + M · 1.9e-5 ms).
const ORIGINAL_MS: f64 = 10.0;

fn error_fit(alpha: f64) -> ErrorFit {
    ErrorFit {
        alpha: Some(alpha),
        lambda: Some(0.1),
        r2: Some(1.0),
        rms_residual: Some(0.0),
        n_samples: 7,
        iterations: 0,
        status: ErrorFitStatus::Ok,
    }
}

/// A candidate whose hit costs `hit_ms` per pixel (the original: 1.9e-5).
fn cand(id: u32, hit_ms: f64, components: u32, inside: &[u32]) -> SetCandidate {
    SetCandidate {
        record: NodeRecord {
            id,
            text: format!("n{id}"),
            strategy: "3pass".into(),
            error: error_fit(0.001),
            timing: TimingFit::from_costs(hit_ms, 2.0e-5, 0.5, M),
            mean_pixels: M,
            measured: None,
            measured_errors: Vec::new(),
        },
        components,
        block: 8,
        inside: inside.to_vec(),
    }
}

#[derive(Default)]
struct Notes(RefCell<Vec<String>>);

impl Progress for Notes {
    fn start(&self, _: u64) {}
    fn step(&self, _: &str) {}
    fn note(&self, line: &str) {
        self.0.borrow_mut().push(line.to_string());
    }
    fn finish(&self) {}
}

/// A measured set: its models are its members' combined ones, its time at Δn = 50 is
/// `ms(members)`.
fn fake(members: &[&SetCandidate], ms: f64) -> SetProfile {
    let records: Vec<&NodeRecord> = members.iter().map(|c| &c.record).collect();
    let m: Measurement = serde_json::from_value(serde_json::json!({
        "delta_n": 50, "error": 0.001, "psnr": null, "hit_rate": 0.9, "frame_ms": ms,
        "frames": []
    }))
    .unwrap();
    SetProfile {
        members: members.iter().map(|c| c.record.id).collect(),
        texts: members.iter().map(|c| c.record.text.clone()).collect(),
        strategy: "3pass".into(),
        block: 8,
        measurements: vec![m],
        predicted: Vec::new(),
        error_fit: error_fit(0.001 * members.len() as f64),
        flip_fit: None,
        dssim_fit: None,
        timing_fit: combined_timing(&records, ORIGINAL_MS).unwrap(),
        holdout: Vec::new(),
        status: NodeStatus::Ok,
    }
}

fn search(
    cands: &[SetCandidate],
    opts: &SetSearchOptions,
    ms: impl Fn(&[u32]) -> f64,
) -> (Vec<SetProfile>, Vec<Vec<u32>>, Vec<String>) {
    let hit_rate = HitRateFit::from_mu(0.9);
    let ctx = SetContext {
        hit_rate: &hit_rate,
        original_ms: ORIGINAL_MS,
        delta_n: 50,
    };
    let notes = Notes::default();
    let mut replayed = Vec::new();
    let mut measure = |members: &[&SetCandidate]| {
        let ids: Vec<u32> = members.iter().map(|c| c.record.id).collect();
        replayed.push(ids.clone());
        Ok(fake(members, ms(&ids)))
    };
    let sets = search_sets(cands, &ctx, opts, &mut measure, &notes).unwrap();
    (sets, replayed, notes.0.into_inner())
}

#[test]
fn nested_and_wide_pairs_are_not_formed() {
    // 1 holds 2 (nested); 1 and 3 are vec3s (6 floats together).
    let cands = [
        cand(1, 2e-6, 3, &[2]),
        cand(2, 1e-5, 1, &[]),
        cand(3, 4e-6, 3, &[]),
    ];
    let opts = SetSearchOptions {
        replays: 10,
        max_nodes: 2,
        ..Default::default()
    };
    let (sets, replayed, _) = search(&cands, &opts, |_| 5.0);
    assert_eq!(replayed, [vec![3, 2]], "only the pair that is neither");
    assert_eq!(sets.len(), 1);
    // Predictions are recorded at the measured periods.
    assert_eq!(sets[0].predicted.len(), 1);
    assert!(sets[0].predicted[0].frame_ms.is_some());

    // Nothing possible: one line, nothing replayed or recorded.
    let (sets, replayed, notes) = search(&cands[..2], &opts, |_| 5.0);
    assert!(sets.is_empty() && replayed.is_empty());
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].contains("no pair possible") && notes[0].contains("1 nested"),
        "{notes:?}"
    );
}

#[test]
fn pairs_are_ranked_by_the_combined_prediction() {
    let cands = [
        cand(1, 1.4e-5, 1, &[]),
        cand(2, 1.1e-5, 1, &[]),
        cand(3, 1.2e-5, 1, &[]),
        cand(4, 1.6e-5, 1, &[]),
        // Slower than the original: never a candidate.
        cand(5, 3e-5, 1, &[]),
    ];
    let opts = SetSearchOptions {
        replays: 2,
        max_nodes: 2,
        ..Default::default()
    };
    let (_, replayed, _) = search(&cands, &opts, |_| 5.0);
    // The cheapest hits together first; payload order by saving.
    assert_eq!(replayed, [vec![2, 3], vec![2, 1]]);
    // Only the top K by saving pair up.
    let top2 = SetSearchOptions {
        top: 2,
        replays: 10,
        max_nodes: 2,
    };
    let (_, replayed, _) = search(&cands, &top2, |_| 5.0);
    assert_eq!(replayed, [vec![2, 3]]);
}

#[test]
fn a_set_aside_pair_is_recorded_and_never_grown() {
    let cands = [
        cand(1, 1.6e-5, 1, &[]),
        cand(2, 1.7e-5, 1, &[]),
        cand(3, 1.8e-5, 1, &[]),
    ];
    let opts = SetSearchOptions {
        replays: 1,
        ..Default::default()
    };
    let hit_rate = HitRateFit::from_mu(0.9);
    let ctx = SetContext {
        hit_rate: &hit_rate,
        original_ms: ORIGINAL_MS,
        delta_n: 50,
    };
    let notes = Notes::default();
    // Slower than the original: the replay sets it aside.
    let mut measure = |members: &[&SetCandidate]| {
        let mut set = fake(members, 12.0);
        set.status = NodeStatus::SetAside {
            reason: "slower than the original".into(),
        };
        Ok(set)
    };
    let sets = search_sets(&cands, &ctx, &opts, &mut measure, &notes).unwrap();
    assert_eq!(sets.len(), 1);
    assert!(matches!(sets[0].status, NodeStatus::SetAside { .. }));
    let notes = notes.0.into_inner();
    assert!(
        notes.last().unwrap().contains("no pair was usable"),
        "{notes:?}"
    );
}

#[test]
fn growth_stops_when_not_measured_faster_or_at_the_limit() {
    // Savings that add without reaching the whole shader's cost.
    let cands = [
        cand(1, 1.6e-5, 1, &[]),
        cand(2, 1.7e-5, 1, &[]),
        cand(3, 1.8e-5, 1, &[]),
        cand(4, 1.85e-5, 1, &[]),
    ];
    let one = SetSearchOptions {
        replays: 1,
        ..Default::default()
    };
    // The triple measures slower than the pair: growth stops there.
    let (sets, replayed, notes) = search(&cands, &one, |ids| 4.0 + ids.len() as f64);
    assert_eq!(replayed, [vec![1, 2], vec![1, 2, 3]]);
    assert_eq!(sets.len(), 2);
    assert!(notes.last().unwrap().contains("growth stops"), "{notes:?}");
    // Measured faster: grows to the limit (4 floats hold 4 scalars; 3 nodes by default).
    let (_, replayed, _) = search(&cands, &one, |ids| 6.0 - ids.len() as f64);
    assert_eq!(replayed, [vec![1, 2], vec![1, 2, 3]]);
    let four = SetSearchOptions {
        replays: 1,
        max_nodes: 4,
        ..Default::default()
    };
    let (_, replayed, _) = search(&cands, &four, |ids| 6.0 - ids.len() as f64);
    assert_eq!(replayed.last().unwrap(), &vec![1, 2, 3, 4]);
    // A vec3 pair member leaves no room for a third node.
    let wide = [
        cand(1, 1.6e-5, 3, &[]),
        cand(2, 1.7e-5, 1, &[]),
        cand(3, 1.8e-5, 1, &[]),
    ];
    let (_, replayed, notes) = search(&wide, &one, |ids| 6.0 - ids.len() as f64);
    assert_eq!(replayed, [vec![1, 2]]);
    assert!(
        notes.last().unwrap().contains("grows no further"),
        "{notes:?}"
    );
}
