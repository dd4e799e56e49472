//! Finishing a pass module: dead code out, validate, compact, validate again, then WGSL (written
//! by [`reproj_front::write_wgsl`], the one writer) that reaches a fixed point on a round trip;
//! and the file name of each pass.

use super::*;
use reproj_front::wgsl::generated;
use reproj_front::write_wgsl;

/// Turn WGSL's `derivative_uniformity` diagnostic off for the whole module (see the fused entry in
/// [`strategy`]: its recompute branch is uniform over each 2×2 quad, which the analysis cannot see).
pub(crate) fn allow_quad_uniform_derivatives(module: &mut Module) {
    reproj_front::ir::derivative_uniformity_off(module);
}

/// Validate, compact, validate again, write WGSL and run it to a fixed point of the round trip.
pub(crate) fn finish(pass: PassKind, module: Module) -> Result<PassModule, InstanceError> {
    let (module, info, wgsl) =
        finish_module(module, |what| InstanceError::Internal { pass, what })?;
    Ok(PassModule {
        kind: pass,
        module,
        info,
        wgsl,
    })
}

/// Round trips allowed before the WGSL must stop changing. naga's WGSL front end folds one more
/// level of a constant expression on each trip (a helper inlined with literal arguments leaves
/// `d / ((1f + 0.2f) * (1f + 0.2f))`: `1.2f * 1.2f` on the first trip, `1.44f` on the second),
/// so the trips needed grow with how deeply constants nest; each trip that changes the text makes
/// it shorter, so this bound is reached only by a bug.
const MAX_TRIPS: usize = 16;

/// Validate, compact, validate again and write `module` as WGSL that is a fixed point of parse →
/// validate → write within [`MAX_TRIPS`] trips; `internal` makes the error of a step that fails (a
/// bug in reproj).
pub(crate) fn finish_module(
    mut module: Module,
    internal: impl Fn(String) -> InstanceError,
) -> Result<(Module, naga::valid::ModuleInfo, String), InstanceError> {
    let rounds = MAX_TRIPS;
    validator().validate(&module).map_err(|e| {
        internal(format!(
            "does not validate before compaction: {}",
            e.as_inner()
        ))
    })?;
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    let info = validator().validate(&module).map_err(|e| {
        internal(format!(
            "does not validate after compaction: {}",
            e.as_inner()
        ))
    })?;
    let mut text = write_wgsl(&module, &info).map_err(|e| internal(e.to_string()))?;
    // The text may change (names, literal spellings; constants naga folds on parsing) and must
    // then stop changing.
    for round in 0..rounds {
        let reparsed = naga::front::wgsl::parse_str(&text).map_err(|e| {
            internal(format!(
                "written WGSL does not parse: {}",
                e.emit_to_string(&text)
            ))
        })?;
        let reinfo = validator().validate(&reparsed).map_err(|e| {
            internal(format!(
                "written WGSL does not validate: {}",
                e.emit_to_string(&text)
            ))
        })?;
        let again = write_wgsl(&reparsed, &reinfo).map_err(|e| internal(e.to_string()))?;
        if again == text {
            return Ok((reparsed, reinfo, text));
        }
        // naga's namer may rename on every trip (`a_1` becomes `a_1_`, and then the next `a`
        // takes `a_1`): after the first trip, the same program under other names is a fixed
        // point too.
        if round >= 1 && same_up_to_names(&text, &again) {
            return Ok((reparsed, reinfo, text));
        }
        if round + 1 == rounds {
            return Err(internal(format!(
                "the WGSL round trip does not reach a fixed point in {rounds} trips"
            )));
        }
        text = again;
    }
    unreachable!()
}

