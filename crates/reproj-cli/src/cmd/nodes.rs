//! `reproj nodes`: the candidate nodes of a shader.

use std::io::Write;

use crate::NodesArgs;

pub fn run(args: &NodesArgs) -> anyhow::Result<()> {
    let loaded = super::load_shader(
        &args.shader,
        args.entry.as_deref(),
        args.lang_in,
        &args.unroll,
        &args.input.to_input(),
    )?;
    let mut table = loaded.table;
    let total = table.nodes.len();
    let cacheable = table.cacheable().count();
    let why = super::no_cacheable_lines(&table);
    if !args.all {
        table.nodes.retain(|n| n.cacheable);
    }
    let mut out = super::stdout::stdout();
    // No cacheable node is an honest answer, not an error: say why (after the table with
    // `--all`) and exit 0.
    if let (Some(lines), false, false) = (&why, args.json, args.all) {
        for line in lines {
            writeln!(out, "{line}")?;
        }
        return Ok(());
    }
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
        "{:>5} {:<11}{reason_col} {:>8} {:>8} {:>6}  {:<9} text",
        "id", "type", "cost", "overlap", "saves", "line:col"
    )?;
    // What caching a node can save at most: its cost less what it shares with the rest, as a
    // share of the whole shader's (the root's is 100 %). A variant's own passes cost about as
    // much as a cheap shader does, so a node that saves a small share cannot pay.
    let total_cost = table.total_cost.max(1e-9);
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
            "{:>5} {:<11}{reason} {:>8.0} {:>8.0} {:>5.0}%  {:<9} {text}",
            n.id,
            n.ty,
            n.cost,
            n.overlap,
            100.0 * n.saving() / total_cost,
            format!("{}:{}", n.line, n.col),
        )?;
    }
    for line in why.iter().flatten() {
        writeln!(out, "{line}")?;
    }
    Ok(())
}
