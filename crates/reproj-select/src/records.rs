//! A profile as the selector sees it: its usable nodes and sets as records. One builder, so that
//! `emit`, the report's slider and the charts' marks choose from the same things.

use crate::{NodeRecord, SetRecord, measured_errors};

/// A profile's usable nodes and sets as the selector's records (status ok), kept by `strategy` (a
/// pass layout's name) and `keep_node`; sets only where `sets`. The one way `emit`, `report` and
/// the charts build what they choose from. `Err` names the first usable node with no model for
/// `metric` (a profile made before that metric was recorded).
pub fn profile_records(
    profile: &reproj_models::Profile,
    metric: reproj_models::Metric,
    strategy: Option<&str>,
    keep_node: &dyn Fn(&reproj_models::profile::NodeProfile) -> bool,
    sets: bool,
) -> Result<ProfileRecords, u32> {
    use reproj_models::profile::NodeStatus;
    let usable: Vec<_> = profile
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Ok)
        .filter(|n| strategy.is_none_or(|s| s == n.strategy))
        .filter(|n| keep_node(n))
        .collect();
    if let Some(n) = usable.iter().find(|n| n.fit(metric).is_none()) {
        return Err(n.id);
    }
    let nodes = usable
        .iter()
        .filter_map(|n| NodeRecord::from_profile(profile, n, metric))
        .collect();
    let set_records = profile
        .sets
        .iter()
        .filter(|s| s.status == NodeStatus::Ok)
        .filter(|s| strategy.is_none_or(|st| st == s.strategy))
        .filter(|_| sets)
        .filter_map(|s| {
            Some(SetRecord {
                members: s.members.clone(),
                texts: s.texts.clone(),
                strategy: s.strategy.clone(),
                error: s.fit(metric)?.clone(),
                timing: s.timing_fit.clone(),
                mean_pixels: profile.original.mean_pixels,
                measured_errors: measured_errors(&s.measurements, metric),
            })
        })
        .collect();
    Ok(ProfileRecords {
        nodes,
        sets: set_records,
    })
}

/// What [`profile_records`] builds.
#[derive(Debug, Clone)]
pub struct ProfileRecords {
    pub nodes: Vec<NodeRecord>,
    pub sets: Vec<SetRecord>,
}
