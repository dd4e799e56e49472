//! The variant a profile measured, typed: [`VariantSpec`] is built from a profiled node or set in
//! one place ([`VariantSpec::of`]) — its strategy, reconstruction filter and cache format parsed
//! from the profile's names, its refresh block, Δn and depth tolerance — and is what `emit` writes,
//! `report` renders and `compare` races, so the three cannot drift apart. A name the profile holds
//! that reproj does not write is a bad profile, named by its field.

use std::path::Path;

use reproj_front::{Loaded, Shader};
use reproj_instance::{
    CacheFormatChoice, InstanceOptions, NodeSelector, Reconstruct, Strategy, Variant,
    instance_nodes,
};
use reproj_models::Profile;
use reproj_models::profile::{NodeProfile, SetProfile};
use reproj_select::Choice;

use crate::{EmitError, profile_variant_settings};

/// One of a profile's measured variants: a node (the root included), or a set of nodes cached
/// together.
#[derive(Debug, Clone, Copy)]
pub enum Profiled<'p> {
    Node(&'p NodeProfile),
    Set(&'p SetProfile),
}

impl<'p> Profiled<'p> {
    /// The node or set of `profile` that `choice` (the selector's) stands for: the same id or
    /// members, measured in the same strategy. `None` when the profile holds none.
    pub fn of_choice(profile: &'p Profile, choice: &Choice) -> Option<Profiled<'p>> {
        if choice.members.is_empty() {
            profile
                .nodes
                .iter()
                .find(|n| n.id == choice.node_id && n.strategy == choice.strategy)
                .map(Profiled::Node)
        } else {
            profile
                .sets
                .iter()
                .find(|s| s.members == choice.members && s.strategy == choice.strategy)
                .map(Profiled::Set)
        }
    }

    /// The profile's strategy name of it.
    pub fn strategy_name(self) -> &'p str {
        match self {
            Profiled::Node(n) => &n.strategy,
            Profiled::Set(s) => &s.strategy,
        }
    }

    /// Its refresh block: a node's own where its race chose one, else the profile's; a set's own.
    pub fn block(self, profile: &Profile) -> u32 {
        match self {
            Profiled::Node(n) => n.block.unwrap_or(profile.block),
            Profiled::Set(s) => s.block,
        }
    }

    /// How `emit` and the reports name it: a node id, `root`, or a set's members joined by `+`.
    pub fn name(self) -> String {
        match self {
            Profiled::Node(n) if n.root => "root".into(),
            Profiled::Node(n) => n.id.to_string(),
            Profiled::Set(s) => s.name(),
        }
    }

    /// Its source text: a node's, or a set's members' joined by ` + `.
    pub fn text(self) -> String {
        match self {
            Profiled::Node(n) => n.text.clone(),
            Profiled::Set(s) => s.texts.join(" + "),
        }
    }

    /// What a message calls it: `node 12`, `set 3+7`.
    fn what(self) -> String {
        match self {
            Profiled::Node(n) => format!("node {}", n.id),
            Profiled::Set(s) => format!("set {}", s.name()),
        }
    }
}

/// A variant as the profile measured it, at one Δn: everything [`reproj_instance`] needs but where
/// the passes sit in a host (their bind group, what the first pass loads), which the caller adds.
#[derive(Debug, Clone, PartialEq)]
pub struct VariantSpec {
    /// The nodes cached: one (a node or the root), or a set's members packed in one payload.
    pub nodes: Vec<NodeSelector>,
    pub strategy: Strategy,
    pub reconstruct: Reconstruct,
    pub cache_format: CacheFormatChoice,
    /// Refresh block size k.
    pub block: u32,
    /// The refresh period (the manifest's default; the passes take it at run time).
    pub delta_n: u32,
    /// Relative depth tolerance of the hit test.
    pub depth_epsilon: f32,
}

impl VariantSpec {
    /// The spec of `profiled` at `delta_n`: its strategy, its reconstruction (a node's own, else
    /// the profile's), the profile's cache format, its block and the profile's ε. A name the
    /// profile holds that reproj does not write is [`EmitError::BadProfile`] at `profile_path`.
    pub fn of(
        profile: &Profile,
        profile_path: &Path,
        profiled: Profiled<'_>,
        delta_n: u32,
    ) -> Result<VariantSpec, EmitError> {
        let strategy: Strategy =
            profiled
                .strategy_name()
                .parse()
                .map_err(|e: String| EmitError::BadProfile {
                    path: profile_path.to_owned(),
                    message: format!("{}: {e}", profiled.what()),
                })?;
        let node = match profiled {
            Profiled::Node(n) => Some(n),
            Profiled::Set(_) => None,
        };
        let (reconstruct, cache_format) = profile_variant_settings(profile, node, profile_path)?;
        let nodes = match profiled {
            Profiled::Node(n) if n.root => vec![NodeSelector::Root],
            Profiled::Node(n) => vec![NodeSelector::Id(n.id)],
            Profiled::Set(s) => s.members.iter().map(|&id| NodeSelector::Id(id)).collect(),
        };
        Ok(VariantSpec {
            nodes,
            strategy,
            reconstruct,
            cache_format,
            block: profiled.block(profile),
            delta_n,
            depth_epsilon: profile.depth_epsilon,
        })
    }

    /// The spec of the selector's `choice` (a node or a set of `profile`, at its Δn).
    pub fn of_choice(
        profile: &Profile,
        profile_path: &Path,
        choice: &Choice,
    ) -> Result<VariantSpec, EmitError> {
        let profiled =
            Profiled::of_choice(profile, choice).ok_or_else(|| EmitError::BadProfile {
                path: profile_path.to_owned(),
                message: format!(
                    "the choice {} ({}) is none of its nodes or sets",
                    choice.node_id, choice.strategy
                ),
            })?;
        VariantSpec::of(profile, profile_path, profiled, choice.delta_n)
    }

    /// This spec in the cache format `asked` (`emit --cache-format`; `None`: the profile's).
    pub fn in_format(self, asked: Option<CacheFormatChoice>) -> VariantSpec {
        VariantSpec {
            cache_format: asked.unwrap_or(self.cache_format),
            ..self
        }
    }

    /// The instancer's options of this spec, placed in a host as `integration` says (its bind
    /// group, frame and depth loads and reprojection; its other fields are not read).
    pub fn options(&self, integration: &InstanceOptions) -> InstanceOptions {
        InstanceOptions {
            strategy: self.strategy,
            reconstruct: self.reconstruct,
            cache_format: self.cache_format,
            delta_n: self.delta_n,
            block: self.block,
            depth_epsilon: self.depth_epsilon,
            group: integration.group,
            frame_load: integration.frame_load,
            depth_load: integration.depth_load,
            reprojection: integration.reprojection,
        }
    }

    /// Build the variant of `shader` (its loaded IR and node table) this spec describes.
    pub fn instance(
        &self,
        shader: &Shader,
        loaded: &Loaded,
        integration: &InstanceOptions,
    ) -> Result<Variant, EmitError> {
        Ok(instance_nodes(
            shader,
            &loaded.norm,
            &loaded.table,
            &self.nodes,
            &self.options(integration),
        )?)
    }
}
