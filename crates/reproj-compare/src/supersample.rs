//! A fair reference for methods that antialias: the original rendered `n` times, each with its
//! own fixed sub-pixel offset (Halton (2, 3), as the temporal upsampler's jitter), averaged — the
//! image a temporal method converges toward. Scoring only against the one-sample original would
//! punish the better-looking method. And which frames move: history methods ghost on motion,
//! reproj misses on disocclusion, so the figures are split into still and moving frames.

use reproj_front::Shader;
use reproj_replay::jitter::halton_offset;
use reproj_replay::{Jitter, RenderOptions, Renderer};
use reproj_scene::Session;

use crate::CompareError;

/// The supersampled frames (RGBA f32, full resolution): the mean of `samples` jittered renders
/// of the original over `frames` frames; `None` for `samples` 0, or where the machine has not
/// the memory for them (each sample's frames and the sum: 32 bytes a pixel a frame, beside the
/// reference's) — then `skipped` says why. One sample would be the original moved by a Halton
/// offset, not a reference: refused.
pub fn reference(
    renderer: &Renderer,
    shader: &Shader,
    entry: usize,
    session: &Session,
    (opts, frames): (&RenderOptions, u32),
    samples: u32,
    skipped: &mut Vec<String>,
) -> Result<Option<Vec<Vec<f32>>>, CompareError> {
    let [w, h] = session.resolution;
    let need = 32 * u64::from(w) * u64::from(h) * u64::from(frames);
    if samples > 1
        && let Some(available) = reproj_replay::available_memory()
        && need > available
    {
        skipped.push(format!(
            "no supersampled reference: {frames} frames at {w}×{h} need {:.1} GiB more and {:.1} GiB are available (--max-frames fewer, or --supersample 0)",
            need as f64 / (1u64 << 30) as f64,
            available as f64 / (1u64 << 30) as f64
        ));
        return Ok(None);
    }
    match samples {
        0 => return Ok(None),
        1 => {
            return Err(CompareError::Options(
                "a supersampled reference needs at least 2 samples per pixel (0 turns it off)"
                    .into(),
            ));
        }
        _ => {}
    }
    let mut sum: Vec<Vec<f32>> = Vec::new();
    for i in 0..samples {
        let one = renderer.render_original_jittered(
            shader,
            entry,
            session,
            opts,
            Jitter::Fixed(halton_offset(i)),
        )?;
        if sum.is_empty() {
            sum = one.frames;
            continue;
        }
        for (acc, frame) in sum.iter_mut().zip(&one.frames) {
            for (a, v) in acc.iter_mut().zip(frame) {
                *a += v;
            }
        }
    }
    let scale = 1.0 / samples as f32;
    for frame in &mut sum {
        for v in frame.iter_mut() {
            *v *= scale;
        }
    }
    Ok(Some(sum))
}

/// Which of the first `frames` frames move: the camera or an object moved since the frame
/// before (the light's motion does not count: it moves no surface). Frame 0 is still.
pub fn moving_frames(session: &Session, frames: u32) -> Vec<bool> {
    let mut previous = session.frame_state(0);
    let mut moving = vec![false];
    for f in 1..frames {
        let state = session.frame_state(f);
        let moved =
            state.camera.view_proj != previous.camera.view_proj || state.models != previous.models;
        moving.push(moved);
        previous = state;
    }
    moving.truncate(frames as usize);
    moving
}

/// What the table's reader should know of the session's motion.
pub fn notes(moving: &[bool], temporal: bool) -> Vec<String> {
    let n = moving.iter().filter(|&&m| m).count();
    let mut notes = Vec::new();
    if n == 0 && temporal {
        notes.push(
            "the session has no motion: the temporal upsampler's history never moves (its best case), and no figure is split into still and moving frames".into(),
        );
    } else if n == moving.len().saturating_sub(1) || n == moving.len() {
        notes.push("every frame moves: no figure is split into still and moving frames".into());
    }
    notes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notes_say_when_nothing_or_everything_moves() {
        assert!(notes(&[false, false, false], true)[0].contains("no motion"));
        assert!(notes(&[false, false, false], false).is_empty());
        assert!(notes(&[false, true, true], true)[0].contains("every frame"));
        assert!(notes(&[false, true, false, true], true).is_empty());
    }
}
