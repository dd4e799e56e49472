//! [`carry`]: a profile's records taken to a session of other motion (the time warp), the motion
//! exponent fitted across profiles (and their segments), and the manifest's run-time schedule.

use reproj_models::motion::{
    ExponentSource, Motion, MotionExponent, MotionRange, STATIC_PIXELS, fit_exponent, period_scale,
};
use reproj_select::motion::{Profiled, cross_predictions};
use reproj_select::{NodeRecord, SetRecord};
use serde::{Deserialize, Serialize};

use super::Segment;

/// The session a variant is meant for, when it is not one of the profiled ones (`emit --verify
/// --session NEW`): its name and motion.
#[derive(Debug, Clone)]
pub struct TargetSession {
    pub name: String,
    /// Its content hash (`reproj_models::content_hash` of the file): the same file as a profiled
    /// session needs no carrying over.
    pub hash: String,
    pub motion: Motion,
}

/// One session's motion as `emit` reports it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SessionMotion {
    pub session: String,
    pub pixels_per_frame: f64,
    pub view_deg_per_frame: f64,
}

/// What `emit` knew of motion (`report.json`'s `motion`, report version 4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MotionReport {
    /// Each profiled session's motion (`null` entries are left out: profiles before version 8).
    pub profiled: Vec<SessionMotion>,
    /// The session the choice was carried to, when one was given that no profile covers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<SessionMotion>,
    /// The profile it was carried from (the nearest in motion) and the factor on the period's
    /// age, `r = (target / profiled)^β`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub carried_from: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub period_scale: Option<f64>,
    /// The motion exponent, where it came from, and what it rests on.
    pub exponent: MotionExponent,
    /// Segments of the profiled sessions (a slower and a faster half of each session of uneven
    /// motion, profile version 9) the exponent was fitted on, in place of their whole sessions.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub segments: usize,
    /// The target's predicted error for the choice (in the budget's metric), before rendering.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_predicted_error: Option<f64>,
    /// Said to the user: a target outside the profiled motions, an assumed exponent.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// One profiled session for [`carry`]: its name, content hash, motion and records.
#[derive(Debug, Clone, Copy)]
pub struct ProfiledSession<'a> {
    pub name: &'a str,
    pub hash: &'a str,
    pub motion: Option<&'a Motion>,
    pub nodes: &'a [NodeRecord],
    pub sets: &'a [SetRecord],
    /// Its slower and faster halves ([`segments`](super::segments); empty: none usable).
    pub segments: &'a [Segment],
}

/// A profile's records carried to the target's motion: the extra scene `emit` selects over.
#[derive(Debug, Clone)]
pub struct Carried {
    /// Index of the profiled session it comes from.
    pub from: usize,
    pub nodes: Vec<NodeRecord>,
    pub sets: Vec<SetRecord>,
}

