//! The font for text in PNG charts.
//!
//! Bitmap text is drawn by [`crate::glyph`] with ab_glyph from a font file read at run time; we
//! never ask the system (no fontconfig, no font-kit). The font file comes from `REPROJ_FONT` when it names a
//! readable TrueType/OpenType file, else from a list of usual places (Debian's `fonts-dejavu-core`
//! first). None found: PNGs are drawn without text and the caller is told. SVG text needs no font
//! file: the SVG backend writes `<text>` elements and the viewer picks the font.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use ab_glyph::FontVec;

/// Environment variable naming a TrueType/OpenType font file for PNG text.
pub const FONT_ENV: &str = "REPROJ_FONT";

/// Family written into SVG `font-family` (the viewer's sans-serif).
pub(crate) const FAMILY: &str = "sans-serif";

/// Where a sans-serif font usually is (Debian/Ubuntu, Fedora, Arch, Alpine, macOS, Windows).
const CANDIDATES: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation-sans/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf",
    "/usr/share/fonts/noto/NotoSans-Regular.ttf",
    "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
    "/usr/share/fonts/gnu-free/FreeSans.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "/Library/Fonts/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// The faces text is drawn with.
pub(crate) struct Fonts {
    pub(crate) regular: FontVec,
    /// The bold face, when found beside the regular one (else bold text is drawn regular).
    pub(crate) bold: Option<FontVec>,
}

impl std::fmt::Debug for Fonts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fonts")
            .field("bold", &self.bold.is_some())
            .finish_non_exhaustive()
    }
}

/// Outcome of the one-time font lookup.
#[derive(Debug)]
pub(crate) struct FontState {
    /// The regular font's file, if any.
    pub(crate) path: Option<PathBuf>,
    pub(crate) fonts: Option<Fonts>,
    /// What went wrong on the way (a bad `REPROJ_FONT`, no font at all).
    pub(crate) warnings: Vec<String>,
}

static FONT: OnceLock<FontState> = OnceLock::new();

/// Find and register the font, once per process.
pub(crate) fn font() -> &'static FontState {
    FONT.get_or_init(init)
}

/// The font file used for PNG text, if one was found (looks it up on first use).
pub fn font_path() -> Option<&'static Path> {
    font().path.as_deref()
}

/// Read and parse a font file; `Err` says why not.
fn load(path: &Path) -> Result<FontVec, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    FontVec::try_from_vec(bytes)
        .map_err(|_| format!("{} is not a TrueType/OpenType font", path.display()))
}

/// `DejaVuSans.ttf` → `DejaVuSans-Bold.ttf`; `LiberationSans-Regular.ttf` →
/// `LiberationSans-Bold.ttf`; `NotoSans-Regular.ttf` → `NotoSans-Bold.ttf`.
fn bold_sibling(path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?.to_str()?;
    let (base, ext) = name.rsplit_once('.')?;
    let base = base.strip_suffix("-Regular").unwrap_or(base);
    let bold = path.with_file_name(format!("{base}-Bold.{ext}"));
    bold.is_file().then_some(bold)
}

fn init() -> FontState {
    let env = std::env::var_os(FONT_ENV)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from);
    let candidates: Vec<PathBuf> = CANDIDATES.iter().map(PathBuf::from).collect();
    lookup(env.as_deref(), &candidates)
}

/// The first font that loads: `env` (a warning if it does not), then the first existing
/// `candidates`.
fn lookup(env: Option<&Path>, candidates: &[PathBuf]) -> FontState {
    let mut warnings = Vec::new();
    let tried = env.into_iter().map(|p| (p, true)).chain(
        candidates
            .iter()
            .filter(|p| p.is_file())
            .map(|p| (p.as_path(), false)),
    );
    for (path, from_env) in tried {
        match load(path) {
            Ok(regular) => {
                // Optional: without it bold text is drawn with the regular face.
                let bold = bold_sibling(path).and_then(|b| load(&b).ok());
                return FontState {
                    path: Some(path.to_path_buf()),
                    fonts: Some(Fonts { regular, bold }),
                    warnings,
                };
            }
            Err(e) if from_env => warnings.push(format!("{FONT_ENV}: {e}; looking elsewhere")),
            Err(_) => {}
        }
    }
    warnings.push(format!(
        "no font file found (set {FONT_ENV} to a .ttf file, or install fonts-dejavu-core): \
         PNG charts are drawn without text; the SVG charts have it"
    ));
    FontState {
        path: None,
        fonts: None,
        warnings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_order_and_warnings() {
        let dir = tempfile::tempdir().unwrap();
        let junk = dir.path().join("junk.ttf");
        std::fs::write(&junk, b"not a font").unwrap();
        let missing = dir.path().join("missing.ttf");

        // Nothing usable: two warnings (the bad REPROJ_FONT, no font at all), no fonts.
        let state = lookup(Some(&missing), &[junk.clone(), missing.clone()]);
        assert!(state.fonts.is_none() && state.path.is_none());
        assert_eq!(state.warnings.len(), 2, "{:?}", state.warnings);
        assert!(state.warnings[0].starts_with(FONT_ENV));
        assert!(state.warnings[1].contains("no font file found"));

        // A real font among the candidates (where this machine has one).
        if let Some(real) = CANDIDATES.iter().map(PathBuf::from).find(|p| p.is_file()) {
            let state = lookup(Some(&junk), &[missing.clone(), real.clone()]);
            assert_eq!(state.path.as_deref(), Some(real.as_path()));
            assert!(state.fonts.is_some());
            assert_eq!(state.warnings.len(), 1);
            // And named by REPROJ_FONT, it comes first.
            let state = lookup(Some(&real), &[]);
            assert_eq!(state.path.as_deref(), Some(real.as_path()));
            assert!(state.warnings.is_empty());
        }
    }

    #[test]
    fn bold_sibling_names() {
        let dir = tempfile::tempdir().unwrap();
        let regular = dir.path().join("NotoSans-Regular.ttf");
        assert_eq!(bold_sibling(&regular), None);
        std::fs::write(dir.path().join("NotoSans-Bold.ttf"), b"x").unwrap();
        assert_eq!(
            bold_sibling(&regular),
            Some(dir.path().join("NotoSans-Bold.ttf"))
        );
    }
}
