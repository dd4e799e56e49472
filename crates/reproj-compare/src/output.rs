//! The comparison's files: `compare.json`, the chart, the crops and the simplified shader.

use std::path::{Path, PathBuf};

use crate::{CompareError, Comparison, crops};

/// Write `compare.json`, the chart (`compare.svg`, `compare.png`), the crops (`crops.png`) and
/// the simplified shader (`simplified.wgsl`) into `dir`, all or none; record them in the report.
pub fn write_outputs(c: &mut Comparison, dir: &Path) -> Result<Vec<String>, CompareError> {
    let r = &c.report;
    let series = r
        .methods
        .iter()
        .map(|m| {
            let points: Vec<reproj_charts::ComparePoint> = match m.method.as_str() {
                "resize" => r
                    .resize
                    .tries
                    .iter()
                    .map(|t| point(t.speedup, t.error))
                    .collect(),
                "simplify" => r
                    .simplify
                    .steps
                    .iter()
                    .map(|s| point(s.speedup, s.error))
                    .collect(),
                _ => vec![point(m.speedup, m.scores.error)],
            };
            reproj_charts::CompareSeries {
                method: m.method.clone(),
                points,
            }
        })
        .collect();
    let chart = reproj_charts::Compare {
        title: format!(
            "{}: error at equal frame time (target {:.2}×{})",
            Path::new(&r.shader)
                .file_name()
                .map_or_else(|| r.shader.clone(), |n| n.to_string_lossy().into_owned()),
            r.target_speedup,
            r.max_error
                .map_or_else(String::new, |e| format!(", reproj's under error {e}"))
        ),
        subtitle: format!(
            "{} frames at {}×{}, {} ({} timing)",
            r.frames, r.resolution[0], r.resolution[1], r.adapter, r.timing
        ),
        target: r.target_speedup,
        series,
    };
    let (svg, png) = reproj_charts::compare_chart(&chart)?;
    let panels: Vec<crops::Panel<'_>> = c
        .crop_frames
        .iter()
        .map(|(name, frame)| crops::Panel {
            name: name.clone(),
            detail: match r.methods.iter().find(|m| &m.method == name) {
                Some(m) => format!("{:.2}× · {:.1} dB", m.speedup, m.scores.psnr),
                None => format!("{:.2} ms/frame", r.original_ms),
            },
            frame,
        })
        .collect();
    let (crops, mut warnings) = crops::crops_png(&panels, r.resolution, &r.crops)?;
    let names = [
        "compare.json",
        "compare.svg",
        "compare.png",
        "crops.png",
        "simplified.wgsl",
    ];
    c.report.files = names
        .iter()
        .map(|n| dir.join(n).display().to_string())
        .collect();
    let mut json = serde_json::to_vec_pretty(&c.report).expect("the report serializes");
    json.push(b'\n');
    let files: Vec<(PathBuf, Vec<u8>)> = vec![
        (dir.join(names[0]), json),
        (dir.join(names[1]), svg.into_bytes()),
        (dir.join(names[2]), png.bytes),
        (dir.join(names[3]), crops),
        (dir.join(names[4]), c.simplified_wgsl.clone().into_bytes()),
    ];
    std::fs::create_dir_all(dir)
        .map_err(|e| CompareError::Options(format!("cannot create {}: {e}", dir.display())))?;
    reproj_io::write_files(&files)?;
    warnings.retain(|w| !png.warnings.contains(w));
    warnings.extend(png.warnings);
    Ok(warnings)
}

fn point(speedup: f64, error: f64) -> reproj_charts::ComparePoint {
    reproj_charts::ComparePoint { speedup, error }
}