/// Fit the motion exponent across the profiled sessions, and carry the nearest one (in log
/// motion) to `target` when it is given and is none of them. The report says what was done and
/// warns where the prediction rests on less than a measurement: a target outside the profiled
/// motions, an exponent assumed rather than fitted, a profile without motion.
pub fn carry(
    profiled: &[ProfiledSession<'_>],
    target: Option<&TargetSession>,
) -> (MotionReport, Option<Carried>) {
    let with_motion: Vec<(usize, f64)> = profiled
        .iter()
        .enumerate()
        .filter_map(|(i, p)| Some((i, p.motion?.pixels_per_frame)))
        .collect();
    // Segments of one session (a slower and a faster half) stand for their profile where they
    // exist: they also tell how the error follows motion, from one session alone.
    let segmented = profiled.iter().any(|p| !p.segments.is_empty());
    let fit_input: Vec<Profiled> = with_motion
        .iter()
        .filter(|&&(i, _)| !segmented || profiled[i].segments.is_empty())
        .map(|&(i, m)| Profiled {
            motion: m,
            nodes: profiled[i].nodes,
        })
        .chain(profiled.iter().flat_map(|p| {
            p.segments.iter().map(|s| Profiled {
                motion: s.motion,
                nodes: &s.nodes,
            })
        }))
        .collect();
    let exponent = fit_exponent(|beta| cross_predictions(&fit_input, beta));
    let segments = profiled.iter().map(|p| p.segments.len()).sum();
    let mut report = MotionReport {
        profiled: profiled
            .iter()
            .filter_map(|p| {
                Some(SessionMotion {
                    session: p.name.to_string(),
                    pixels_per_frame: p.motion?.pixels_per_frame,
                    view_deg_per_frame: p.motion?.view_deg_per_frame,
                })
            })
            .collect(),
        target: None,
        carried_from: None,
        period_scale: None,
        exponent,
        segments,
        target_predicted_error: None,
        warnings: Vec::new(),
    };
    let Some(target) = target else {
        return (report, None);
    };
    if profiled.iter().any(|p| p.hash == target.hash) {
        return (report, None);
    }
    report.target = Some(SessionMotion {
        session: target.name.clone(),
        pixels_per_frame: target.motion.pixels_per_frame,
        view_deg_per_frame: target.motion.view_deg_per_frame,
    });
    let m = target.motion.pixels_per_frame;
    let log_distance = |p: f64| (p.max(STATIC_PIXELS) / m.max(STATIC_PIXELS)).ln().abs();
    let Some(&(from, from_motion)) = with_motion
        .iter()
        .min_by(|a, b| log_distance(a.1).total_cmp(&log_distance(b.1)))
    else {
        report.warnings.push(format!(
            "the profile records no motion (made before profile version 8): {} cannot be predicted for its own motion; re-run `reproj analyze`",
            target.name
        ));
        return (report, None);
    };
    let range = MotionRange::of(with_motion.iter().map(|p| p.1)).expect("one motion at least");
    if !range.covers(m) {
        report.warnings.push(format!(
            "{} moves {m:.2} px/frame, outside the profiled {:.2}–{:.2} px/frame: its prediction is carried beyond what was measured; profile a session like it (`analyze --session`) to be sure",
            target.name,
            range.min,
            range.max
        ));
    }
    if report.exponent.source == ExponentSource::Assumed
        && log_distance(from_motion) > 0.1f64.ln_1p()
    {
        report.warnings.push(
            "how the error follows motion is assumed (β = 1: proportional), not fitted: profile two sessions of different motion to fit it"
                .into(),
        );
    }
    let r = period_scale(from_motion, m, report.exponent.beta);
    let source = &profiled[from];
    report.carried_from = Some(source.name.to_string());
    report.period_scale = Some(r);
    let carried = Carried {
        from,
        nodes: source.nodes.iter().map(|n| n.at_motion(r)).collect(),
        sets: source.sets.iter().map(|s| s.at_motion(r)).collect(),
    };
    (report, Some(carried))
}

/// The manifest's run-time Δn schedule (`params.schedule`) for a chosen node or set, from its
/// record in each profiled session (`per_profile`: that profile's motion and record, either
/// missing where the profile lacks it) and the motion exponent `beta`
/// ([`reproj_select::motion::schedule`]).
pub fn manifest_schedule(
    per_profile: impl IntoIterator<Item = (Option<f64>, Option<NodeRecord>)>,
    beta: f64,
    opts: &reproj_select::SelectOptions,
) -> Vec<reproj_instance::DeltaNBand> {
    let found: Vec<(f64, NodeRecord)> = per_profile
        .into_iter()
        .filter_map(|(m, r)| Some((m?, r?)))
        .collect();
    let refs: Vec<(f64, &NodeRecord)> = found.iter().map(|(m, r)| (*m, r)).collect();
    reproj_select::motion::schedule(&refs, beta, opts)
        .into_iter()
        .map(|(up_to, delta_n)| reproj_instance::DeltaNBand {
            up_to_pixels_per_frame: up_to,
            delta_n,
        })
        .collect()
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}
