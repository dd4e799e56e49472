//! `reproj nodes`: the candidate nodes of a shader.

use std::io::Write;

use reproj_front::{NormalizeOptions, enumerate, load_file, normalize};

use super::front_error;
use crate::NodesArgs;

pub fn run(args: &NodesArgs) -> anyhow::Result<()> {
    let shader = load_file(&args.shader).map_err(front_error)?;
    let norm = normalize(
        &shader,
        &NormalizeOptions {
            entry: args.entry.clone(),
        },
    )
    .map_err(front_error)?;
    let mut table = enumerate(&shader, &norm);
    let total = table.nodes.len();
    let cacheable = table.cacheable().count();
    if !args.all {
        table.nodes.retain(|n| n.cacheable);
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &table)?;
        writeln!(out)?;
        return Ok(());
    }
    writeln!(
        out,
        "{} ({}): {total} nodes, {cacheable} cacheable, total cost {:.0}",
        table.shader, table.entry, table.total_cost
    )?;
    let reason_col = if args.all {
        format!(" {:<18}", "culled")
    } else {
        String::new()
    };
    writeln!(
        out,
        "{:>5} {:<11}{reason_col} {:>8} {:>8}  {:<9} text",
        "id", "type", "cost", "overlap", "line:col"
    )?;
    for n in &table.nodes {
        let reason = if args.all {
            format!(" {:<18}", n.reason.map_or("", |r| r.as_str()))
        } else {
            String::new()
        };
        let mut text = n.text.clone();
        if n.root {
            text = format!("[root] {text}");
        }
        if let (Some(l), Some(c)) = (n.call_line, n.call_col) {
            text = format!("{text}  (inlined at {l}:{c})");
        }
        if text.chars().count() > 90 {
            text = text.chars().take(87).collect::<String>() + "...";
        }
        writeln!(
            out,
            "{:>5} {:<11}{reason} {:>8.0} {:>8.0}  {:<9} {text}",
            n.id,
            n.ty,
            n.cost,
            n.overlap,
            format!("{}:{}", n.line, n.col),
        )?;
    }
    Ok(())
}
