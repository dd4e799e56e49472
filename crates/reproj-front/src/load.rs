//! The front end in one call: read a shader file, normalize its fragment entry point, list its
//! nodes. Every command and stage that starts from a shader file goes through [`load`].

use std::path::Path;

use crate::nodes::{CullReason, NodeTable, enumerate};
use crate::normalize::{NormalizeOptions, Normalized, normalize};
use crate::parse::{FrontError, Lang, Shader, load_file_as};
use crate::unroll::UnrollOptions;

/// Options of [`load`].
#[derive(Debug, Clone, Copy, Default)]
pub struct LoadOptions {
    /// The input language; `None` chooses by the file's extension (WGSL for an unknown one).
    pub lang: Option<Lang>,
    /// Loops to unroll before the nodes are enumerated.
    pub unroll: UnrollOptions,
}

/// A loaded shader: the parsed module, its normalized fragment entry point and its node table.
#[derive(Debug, Clone)]
pub struct Loaded {
    pub shader: Shader,
    pub norm: Normalized,
    pub table: NodeTable,
}

/// Read `path`, normalize the fragment entry point `entry` (`None`: the only one) and enumerate
/// its nodes.
pub fn load(path: &Path, entry: Option<&str>, options: &LoadOptions) -> Result<Loaded, FrontError> {
    let shader = load_file_as(path, options.lang)?;
    Loaded::with_unroll(shader, entry, options.unroll)
}

impl Loaded {
    /// Normalize and enumerate an already parsed shader (see [`load`]).
    pub fn new(shader: Shader, entry: Option<&str>) -> Result<Loaded, FrontError> {
        Loaded::with_unroll(shader, entry, UnrollOptions::OFF)
    }

    /// [`Loaded::new`], unrolling loops as `unroll` says before enumerating.
    pub fn with_unroll(
        shader: Shader,
        entry: Option<&str>,
        unroll: UnrollOptions,
    ) -> Result<Loaded, FrontError> {
        let norm = normalize(
            &shader,
            &NormalizeOptions {
                entry: entry.map(str::to_owned),
                unroll,
            },
        )?;
        let table = enumerate(&shader, &norm);
        Ok(Loaded {
            shader,
            norm,
            table,
        })
    }
}

/// Why a shader has no cacheable node: the culled nodes counted per reason (in [`CullReason`]
/// order, reasons with no node left out) and a hint for the most common one.
#[derive(Debug, Clone, PartialEq)]
pub struct CullSummary {
    pub counts: Vec<(CullReason, usize)>,
    pub hint: &'static str,
}

impl NodeTable {
    /// The culled nodes counted per reason, with a hint for the commonest reason.
    pub fn cull_summary(&self) -> CullSummary {
        let counts: Vec<(CullReason, usize)> = CullReason::ALL
            .iter()
            .map(|&r| (r, self.nodes.iter().filter(|n| n.reason == Some(r)).count()))
            .filter(|&(_, n)| n > 0)
            .collect();
        let top = counts
            .iter()
            .max_by_key(|&&(r, n)| (n, std::cmp::Reverse(r as u8)));
        CullSummary {
            hint: top.map_or("the shader has no float-valued expression", |&(r, _)| {
                r.hint()
            }),
            counts,
        }
    }
}
