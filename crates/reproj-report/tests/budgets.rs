//! The page's lookup (the entry with the largest budget ≤ b) is emit's selector at b, for budgets
//! all over the slider's range and right at and around every threshold. The profile is a real one: marble at
//! 160×120, 16 frames, three nodes (`reproj analyze --delta-n 2,4,8 --holdout 6 --max-nodes 3`).

use reproj_report::budgets::{Records, budgets, select_at};
use reproj_select::Selection;

fn key(s: &Selection) -> Option<(u32, Vec<u32>, String, u32)> {
    match s {
        Selection::Node(c) => Some((c.node_id, c.members.clone(), c.strategy.clone(), c.delta_n)),
        Selection::Original { .. } => None,
    }
}

#[test]
fn the_lookup_is_the_selector_at_every_budget() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/marble_small.profile.json"
    );
    let path = std::path::Path::new(path);
    let profile = reproj_emit::load_profile(path).unwrap();
    let (nodes, sets) =
        reproj_emit::selector_records(&profile, path, reproj_models::Metric::L2).unwrap();
    let recs = Records { nodes, sets };
    let b = budgets(&profile, &recs);
    let [lo, hi] = b.range;
    assert!(lo > 0.0 && hi > lo);
    assert!(b.choices.len() >= 2, "the selection changes over the range");
    assert!(b.entries.windows(2).all(|w| w[0].budget < w[1].budget));
    let mut tried: Vec<f64> = (0..=2000)
        .map(|i| lo * (hi / lo).powf(f64::from(i) / 2000.0))
        .collect();
    for e in &b.entries {
        tried.extend([e.budget, e.budget * (1.0 - 1e-12), e.budget * (1.0 + 1e-12)]);
    }
    let mut changes = 0;
    let mut last = None;
    for budget in tried.into_iter().filter(|x| (lo..=hi).contains(x)) {
        let want = key(&select_at(
            &profile,
            &recs,
            reproj_select::Budget::new(budget).unwrap(),
        ));
        let entry = b.lookup(budget).unwrap();
        let got = entry.choice.map(|i| {
            let c = &b.choices[i];
            (c.node_id, c.members.clone(), c.strategy.clone(), c.delta_n)
        });
        assert_eq!(got, want, "budget {budget}");
        if last.as_ref() != Some(&want) {
            changes += 1;
            last = Some(want);
        }
    }
    assert!(changes >= 3, "{changes}");
}
