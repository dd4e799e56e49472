//! `reproj merge`: join shard profiles into one.

use std::io::Write;

use reproj_emit::{load_profile, resolve};

use crate::MergeArgs;

pub fn run(args: &MergeArgs) -> anyhow::Result<()> {
    if args.out.as_os_str() == "-" {
        return Err(super::UserError("--out needs a file path".into()).into());
    }
    reproj_io::check_target(&args.out, super::PROFILE_FILE)?;
    let mut shards = Vec::new();
    for path in &args.shards {
        shards.push((path.clone(), load_profile(path)?));
    }
    let mut merged = reproj_analyze::merge(&shards)?;
    // Paths relative to the merged profile, wherever the shards were.
    let (first_path, first) = &shards[0];
    let dir = args.out.parent().unwrap_or(std::path::Path::new(""));
    merged.shader.path = super::relative_to(dir, &resolve(&first.shader.path, first_path));
    merged.session.path = super::relative_to(dir, &resolve(&first.session.path, first_path));
    let mut json = serde_json::to_vec_pretty(&merged)?;
    json.push(b'\n');
    reproj_io::write_owned_file(&args.out, &json, super::PROFILE_FILE)?;
    let usable = merged
        .nodes
        .iter()
        .filter(|n| n.status == reproj_models::profile::NodeStatus::Ok)
        .count();
    let mut stdout = super::stdout::stdout();
    if args.json {
        let out = serde_json::json!({
            "schema": "reproj.merge",
            "version": 1,
            "out": args.out.display().to_string(),
            "shards": shards.len(),
            "nodes": merged.nodes.len(),
            "usable": usable,
            "hit_rate_mu": merged.hit_rate.mu,
        });
        writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)?;
        return Ok(());
    }
    writeln!(
        stdout,
        "merged {} shards: {} nodes ({usable} usable); hit-rate model µ = {}",
        shards.len(),
        merged.nodes.len(),
        merged
            .hit_rate
            .mu
            .map_or_else(|| "n/a".into(), |m| format!("{m:.3}"))
    )?;
    writeln!(stdout, "wrote {}", args.out.display())?;
    Ok(())
}
