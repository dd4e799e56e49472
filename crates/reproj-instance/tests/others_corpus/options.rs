//! `tests/others/options.json`: how a user of each project's engine reads its shaders (defs, a
//! defs preset, import paths, include folders), the defs an engine's own pipeline always sets
//! for one file or entry point, and why the entry points that do not parse do not.

use std::path::Path;

use reproj_front::{DefsPreset, ShaderInput, parse_def};
use serde_json::Value;

/// One project: its files by name prefix and the options its engine's users pass.
pub struct Project {
    pub name: String,
    prefixes: Vec<String>,
    defs: Vec<String>,
    preset: Option<DefsPreset>,
    import_paths: Vec<String>,
    include_dirs: Vec<String>,
}

pub struct Options {
    projects: Vec<Project>,
    /// Per file: further defs, and per entry point further defs still.
    files: serde_json::Map<String, Value>,
    /// Why entry points do not parse, by file-name prefix.
    reasons: Vec<(String, String)>,
}

fn strings(v: &Value) -> Vec<String> {
    v.as_array()
        .into_iter()
        .flatten()
        .map(|s| s.as_str().expect("a string").to_owned())
        .collect()
}

impl Options {
    pub fn read(path: &Path) -> Options {
        let text = std::fs::read_to_string(path).unwrap();
        let v: Value = serde_json::from_str(&text).unwrap();
        let projects = v["projects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| Project {
                name: p["name"].as_str().unwrap().to_owned(),
                prefixes: strings(&p["prefixes"]),
                defs: strings(&p["defs"]),
                preset: p["defs_preset"].as_str().map(|s| s.parse().unwrap()),
                import_paths: strings(&p["import_paths"]),
                include_dirs: strings(&p["include_dirs"]),
            })
            .collect();
        let reasons = v["reasons"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(k, r)| (k.clone(), r.as_str().unwrap().to_owned()))
            .collect();
        Options {
            projects,
            files: v["files"].as_object().unwrap().clone(),
            reasons,
        }
    }

    /// The project `file` (`wgsl/x.wgsl`) belongs to, by its prefix.
    pub fn project(&self, file: &str) -> &Project {
        self.projects
            .iter()
            .find(|p| p.prefixes.iter().any(|x| file.starts_with(x.as_str())))
            .unwrap_or_else(|| panic!("{file}: no project in options.json has its prefix"))
    }

    /// What `file` (and its entry point `entry`, where given) is read with, folders under `root`.
    pub fn input(&self, file: &str, entry: Option<&str>, root: &Path) -> ShaderInput {
        let project = self.project(file);
        let mut defs = project.defs.clone();
        if let Some(f) = self.files.get(file) {
            defs.extend(strings(&f["defs"]));
            if let Some(e) = entry {
                defs.extend(strings(&f["entries"][e]));
            }
        }
        ShaderInput {
            defs: defs.iter().map(|d| parse_def(d).unwrap()).collect(),
            preset: project.preset,
            import_paths: project.import_paths.iter().map(|p| root.join(p)).collect(),
            include_dirs: project.include_dirs.iter().map(|p| root.join(p)).collect(),
        }
    }

    /// Why the entry points of `file` that do not parse do not: the reason of the longest prefix.
    pub fn reason(&self, file: &str) -> Option<&str> {
        self.reasons
            .iter()
            .filter(|(prefix, _)| file.starts_with(prefix.as_str()))
            .max_by_key(|(prefix, _)| prefix.len())
            .map(|(_, r)| r.as_str())
    }
}

/// The names of the `@fragment` functions of a WGSL text, outside `//` comments, in order:
/// every one counts, those a preprocessor leaves out included.
pub fn fragment_names(text: &str) -> Vec<String> {
    let code: String = text
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    let mut names = Vec::new();
    for (at, _) in code.match_indices("@fragment") {
        let rest = &code[at..];
        let Some(fn_at) = rest.find("fn ") else {
            continue;
        };
        let name: String = rest[fn_at + 3..]
            .trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if !name.is_empty() && !names.contains(&name) {
            names.push(name);
        }
    }
    names
}

/// The number of checks in a `"validates (N checks)"` cell.
pub fn checks_in(cell: &str) -> Option<usize> {
    cell.strip_prefix("validates (")?
        .split(' ')
        .next()?
        .parse()
        .ok()
}