/// True when `a` and `b` are the same WGSL text but for identifiers renamed one to one, each
/// renaming being one naga's namer makes: the two names differ only in `_` and `_N` suffixes
/// (`a`, `a_1`, `a_1_`, `a_1_1`), or both are names naga's writer invents from expression handles
/// (`_e31` and `_e30`: a trip that folds one more constant numbers the expressions after it
/// anew; such names are local to their function, so each function may renumber them its own
/// way). Keywords, types and built-in functions have no such suffix, so a change of any of them,
/// or of anything else, still counts as a difference.
pub(crate) fn same_up_to_names(a: &str, b: &str) -> bool {
    use std::collections::HashMap;
    fn tokens(s: &str) -> Vec<&str> {
        let mut out = Vec::new();
        let mut rest = s;
        while let Some(c) = rest.chars().next() {
            let len = if c.is_alphanumeric() || c == '_' {
                // A name, or a number with its suffix (`1.5f`, `12u`).
                let number = c.is_ascii_digit();
                rest.find(|d: char| !(d.is_alphanumeric() || d == '_' || (number && d == '.')))
                    .unwrap_or(rest.len())
            } else {
                c.len_utf8()
            };
            if !c.is_whitespace() {
                out.push(&rest[..len]);
            }
            rest = &rest[len..];
        }
        out
    }
    /// The name naga's namer started from: `_` and `_N` suffixes off.
    fn base(name: &str) -> &str {
        let mut s = name;
        loop {
            let mut t = s.trim_end_matches('_');
            if let Some(i) = t.rfind('_')
                && i > 0
                && i + 1 < t.len()
                && t[i + 1..].bytes().all(|b| b.is_ascii_digit())
            {
                t = &t[..i];
            }
            if t == s || t.is_empty() {
                return s;
            }
            s = t;
        }
    }
    let is_name = |t: &str| t.starts_with(|c: char| c.is_alphabetic() || c == '_');
    let (ta, tb) = (tokens(a), tokens(b));
    if ta.len() != tb.len() {
        return false;
    }
    let mut forward: HashMap<&str, &str> = HashMap::new();
    let mut backward: HashMap<&str, &str> = HashMap::new();
    for (x, y) in ta.into_iter().zip(tb) {
        if x == "fn" && y == "fn" {
            // Invented names are numbered per function: each function renames them afresh.
            forward.retain(|k, _| !generated(k));
            backward.retain(|k, _| !generated(k));
        }
        if !is_name(x) || !is_name(y) {
            if x != y {
                return false;
            }
            continue;
        }
        if x != y && base(x) != base(y) && !(generated(x) && generated(y)) {
            return false;
        }
        if *forward.entry(x).or_insert(y) != y || *backward.entry(y).or_insert(x) != x {
            return false;
        }
    }
    true
}

/// File name of a pass's WGSL beside the manifest.
pub fn pass_file(kind: PassKind) -> &'static str {
    match kind {
        PassKind::Reproject => "pass1_reproject.wgsl",
        PassKind::Recompute => "pass2_recompute.wgsl",
        PassKind::Shade => "pass3_shade.wgsl",
        PassKind::Fused => "pass1_fused.wgsl",
        PassKind::ShadeHits => "pass1_shade_hits.wgsl",
        PassKind::ShadeMisses => "pass2_shade_misses.wgsl",
    }
}

#[cfg(test)]
mod tests {
    use super::same_up_to_names;

    #[test]
    fn names_renamed_by_naga_are_the_same_text() {
        let a = "fn f(a: f32) -> f32 { let a_1 = a * 2f; let a_2 = a_1 + 1f; return a_2; }";
        let b = "fn f(a: f32) -> f32 { let a_1_ = a * 2f; let a_1_1 = a_1_ + 1f; return a_1_1; }";
        assert!(same_up_to_names(a, b));
    }

    #[test]
    fn renumbered_expression_names_are_the_same_text() {
        // One more constant folded on a trip numbers the later expressions one lower.
        let a = "fn f(t: vec2<i32>) -> f32 { let _e31 = t.x; let _e33 = t.y; return f32(_e31 + _e33); }";
        let b = "fn f(t: vec2<i32>) -> f32 { let _e30 = t.x; let _e32 = t.y; return f32(_e30 + _e32); }";
        assert!(same_up_to_names(a, b));
        // Still one to one: two names merged into one is a difference.
        let c = "fn f(t: vec2<i32>) -> f32 { let _e30 = t.x; let _e30 = t.y; return f32(_e30 + _e30); }";
        assert!(!same_up_to_names(a, c));
        // An invented name is not interchangeable with the shader's own.
        let d = "fn f(t: vec2<i32>) -> f32 { let x = t.x; let _e32 = t.y; return f32(x + _e32); }";
        assert!(!same_up_to_names(a, d));
        // Each function numbers its own: one shifted down, the other up.
        let two = |n: [u32; 2]| {
            format!(
                "fn f(t: i32) -> i32 {{ let _e{} = t; return _e{0}; }} fn g(t: i32) -> i32 {{ let _e{} = t; return _e{1}; }}",
                n[0], n[1]
            )
        };
        assert!(same_up_to_names(&two([5, 5]), &two([4, 6])));
    }

    #[test]
    fn other_changes_are_differences() {
        let a = "fn f(a: f32) -> f32 { let a_1 = a * 2f; return a_1; }";
        // Another operator, another literal, another type, another name, two names merged.
        for b in [
            "fn f(a: f32) -> f32 { let a_1 = a + 2f; return a_1; }",
            "fn f(a: f32) -> f32 { let a_1 = a * 3f; return a_1; }",
            "fn f(a: f16) -> f32 { let a_1 = a * 2f; return a_1; }",
            "fn f(a: f32) -> f32 { let b_1 = a * 2f; return b_1; }",
            "fn f(a: f32) -> f32 { let a = a * 2f; return a; }",
        ] {
            assert!(!same_up_to_names(a, b), "{b}");
        }
    }
}
