//! A profile's numbers checked as data, after the schema ([`Profile::check`]): times finite,
//! positive and under ten minutes a frame, errors finite and ≥ 0, hit rates in [0, 1], periods
//! ≥ 1; the first bad field is named by its JSON path.

use super::{Measurement, OriginalRecord, Profile};

/// The longest frame time a profile may record, ms: ten minutes a frame is no measurement.
const MAX_FRAME_MS: f64 = 600_000.0;

/// A frame time in milliseconds: finite, below [`MAX_FRAME_MS`], above 0 (or ≥ 0 with `zero_ok`).
fn check_ms(field: String, v: f64, zero_ok: bool) -> Result<(), (String, String)> {
    let low_ok = if zero_ok { v >= 0.0 } else { v > 0.0 };
    if v.is_finite() && low_ok && v <= MAX_FRAME_MS {
        Ok(())
    } else {
        Err((
            field,
            format!(
                "{v} is not a frame time: a finite number of milliseconds in {}0, {MAX_FRAME_MS}]",
                if zero_ok { "[" } else { "(" }
            ),
        ))
    }
}

impl OriginalRecord {
    /// Check the numbers as data (see [`Profile::check`]); `at` is this record's JSON path.
    pub fn check(&self, at: &str) -> Result<(), (String, String)> {
        check_ms(format!("{at}.frame_ms"), self.frame_ms, false)?;
        for (i, &t) in self.frame_times_ms.iter().enumerate() {
            check_ms(format!("{at}.frame_times_ms[{i}]"), t, true)?;
        }
        Ok(())
    }
}

impl Measurement {
    /// Check the numbers as data (see [`Profile::check`]); `at` is this record's JSON path.
    pub fn check(&self, at: &str) -> Result<(), (String, String)> {
        check_ms(format!("{at}.frame_ms"), self.frame_ms, false)?;
        if !(self.error.is_finite() && self.error >= 0.0) {
            return Err((
                format!("{at}.error"),
                format!("{} is not an error: a finite number ≥ 0", self.error),
            ));
        }
        if !(0.0..=1.0).contains(&self.hit_rate) {
            return Err((
                format!("{at}.hit_rate"),
                format!("{} is not a hit rate in [0, 1]", self.hit_rate),
            ));
        }
        if self.delta_n == 0 {
            return Err((
                format!("{at}.delta_n"),
                "a refresh period is at least 1".into(),
            ));
        }
        for (k, f) in self.frames.iter().enumerate() {
            check_ms(format!("{at}.frames[{k}].time_ms"), f.time_ms, true)?;
        }
        Ok(())
    }
}

impl Profile {
    /// Check the numbers as data, after the schema: every time finite, positive and below
    /// ten minutes a frame, every error finite and ≥ 0, every hit rate in [0, 1], every period
    /// ≥ 1. A hand-edited or corrupt profile is refused here, naming the field (its JSON path)
    /// and what it must be, rather than steering a selection.
    pub fn check(&self) -> Result<(), (String, String)> {
        if self.resolution.contains(&0) || self.frames == 0 {
            return Err((
                "resolution".into(),
                format!(
                    "{:?} over {} frames: the resolution and the frame count must be at least 1",
                    self.resolution, self.frames
                ),
            ));
        }
        self.original.check("original")?;
        if let Some(m) = &self.motion {
            m.check().map_err(|e| ("motion".to_string(), e))?;
        }
        for (i, n) in self.nodes.iter().enumerate() {
            for (j, m) in n.measurements.iter().enumerate() {
                m.check(&format!("nodes[{i}].measurements[{j}]"))?;
            }
        }
        for (i, set) in self.sets.iter().enumerate() {
            for (j, m) in set.measurements.iter().enumerate() {
                m.check(&format!("sets[{i}].measurements[{j}]"))?;
            }
        }
        Ok(())
    }
}
