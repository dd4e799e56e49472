//! `reproj session init`: a starting session for a shader (see
//! `reproj_scene::init::starter_session`), written where asked or printed.

use std::io::Write;

use reproj_scene::init::{StarterError, StarterOptions, starter_session};

use super::UserError;
use crate::{SessionArgs, SessionCommand, SessionInitArgs};

pub fn run(args: &SessionArgs) -> anyhow::Result<()> {
    match &args.command {
        SessionCommand::Init(a) => init(a),
    }
}

fn init(args: &SessionInitArgs) -> anyhow::Result<()> {
    if let Some(out) = &args.out
        && out.exists()
        && !args.force
    {
        return Err(UserError(format!(
            "{} exists; pass --force to replace it",
            out.display()
        ))
        .into());
    }
    let input = super::read_shader(&args.shader, args.lang_in, &args.input)?;
    let shader = input.to_wgsl()?;
    let entry = shader.fragment_entry(args.entry.as_deref())?;
    let iface = reproj_scene::reflect::reflect(&shader.module, &shader.info, entry)?;
    let name = args.shader.file_name().map_or_else(
        || args.shader.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let opts = StarterOptions {
        resolution: [args.resolution[0], args.resolution[1]],
        frames: args.frames,
        description: format!(
            "A starting session for {name} (`{}`), written by `reproj session init`: a torus turning under an orbiting camera and light. Values marked in the notes are guesses: set what the shader expects (crates/reproj-scene/SESSION.md).",
            iface.entry
        ),
    };
    let starter = starter_session(&iface, &opts).map_err(|e| match e {
        StarterError::Invalid(_) => anyhow::Error::from(e),
        e => UserError(format!("{}: {e}", args.shader.display())).into(),
    })?;
    let mut json = serde_json::to_vec_pretty(&starter.session)?;
    json.push(b'\n');
    match &args.out {
        Some(out) => {
            reproj_io::write_file(out, &json)?;
            crate::ui::note(format_args!("wrote {}", out.display()));
        }
        None => super::stdout::stdout().write_all(&json)?,
    }
    for line in &starter.notes {
        crate::ui::note(format_args!("{line}"));
    }
    if let Some(out) = &args.out {
        crate::ui::note(format_args!(
            "next: reproj render {} --session {}",
            args.shader.display(),
            out.display()
        ));
    }
    Ok(())
}
