//! Equal time between reproj and resizing, decided: where `compare`'s final interleaved run leaves
//! the answer undecided (the two further apart than `CompareOptions::equal_time`, the faster with
//! the larger error), reproj moves along its own node's curve to resizing's measured speed and
//! every method is timed again.

use std::path::Path;

use reproj_models::Profile;

use crate::{
    CompareError, CompareInput, CompareOptions, Ctx, MethodResult, Methods, Target, reproj,
};

/// Resizing's and reproj's speedups in the final run, `(resize, reproj)`, where that run leaves
/// the comparison undecided at a target speedup ([`undecided`]; `None` under an error budget,
/// without reproj, or without a figure). Each search lands within its tolerance (5 %) of the
/// target by its own short race, whose noise is ±6–8 % on lavapipe, so the two can stand 10 % apart
/// and more; near reproj's ceiling a few percent of speed cost decibels: on marble at 2.5× reproj's
/// steering took Δn 50 on a race that said 2.47×, the final run said 2.60× against resizing's
/// 2.43×, and reproj lost 2.7 dB while 7 % faster.
pub(crate) fn apart(
    timed: &reproj_bench::BenchReport,
    results: &[MethodResult],
    opts: &CompareOptions,
) -> Option<(f64, f64)> {
    if !matches!(opts.target, Target::Speedup(_)) {
        return None;
    }
    let speed = |name: &str| {
        Some(
            timed
                .estimate(timed.candidates.iter().position(|c| c.name == name)?)?
                .speedup,
        )
    };
    let error = |name: &str| Some(results.iter().find(|r| r.method == name)?.scores.error);
    let (resize, reproj) = (
        (speed("resize")?, error("resize")?),
        (speed("reproj")?, error("reproj")?),
    );
    undecided(resize, reproj, opts.equal_time).then_some((resize.0, reproj.0))
}

/// Whether two methods' `(speedup, error)` leave it undecided which is better: further apart in
/// speed than `margin` (a fraction), the faster one with the larger error. One faster and no worse
/// (or slower and no better) is decided; within the margin they are at equal time.
fn undecided(a: (f64, f64), b: (f64, f64), margin: f64) -> bool {
    let apart = (b.0 / a.0).ln().abs() > (1.0 + margin).ln();
    let (fast, slow) = if b.0 > a.0 { (b, a) } else { (a, b) };
    apart && fast.1 > slow.1
}

/// reproj moved to resizing's speed in the final run (`apart`: both measured in the same rounds,
/// which is what "at equal time" asks): the reported node's (or set's) own period for that speed
/// (`reproj::along`), its models scaled by how far they were off for the reported point in that
/// run (48 rounds, not a search race's 8).
/// Where that is another point, it is rendered and scored and replaces the reported one, and
/// `true` says every method is to be timed again; `reproj.rematch` records it either way.
pub(crate) fn rematch(
    ctx: &Ctx,
    input: &CompareInput,
    opts: &CompareOptions,
    (profile, path): (&Profile, &Path),
    m: &mut Methods,
    (resize, reproj_speedup): (f64, f64),
    mid: usize,
) -> Result<bool, CompareError> {
    let detail = m
        .reproj
        .as_mut()
        .expect("apart found reproj in the final run");
    let ask = resize * detail.predicted_speedup / reproj_speedup;
    let Some(planned) = reproj::along(profile, detail, ask, opts.max_delta_n) else {
        return Ok(false);
    };
    let mut rematched = reproj::Rematch {
        to_speedup: resize,
        from_speedup: reproj_speedup,
        asked: ask,
        moved: false,
    };
    if planned.same_point(detail) {
        detail.rematch = Some(rematched);
        return Ok(false);
    }
    let first_tries = std::mem::take(&mut detail.tries);
    let r = reproj::reproj(
        ctx,
        input.loaded,
        (profile, path),
        &planned,
        first_tries,
        mid as u32,
    )?;
    let mut detail = r.detail;
    rematched.moved = true;
    detail.rematch = Some(rematched);
    m.reproj = Some(detail);
    if let Some(slot) = m.results.iter_mut().find(|x| x.method == "reproj") {
        *slot = r.result;
    }
    if let Some(slot) = m.crop_frames.iter_mut().find(|(name, _)| name == "reproj") {
        slot.1 = r.crop_frame;
    }
    m.reproj_input = Some(r.input);
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// marble at 2.5×: reproj 2.60× at 0.0178 against resizing 2.43× at 0.0163 is undecided;
    /// faster and better, or within 3 %, is decided.
    #[test]
    fn an_undecided_comparison_is_one_the_faster_pays_for_in_error() {
        let resize = (2.43, 0.0163);
        assert!(undecided(resize, (2.60, 0.0178), 0.03));
        assert!(undecided((2.60, 0.0178), resize, 0.03));
        assert!(
            !undecided(resize, (2.60, 0.0100), 0.03),
            "faster and better"
        );
        assert!(!undecided(resize, (2.30, 0.0200), 0.03), "slower and worse");
        assert!(undecided(resize, (1.78, 0.0030), 0.03), "slower and better");
        assert!(
            !undecided(resize, (2.48, 0.0178), 0.03),
            "within the margin"
        );
    }
}
