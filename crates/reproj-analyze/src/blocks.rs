//! The refresh block size as a measured variant dimension (`analyze --block auto`).
//!
//! Each frame refreshes the k×k blocks whose hashed phase comes up (docs/PASSES.md), so a value
//! the camera carries across block borders meets a new random phase at each border: its age is
//! then no longer bounded by Δn but geometric, and the oldest values — resampled most, blurred
//! most — dominate the error. Larger blocks keep a moving value under one phase for longer, so
//! at the same Δn (the same share of pixels refreshed per frame, the same hit rate) the error is
//! lower; they also make the per-frame refresh count vary more, and may cost coherence on a
//! device. Whether they pay is measured, per node, after its strategy was chosen:
//!
//! 1. the challenger block ([`challenger_block`]: 32, at most an eighth of the frame's shorter
//!    side so that a frame has at least 64 blocks) is replayed at the race's period
//!    ([`race_period`]: the longest training Δn at most half the session, so the refresh shows),
//!    where the base (the strategy's default k) was just replayed;
//! 2. where its error is not lower, the base is kept at once (no race);
//! 3. otherwise both are timed interleaved with the original in one race at that same Δn, and the
//!    challenger is kept unless it is slower than the base beyond doubt (their 95 % intervals
//!    separate, the challenger's below) or slower than the original. Equal speed and lower error
//!    is a better variant at every budget; a kept challenger's node is profiled at its other
//!    periods with the challenger alone.
//!
//! The race costs one replay and one short race per node; `--block K` fixes the size instead.

use reproj_instance::{InstanceOptions, NodeSelector, Strategy};
use reproj_models::profile::{BlockProbe, Measurement, Timed};
use reproj_models::speedup::{SpeedupEstimate, separates};

use crate::AnalyzeError;
use crate::replayer::{RaceEntry, Replayer, finite, timed_candidate};

/// The largest block raced.
pub(crate) const LARGEST: u32 = 32;

/// The block raced against `base` for a frame of `resolution`: [`LARGEST`], but at most an eighth
/// of the shorter side (rounded down to an even size), so that a frame holds at least 8×8 blocks
/// and the refresh is spread over the frame. `None` when that is no larger than `base`.
pub(crate) fn challenger_block(resolution: [u32; 2], base: u32) -> Option<u32> {
    let side = resolution[0].min(resolution[1]) / 8;
    let k = LARGEST.min(side) & !1;
    (k > base).then_some(k)
}

/// The period the blocks are compared at: the longest training period at most half the frames
/// replayed, so that every pixel is refreshed at least twice in the session and the refresh
/// pattern shows in the error (at a period past the session most pixels are never refreshed);
/// the shortest training period when none is that short.
pub(crate) fn race_period(train: &[u32], frames: u32) -> u32 {
    let fits = train
        .iter()
        .copied()
        .filter(|&d| d.saturating_mul(2) <= frames)
        .max();
    fits.or_else(|| train.iter().copied().min()).unwrap_or(2)
}

/// Whether `challenger` is a lower error than `base` (both finite; a NaN is never lower).
fn more_accurate(base: f64, challenger: f64) -> bool {
    challenger.is_finite() && base.is_finite() && challenger < base
}

/// Whether the challenger is kept: its error is lower, and the race says it is neither slower
/// than the base beyond doubt nor slower than the original beyond doubt. Without a base
/// estimate the challenger must be surely faster than the original.
pub(crate) fn challenger_kept(
    base_error: f64,
    challenger_error: f64,
    base: Option<&SpeedupEstimate>,
    challenger: Option<&SpeedupEstimate>,
) -> bool {
    if !more_accurate(base_error, challenger_error) {
        return false;
    }
    let Some(c) = challenger else {
        return false;
    };
    if c.surely_slower() {
        return false;
    }
    match base {
        Some(b) => !(c.speedup < b.speedup && separates(c, b)),
        None => c.surely_faster(),
    }
}

