//! Settling: before the first round, the baseline renders one window in blocks until two
//! successive blocks agree ([`Settle`]), so that a run does not time a GPU's clock ramping up from
//! idle. What it saw is kept with the run ([`Settling`]); where the clock did not settle in time
//! the run goes on with a warning.

use std::time::Instant;

use reproj_models::speedup::{Settle, Settling, Subject as Slot, block_ms};
use reproj_replay::ReplayError;

use crate::Scene;

impl Scene<'_> {
    /// Render the baseline's window at `first` in blocks of `len` frames (the first `warm` of
    /// each discarded) until `settle` is reached or its time is spent; at least two blocks.
    pub(crate) fn settle(
        &self,
        settle: &Settle,
        first: u32,
        len: u32,
        warm: u32,
    ) -> Result<Settling, ReplayError> {
        let t0 = Instant::now();
        let mut blocks_ms = Vec::new();
        loop {
            let ms = self.block(Slot::Baseline, first, len)?;
            blocks_ms.push(block_ms(&ms[(warm as usize).min(ms.len())..]).unwrap_or(f64::NAN));
            let settled = settle.reached(&blocks_ms);
            let seconds = t0.elapsed().as_secs_f64();
            if settled || seconds >= settle.max_seconds {
                return Ok(Settling {
                    blocks_ms,
                    seconds,
                    settled,
                });
            }
        }
    }
}
