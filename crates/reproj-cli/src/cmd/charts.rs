//! Charts written next to a profile.

use std::path::Path;

use reproj_models::Profile;

/// Budgets whose selections the trade-off chart marks: the ones `scripts/demo.sh` emits at and
/// `docs/notebook/speedups-and-budgets.md` reports.
pub const MARKED_BUDGETS: [f64; 4] = [0.002, 0.01, 0.03, 0.1];

/// The directory and the file-name stem of the charts beside `profile_path`.
fn dir_and_stem(profile_path: &Path) -> (&Path, String) {
    let dir = profile_path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = profile_path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let stem = name
        .strip_suffix(".profile.json")
        .or_else(|| name.strip_suffix(".json"))
        .unwrap_or(&name)
        .to_string();
    (dir, stem)
}

/// Check, before the analysis, that the charts beside `profile_path` would replace only charts.
pub fn check_targets(profile_path: &Path) -> Result<(), reproj_io::WriteError> {
    let (dir, stem) = dir_and_stem(profile_path);
    for figure in reproj_charts::Figure::ALL {
        for ext in ["svg", "png"] {
            let path = dir.join(format!("{stem}.{}.{ext}", figure.name()));
            reproj_io::check_target(&path, reproj_io::Owner::Image)?;
        }
    }
    Ok(())
}

/// Write the trade-off, hit-rate and model charts beside `profile_path`; the files written.
pub fn write(profile: &Profile, profile_path: &Path) -> anyhow::Result<Vec<String>> {
    check_targets(profile_path)?;
    let (dir, stem) = dir_and_stem(profile_path);
    let opts = reproj_charts::ChartOptions {
        budgets: MARKED_BUDGETS.to_vec(),
    };
    let paths = reproj_charts::write_charts(profile, dir, &stem, &opts)?;
    for w in &paths.warnings {
        crate::ui::warn(w);
    }
    let all: Vec<String> = paths
        .svg
        .iter()
        .chain(&paths.png)
        .map(|p| p.display().to_string())
        .collect();
    Ok(all)
}