/// A node's variant as its strategy race left it, replayed at the race's period.
pub(crate) struct BlockRace<'a> {
    pub(crate) id: u32,
    pub(crate) sel: NodeSelector,
    pub(crate) strategy: Strategy,
    pub(crate) block: u32,
    pub(crate) base_sources: &'a [String],
    pub(crate) base_variant: &'a reproj_instance::Variant,
    /// The period both blocks are replayed and timed at ([`race_period`]).
    pub(crate) delta_n: u32,
    /// The base's measurement at `delta_n`.
    pub(crate) base: &'a Measurement,
}

/// The challenger, kept: its block, variant and measurement at the race's period.
pub(crate) struct Kept {
    pub(crate) block: u32,
    pub(crate) sources: Vec<String>,
    pub(crate) variant: reproj_instance::Variant,
    pub(crate) measurement: Measurement,
}

/// Race the challenger block against the node's base block (see the module docs), appending the
/// probes to `probes`. `Some`: the challenger is kept and the node's remaining periods are the
/// caller's to replay with it. Reports three progress steps when it races (instance, replay, race).
pub(crate) fn race_block(
    rp: &mut Replayer<'_, '_>,
    race: &BlockRace<'_>,
    probes: &mut Vec<BlockProbe>,
) -> Result<Option<Kept>, AnalyzeError> {
    let (id, dn) = (race.id, race.delta_n);
    let Some(k) = challenger_block(rp.input.session.resolution, race.block) else {
        return Ok(None);
    };
    rp.progress.extend(3);
    let who = format!("node {id}");
    let Some(challenger) = challenger_at(rp, race, k)? else {
        return Ok(None);
    };
    let (base_error, challenger_error) = (race.base.error, challenger.measurement.error);
    let probe = |block: u32, error: f64| BlockProbe {
        node: id,
        reconstruct: None,
        strategy: race.strategy.name().into(),
        block,
        delta_n: dn,
        error: finite(error),
        timed: Timed::default(),
        kept: false,
        note: None,
    };
    if !more_accurate(base_error, challenger_error) {
        rp.progress.step(&format!("{who} blocks"));
        let note = format!(
            "k={k} is no more accurate than k={} at Δn {dn} ({challenger_error:.5} vs {base_error:.5}): not raced, keeps k={}",
            race.block, race.block
        );
        rp.progress.note(&format!("{who}: {note}"));
        probes.push(BlockProbe {
            kept: true,
            ..probe(race.block, base_error)
        });
        probes.push(BlockProbe {
            note: Some(note),
            ..probe(k, challenger_error)
        });
        return Ok(None);
    }
    let base_entry = RaceEntry {
        name: format!("k{}", race.block),
        sources: race.base_sources,
        variant: race.base_variant,
        delta_n: dn,
    };
    let challenger_entry = RaceEntry {
        name: format!("k{k}"),
        sources: &challenger.sources,
        variant: &challenger.variant,
        delta_n: dn,
    };
    // One short race decides (a larger block is kept unless slower beyond doubt).
    let duel = rp.duel(id, "blocks", Some(base_entry), challenger_entry, |_, _| {
        false
    })?;
    let (report, base_estimate, challenger_estimate) = (duel.report, duel.base, duel.challenger);
    let kept = challenger_kept(
        base_error,
        challenger_error,
        base_estimate.as_ref(),
        challenger_estimate.as_ref(),
    );
    let shown = |e: Option<&SpeedupEstimate>| e.map_or_else(|| "untimed".into(), |e| e.display());
    let note = format!(
        "k={k} at Δn {dn}: error {challenger_error:.5}, {} against k={}: {base_error:.5}, {}: {}",
        shown(challenger_estimate.as_ref()),
        race.block,
        shown(base_estimate.as_ref()),
        match &challenger_estimate {
            _ if kept => format!("more accurate and not slower, keeps k={k}"),
            None => format!("untimed, keeps k={}", race.block),
            Some(c) if c.surely_slower() => format!(
                "slower than the original beyond doubt, keeps k={}",
                race.block
            ),
            Some(_) if base_estimate.is_none() => {
                format!(
                    "not faster than the original beyond doubt, keeps k={}",
                    race.block
                )
            }
            Some(_) => format!(
                "slower than k={} beyond doubt, keeps k={}",
                race.block, race.block
            ),
        }
    );
    rp.progress.note(&format!("{who}: {note}"));
    let timed = |p: BlockProbe, i: usize| BlockProbe {
        timed: timed_candidate(&report, i),
        ..p
    };
    probes.push(BlockProbe {
        kept: !kept,
        ..timed(probe(race.block, base_error), 0)
    });
    probes.push(BlockProbe {
        kept,
        note: Some(note),
        ..timed(probe(k, challenger_error), 1)
    });
    Ok(kept.then_some(challenger))
}

