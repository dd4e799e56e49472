//! Reading what `emit` chooses from: a profile (found, read, its shader and settings), and its
//! nodes and sets as the selector's records.

use std::path::{Path, PathBuf};

use crate::*;

/// Read a profile, naming the field when it is malformed.
pub fn load_profile(path: &Path) -> Result<Profile, EmitError> {
    let profile: Profile = reproj_io::read_json(path, &reproj_models::PROFILE_KIND)?;
    profile
        .check()
        .map_err(|(field, message)| reproj_io::ReadError::Field {
            path: path.to_owned(),
            field,
            message,
        })?;
    Ok(profile)
}

/// The most recently modified `*.profile.json` in `dir`.
pub fn latest_profile(dir: &Path) -> Result<PathBuf, EmitError> {
    let entries = std::fs::read_dir(dir).map_err(|source| EmitError::Io {
        path: dir.to_owned(),
        source,
    })?;
    entries
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().ends_with(".profile.json"))
        .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
        .max()
        .map(|(_, p)| p)
        .ok_or_else(|| EmitError::Options(format!(
            "no *.profile.json in {}: run `reproj analyze SHADER --session SESSION` first, or pass --profile (analyze writes none for a shader with nothing worth caching: `reproj nodes SHADER` says why)",
            dir.display()
        )))
}

/// Find a file a profile refers to: an absolute path as recorded, a relative one against the
/// profile's directory (profiles record it so). Nothing else is tried: a file of the same name in
/// the working directory is another file, and using it silently would profile or emit the wrong
/// shader; a missing file is reported with this path.
pub fn resolve(recorded: &str, profile_path: &Path) -> PathBuf {
    let p = PathBuf::from(recorded);
    match profile_path.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) if p.is_relative() => dir.join(&p),
        _ => p,
    }
}

/// The shader file a profile names, resolved against the profile's directory. It must be a
/// shader file by its extension: a profile is data from anywhere, and loading what it names
/// shows that file's first lines in a diagnostic (a profile naming `/etc/passwd` must not print
/// it).
pub fn profile_shader(profile: &Profile, profile_path: &Path) -> Result<PathBuf, EmitError> {
    let path = resolve(&profile.shader.path, profile_path);
    if reproj_front::Lang::from_path(&path).is_none() {
        return Err(EmitError::BadProfile {
            path: profile_path.to_owned(),
            message: format!(
                "field `shader.path`: `{}` is not a shader file (.wgsl, .glsl, .frag or .spv)",
                profile.shader.path
            ),
        });
    }
    if !path.exists() {
        return Err(EmitError::BadProfile {
            path: profile_path.to_owned(),
            message: format!(
                "field `shader.path`: the shader `{}` is not at {} (looked for relative to the profile's folder); restore it, or re-run `reproj analyze`",
                profile.shader.path,
                path.display()
            ),
        });
    }
    Ok(path)
}

/// How `analyze` read the profile's shader ([`reproj_models::profile::ShaderInputRecord`]): its
/// defs parsed as `--def` parses them, its folders resolved against the profile's directory.
pub fn profile_shader_input(
    profile: &Profile,
    profile_path: &Path,
) -> Result<reproj_front::ShaderInput, EmitError> {
    let record = &profile.shader_input;
    let bad = |field: &str, message: String| EmitError::BadProfile {
        path: profile_path.to_owned(),
        message: format!("field `shader_input.{field}`: {message}"),
    };
    let mut defs = std::collections::BTreeMap::new();
    for (name, value) in &record.defs {
        let (name, value) =
            reproj_front::parse_def(&format!("{name}={value}")).map_err(|m| bad("defs", m))?;
        defs.insert(name, value);
    }
    let preset = record
        .defs_preset
        .as_deref()
        .map(str::parse)
        .transpose()
        .map_err(|m| bad("defs_preset", m))?;
    let dirs = |list: &[String]| list.iter().map(|d| resolve(d, profile_path)).collect();
    Ok(reproj_front::ShaderInput {
        defs,
        preset,
        import_paths: dirs(&record.import_paths),
        include_dirs: dirs(&record.include_dirs),
    })
}

/// How the profile's variant of `node` was made (`None`: of its sets): its reconstruction (the
/// node's own, else the profile's) and the cache format, which the written and rendered variants
/// must share to run what was measured.
pub fn profile_variant_settings(
    profile: &Profile,
    node: Option<&reproj_models::profile::NodeProfile>,
    profile_path: &Path,
) -> Result<(Reconstruct, CacheFormatChoice), EmitError> {
    let bad = |field: &str, value: &str| EmitError::BadProfile {
        path: profile_path.to_owned(),
        message: format!("field `{field}`: `{value}` is not one reproj writes"),
    };
    let (field, name) = match node {
        Some(n) if n.reconstruct.is_some() => (
            format!("reconstruct` of node `{}", n.id),
            n.reconstruct_in(profile),
        ),
        _ => ("reconstruct".to_string(), profile.reconstruct.as_str()),
    };
    let reconstruct = Reconstruct::from_name(name).ok_or_else(|| bad(&field, name))?;
    let cache_format = CacheFormatChoice::from_name(&profile.cache_format)
        .ok_or_else(|| bad("cache_format", &profile.cache_format))?;
    Ok((reconstruct, cache_format))
}

