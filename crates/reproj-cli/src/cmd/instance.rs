//! `reproj instance`: write the variant that caches one node.

use std::io::Write;

use reproj_front::{NormalizeOptions, enumerate, load_file, normalize};
use reproj_instance::{NodeSelector, instance, write_variant};

use super::{UserError, front_error, instance_error};
use crate::InstanceArgs;

pub fn run(args: &InstanceArgs) -> anyhow::Result<()> {
    let mut stdout = std::io::stdout().lock();
    let selector: NodeSelector = args.node.parse().map_err(UserError)?;
    let shader = load_file(&args.shader).map_err(front_error)?;
    let norm = normalize(
        &shader,
        &NormalizeOptions {
            entry: args.entry.clone(),
        },
    )
    .map_err(front_error)?;
    let table = enumerate(&shader, &norm);
    let opts = super::integrate(
        super::instance_options(args.cache, args.delta_n),
        args.integration,
    );
    let variant = instance(&shader, &norm, &table, selector, &opts).map_err(instance_error)?;
    write_variant(&variant, &args.out).map_err(instance_error)?;
    let m = &variant.manifest;
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
    for p in &m.passes {
        writeln!(
            stdout,
            "  {:<10} {}",
            format!("{:?}", p.kind).to_lowercase(),
            p.file
        )?;
    }
    writeln!(
        stdout,
        "  manifest   manifest.json (bind group {}, prev clip @location({}))",
        m.group, m.vertex.prev_clip_location
    )?;
    Ok(())
}