/// The challenger block instanced and replayed at the race's period ([`Replayer::challenger_at`]).
fn challenger_at(
    rp: &mut Replayer<'_, '_>,
    race: &BlockRace<'_>,
    k: u32,
) -> Result<Option<Kept>, AnalyzeError> {
    let inst = InstanceOptions {
        strategy: race.strategy,
        block: k,
        ..rp.opts.instance
    };
    let c = rp.challenger_at(
        race.id,
        race.sel,
        &inst,
        race.delta_n,
        &format!("k={k}"),
        &format!("k={}", race.block),
        "blocks",
    )?;
    Ok(c.map(|c| Kept {
        block: k,
        sources: c.sources,
        variant: c.variant,
        measurement: c.measurement,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::replayer::test_estimate as e;

    #[test]
    fn the_challenger_is_32_but_leaves_a_frame_at_least_8_blocks_a_side() {
        assert_eq!(challenger_block([256, 256], 4), Some(32));
        assert_eq!(challenger_block([1920, 1080], 4), Some(32));
        assert_eq!(challenger_block([128, 96], 4), Some(12));
        // Odd eighths round down to an even size (blocks align with 2×2 quads).
        assert_eq!(challenger_block([120, 120], 4), Some(14));
        // Nothing larger than the base to race.
        assert_eq!(challenger_block([32, 32], 4), None);
        assert_eq!(challenger_block([64, 64], 8), None);
        assert_eq!(challenger_block([256, 256], 32), None);
    }

    #[test]
    fn the_race_period_leaves_every_pixel_two_refreshes_in_the_session() {
        let train = [2, 10, 18, 26, 34, 42, 50];
        // marble: 150 frames, the longest training period.
        assert_eq!(race_period(&train, 150), 50);
        // The corpus sessions: 48 frames.
        assert_eq!(race_period(&train, 48), 18);
        assert_eq!(race_period(&train, 20), 10);
        // Shorter than any: the shortest.
        assert_eq!(race_period(&train, 3), 2);
        assert_eq!(race_period(&[], 100), 2);
    }

    /// Marble's node 680, 2pass, Δn 18 on lavapipe (docs/notebook/refresh-block.md): k=4
    /// 2.06× [2.01, 2.11] at 31.51 dB, k=32 2.01× [1.95, 2.09] at 32.62 dB — level in speed,
    /// lower in error: kept.
    #[test]
    fn equal_speed_and_lower_error_keeps_the_larger_block() {
        let (b, c) = (e(2.06, 2.01, 2.11), e(2.01, 1.95, 2.09));
        assert!(challenger_kept(0.01208, 0.01050, Some(&b), Some(&c)));
    }

    #[test]
    fn a_larger_block_slower_beyond_doubt_or_no_more_accurate_is_not_kept() {
        let b = e(2.06, 2.01, 2.11);
        // Slower beyond doubt: the intervals separate, the challenger's below.
        assert!(!challenger_kept(
            0.012,
            0.010,
            Some(&b),
            Some(&e(1.80, 1.75, 1.85))
        ));
        // No more accurate: never kept, whatever its speed.
        assert!(!challenger_kept(
            0.010,
            0.010,
            Some(&b),
            Some(&e(2.5, 2.4, 2.6))
        ));
        assert!(!challenger_kept(0.010, f64::NAN, Some(&b), Some(&b)));
        // Untimed: not kept.
        assert!(!challenger_kept(0.012, 0.010, Some(&b), None));
        // Slower than the original beyond doubt: not kept even against an untimed base.
        assert!(!challenger_kept(
            0.012,
            0.010,
            None,
            Some(&e(0.9, 0.85, 0.95))
        ));
        assert!(challenger_kept(0.012, 0.010, None, Some(&e(1.5, 1.4, 1.6))));
    }
}