/// The selector's records of a profile's usable nodes and sets under `opts`' metric, strategy
/// (when one is named) and node (when one is: sets are then left out).
pub(super) fn records_of(
    profile: &Profile,
    profile_path: &Path,
    opts: &EmitOptions,
) -> Result<(Vec<NodeRecord>, Vec<SetRecord>), EmitError> {
    records_with(
        profile,
        profile_path,
        opts.metric,
        opts.strategy.map(|s| s.name()),
        opts.node.as_ref(),
    )
}

/// The selector's records of a profile exactly as `emit` builds them with no `--strategy` or
/// `--node`: its usable nodes and sets under `metric`. What `report` chooses with, so that its
/// budget slider shows what `emit --max-error` writes, sets included.
pub fn selector_records(
    profile: &Profile,
    profile_path: &Path,
    metric: Metric,
) -> Result<(Vec<NodeRecord>, Vec<SetRecord>), EmitError> {
    records_with(profile, profile_path, metric, None, None)
}

/// [`records_of`] with its filters spelled out (`reproj_select::profile_records`).
fn records_with(
    profile: &Profile,
    profile_path: &Path,
    metric: Metric,
    strategy: Option<&str>,
    node: Option<&NodeChoice>,
) -> Result<(Vec<NodeRecord>, Vec<SetRecord>), EmitError> {
    let r = reproj_select::profile_records(
        profile,
        metric,
        strategy,
        &|n| node.is_none_or(|c| c.admits(n)),
        node.is_none(),
    )
    .map_err(|_| EmitError::BadProfile {
        path: profile_path.to_owned(),
        message: format!(
            "it has no {metric} measurements (profile version {}; they are recorded from version 4): re-run `reproj analyze` to bound {metric}",
            profile.version
        ),
    })?;
    Ok((r.nodes, r.sets))
}

/// Another session's profile must be of the same shader (IR), entry, unrolling and cache
/// settings as the first: its node ids and variants are then the same ones.
pub(super) fn same_shader(
    first: &Profile,
    first_path: &Path,
    other: &Profile,
    other_path: &Path,
) -> Result<(), EmitError> {
    let shader = |p: &Profile| {
        p.shader
            .ir_hash
            .clone()
            .unwrap_or_else(|| p.shader.hash.clone())
    };
    let differs = if shader(first) != shader(other) {
        Some("shader")
    } else if first.entry != other.entry {
        Some("entry point")
    } else if first.unroll != other.unroll {
        Some("--unroll")
    } else if first.block != other.block || first.depth_epsilon != other.depth_epsilon {
        Some("block size or depth tolerance")
    } else {
        None
    };
    match differs {
        None => Ok(()),
        Some(what) => Err(EmitError::BadProfile {
            path: other_path.to_owned(),
            message: format!(
                "its {what} differs from {}'s: profiles selected together must be of one shader with one setting, over different sessions",
                first_path.display()
            ),
        }),
    }
}

/// Whether node `id` was measured as the same variant in `first` and `other` (two sessions'
/// profiles of one shader): the same strategy, refresh block and reconstruction filter, which
/// per-node races (`--block auto`, `--reconstruct auto`) may settle differently per session.
/// A node `first` lacks is not compared (`false`).
pub(super) fn same_variant(first: &Profile, other: &Profile, id: u32) -> bool {
    let a = first.nodes.iter().find(|n| n.id == id);
    let b = other.nodes.iter().find(|n| n.id == id);
    match (a, b) {
        (Some(a), Some(b)) => {
            a.strategy == b.strategy
                && a.block.unwrap_or(first.block) == b.block.unwrap_or(other.block)
                && a.reconstruct_in(first) == b.reconstruct_in(other)
        }
        _ => false,
    }
}

/// Whether `shader` — as WGSL, what `analyze` rendered and hashed — is the one `profile` was made
/// of: the same IR written back by naga (comments and formatting aside), or for a profile before
/// version 3 the same text.
pub fn is_profiled_shader(profile: &Profile, shader: &reproj_front::Shader) -> bool {
    match &profile.shader.ir_hash {
        Some(h) => ir_hash(shader) == *h,
        None => content_hash(shader.source.as_bytes()) == profile.shader.hash,
    }
}

/// The path of the shader a profile was made of: `shader` when given, else the profile's own.
pub(crate) fn shader_path_of(
    profile: &Profile,
    profile_path: &Path,
    shader: Option<&Path>,
) -> Result<PathBuf, EmitError> {
    match shader {
        Some(s) => Ok(s.to_owned()),
        None => profile_shader(profile, profile_path),
    }
}

/// The shader a profile was made of — `shader` when given, else the profile's own — loaded as
/// `analyze` loaded it (its entry point and unrolling), and checked to be the one profiled
/// ([`is_profiled_shader`]): its path, the loaded shader, and its WGSL (what the replay renders:
/// naga's WGSL for GLSL or SPIR-V). What `emit`, `report` and `compare` open a profile with.
pub fn load_profiled(
    profile: &Profile,
    profile_path: &Path,
    shader: Option<&Path>,
) -> Result<(PathBuf, reproj_front::Loaded, reproj_front::Shader), EmitError> {
    let shader_path = shader_path_of(profile, profile_path, shader)?;
    let load_options = LoadOptions {
        unroll: UnrollOptions {
            max_trip: profile.unroll,
        },
        input: profile_shader_input(profile, profile_path)?,
        ..Default::default()
    };
    let loaded = load(&shader_path, Some(&profile.entry), &load_options)?;
    let shader = loaded.shader.to_wgsl()?;
    if !is_profiled_shader(profile, &shader) {
        return Err(EmitError::Stale {
            path: shader_path,
            what: "shader".into(),
        });
    }
    Ok((shader_path, loaded, shader))
}
