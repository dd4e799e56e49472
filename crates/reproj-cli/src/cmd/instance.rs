//! `reproj instance`: write the variant that caches one node, or several packed in one payload.

use std::io::Write;

use reproj_instance::{NodeSelector, instance_nodes, write_variant_in};

use super::UserError;
use crate::InstanceArgs;

pub fn run(args: &InstanceArgs) -> anyhow::Result<()> {
    let mut stdout = super::stdout::stdout();
    let selectors = args
        .node
        .split(',')
        .map(|s| s.trim().parse::<NodeSelector>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(UserError)?;
    let loaded = super::load_shader(
        &args.shader,
        args.entry.as_deref(),
        args.lang_in,
        &args.unroll,
        &args.input.to_input(),
    )?;
    let (shader, norm, table) = (&loaded.shader, &loaded.norm, &loaded.table);
    let opts = super::integrate(
        super::instance_options(args.cache, args.delta_n)?,
        &args.integration,
    );
    let variant = instance_nodes(shader, norm, table, &selectors, &opts)?;
    let outputs = super::outputs(&args.lang, &args.overrides);
    write_variant_in(&variant, &args.out, &outputs)?;
    let langs = outputs.langs;
    let m = &variant.manifest;
    if args.json {
        let files: Vec<String> = m
            .passes
            .iter()
            .zip(&variant.passes)
            .flat_map(|(p, pass)| {
                std::iter::once(p.file.clone()).chain(
                    langs
                        .iter()
                        .map(|&l| reproj_instance::backends::pass_file_in(pass, l)),
                )
            })
            .chain(std::iter::once("manifest.json".to_owned()))
            .collect();
        let out = serde_json::json!({
            "schema": "reproj.instance",
            "version": 1,
            "out": args.out.display().to_string(),
            "files": files,
            "manifest": m,
        });
        writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)?;
        return Ok(());
    }
    writeln!(
        stdout,
        "node {} `{}` ({}, line {}:{}) -> {}",
        m.node.id,
        m.node.text,
        m.node.ty,
        m.node.line,
        m.node.col,
        args.out.display()
    )?;
    for n in &m.also {
        writeln!(
            stdout,
            "  and node {} `{}` ({}, line {}:{}) at payload offset {}",
            n.id, n.text, n.ty, n.line, n.col, n.offset
        )?;
    }
    for (p, pass) in m.passes.iter().zip(&variant.passes) {
        let mut files = p.file.clone();
        for &lang in &langs {
            files += &format!(", {}", reproj_instance::backends::pass_file_in(pass, lang));
        }
        writeln!(
            stdout,
            "  {:<10} {files}",
            format!("{:?}", p.kind).to_lowercase(),
        )?;
    }
    let place = m.added_place();
    let previous = match m.vertex.prev_clip_location {
        Some(location) => format!("prev clip @location({location})"),
        None => format!(
            "motion vectors at binding {}",
            place.binding(reproj_instance::contract::MOTION_BINDING)
        ),
    };
    let group = if place.shared() {
        format!(
            "bind group {} shared with the shader: reproj's bindings from {} on",
            place.group, place.base
        )
    } else {
        format!("bind group {}", place.group)
    };
    writeln!(stdout, "  manifest   manifest.json ({group}, {previous})")?;
    Ok(())
}
