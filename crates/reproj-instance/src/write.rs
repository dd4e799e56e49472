//! Writing a variant directory whole: every file generated first, then staged and swapped in.

use super::*;

/// The file extensions a variant directory holds: [`write_variant`] replaces a directory that
/// holds only these (and refuses any other), so a stale pass from another strategy or language
/// never lingers.
pub const VARIANT_FILES: &[&str] = &["wgsl", "json", "frag", "hlsl", "metal", "spv"];

/// Write the variant's WGSL files and `manifest.json` as the directory `dir`, whole: everything is
/// written into a staging directory beside it, which then replaces `dir`
/// ([`reproj_io::StagedDir`]), so a failure leaves `dir` as it was and a success leaves no file
/// of an earlier variant.
pub fn write_variant(variant: &Variant, dir: &Path) -> Result<(), InstanceError> {
    write_variant_in(variant, dir, &backends::Outputs::default())
}

/// [`write_variant`], and every pass also in each of `outputs`' languages ([`backends`]) beside its
/// WGSL. Every file is generated before any is written: a backend error writes nothing.
pub fn write_variant_in(
    variant: &Variant,
    dir: &Path,
    outputs: &backends::Outputs,
) -> Result<(), InstanceError> {
    let files = variant_files(variant, outputs)?;
    let staged = reproj_io::StagedDir::new(dir, reproj_io::Replace::OwnFiles(VARIANT_FILES))?;
    for (name, bytes) in files {
        staged.write(name, &bytes)?;
    }
    staged.commit()?;
    Ok(())
}

/// The files of a variant directory, by name: each pass's WGSL, each pass in each of `outputs`'
/// languages (override constants resolved), and `manifest.json` (listing those files and their
/// bindings in `languages`).
pub fn variant_files(
    variant: &Variant,
    outputs: &backends::Outputs,
) -> Result<Vec<(String, Vec<u8>)>, InstanceError> {
    if !outputs.langs.is_empty() {
        backends::check_overrides(variant.passes.iter().map(|p| &p.module), &outputs.overrides)?;
    }
    let mut files: Vec<(String, Vec<u8>)> = variant
        .passes
        .iter()
        .map(|p| (pass_file(p.kind).to_owned(), p.wgsl.clone().into_bytes()))
        .collect();
    let mut manifest = variant.manifest.clone();
    for &lang in &outputs.langs {
        let table = backends::language_output(&variant.passes, lang);
        for p in &variant.passes {
            files.push((
                backends::pass_file_in(p, lang),
                backends::write_pass(p, lang, &table, &outputs.overrides)?,
            ));
        }
        manifest.languages.push(table);
    }
    let mut manifest = serde_json::to_vec_pretty(&manifest).expect("manifest serializes");
    manifest.push(b'\n');
    files.push(("manifest.json".to_owned(), manifest));
    Ok(files)
}
