//! `reproj compare` runs on the page (`report --compare DIR`): each run's methods at equal time —
//! measured speedup with its interval, PSNR and ꟻLIP against the original and the supersampled
//! reference — and its crops of the middle frame, so the page shows what the profile's choices
//! stand against.

use std::fmt::Write as _;
use std::path::Path;

use reproj_compare::{COMPARE_SCHEMA, COMPARE_VERSION, CompareReport};

use crate::ReportError;
use crate::base64::png_uri;
use crate::html::{esc, num};

/// One compare run, read from its folder.
#[derive(Debug, Clone)]
pub struct CompareRun {
    /// The folder, as given.
    pub dir: String,
    pub report: CompareReport,
    /// `crops.png`, where the folder has it.
    pub crops: Option<Vec<u8>>,
}

/// `compare.json` of the versions this page reads.
const COMPARE_KIND: reproj_io::Kind = reproj_io::Kind {
    schema: COMPARE_SCHEMA,
    versions: 6..=COMPARE_VERSION,
    hint: "run `reproj compare` again",
};

/// Read the compare run in `dir`: its `compare.json` (an error naming the file and the field),
/// and its `crops.png` where there is one.
pub fn load_compare(dir: &Path) -> Result<CompareRun, ReportError> {
    let report: CompareReport = reproj_io::read_json(&dir.join("compare.json"), &COMPARE_KIND)?;
    let crops_path = dir.join("crops.png");
    let crops = if crops_path.is_file() {
        Some(reproj_io::read_input(
            &crops_path,
            reproj_io::InputKind::Asset,
        )?)
    } else {
        None
    };
    Ok(CompareRun {
        dir: dir.display().to_string(),
        report,
        crops,
    })
}

/// The page's section of the compare runs (nothing where there are none).
pub(crate) fn section(h: &mut String, runs: &[CompareRun]) {
    if runs.is_empty() {
        return;
    }
    h.push_str(
        r#"<section id="compare"><h2>Against other methods at equal time</h2>
<p class="muted">From <code>reproj compare</code>: each method's final setting timed against the original in one interleaved run (95 % interval), scored against the one-sample original and a supersampled reference.</p>
"#,
    );
    for run in runs {
        let r = &run.report;
        let _ = write!(
            h,
            r#"<h3>{shader} at {target:.2}× <span class="muted">({dir} · {w}×{hgt}, {frames} frames · {on})</span></h3>
<table class="numbers"><tr><th>method</th><th>speedup [95 %]</th><th>PSNR dB</th><th>ꟻLIP</th><th>PSNR dB, {ss} spp</th><th>ꟻLIP, {ss} spp</th><th>setting</th></tr>
"#,
            shader = esc(&r.shader),
            target = r.target_speedup,
            dir = esc(&run.dir),
            w = r.resolution[0],
            hgt = r.resolution[1],
            frames = r.frames,
            on = esc(r.measured_on.as_deref().unwrap_or(&r.adapter)),
            ss = r.supersample,
        );
        if let Some(o) = &r.original_vs_supersampled {
            let _ = writeln!(
                h,
                r#"<tr><td>original</td><td>1.00×</td><td></td><td></td><td>{}</td><td>{}</td><td>the floor: one sample</td></tr>"#,
                num(Some(o.psnr), 1),
                num(o.flip, 3)
            );
        }
        for m in &r.methods {
            let speed = match m.speedup_ci95 {
                Some([lo, hi]) => format!("{:.2}× [{lo:.2}, {hi:.2}]", m.speedup),
                None => format!("{:.2}×", m.speedup),
            };
            let missed = if m.reached_target {
                ""
            } else {
                " (not reached)"
            };
            let ss = m.scores.supersampled.as_ref();
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{speed}{missed}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(&m.method),
                num(Some(m.scores.psnr), 1),
                num(m.scores.flip, 3),
                num(ss.map(|s| s.psnr), 1),
                num(ss.and_then(|s| s.flip), 3),
                esc(&m.setting),
            );
        }
        h.push_str("</table>\n");
        if let Some(png) = &run.crops {
            let _ = writeln!(
                h,
                r#"<img class="chart" alt="crops of the middle frame, one per method" src="{}">"#,
                png_uri(png)
            );
        }
    }
    h.push_str("</section>\n");
}
