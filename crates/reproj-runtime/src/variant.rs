//! [`Variant`]: a variant directory, loaded and checked; what the application needs to know before
//! it builds its device, vertex stage and bind groups.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::manifest::{Manifest, VertexContract};
use crate::plan::{self, Plan};
use crate::{ReadLimits, RuntimeError, Setup, VariantResources};

/// A variant written by `reproj emit` or `reproj instance`: its manifest and pass sources, checked.
/// Nothing here touches a GPU; [`Variant::create`] builds it on a device.
#[derive(Debug, Clone)]
pub struct Variant {
    dir: PathBuf,
    manifest: Manifest,
    pub(crate) plan: Arc<Plan>,
}

impl Variant {
    /// Read `dir/manifest.json` (schema `reproj.manifest`, versions 3 to 7) and the pass files it
    /// names, and check every field the runtime uses: an error names the file and the field.
    ///
    /// Each file is read as the reproj CLI reads it: a regular file (a folder, a named pipe or a
    /// device is refused before it is opened) within the default [`ReadLimits`], and each pass a
    /// file of `dir` (a link out of it is refused).
    pub fn load(dir: impl AsRef<Path>) -> Result<Variant, RuntimeError> {
        Variant::load_with(dir, &ReadLimits::default())
    }

    /// [`Variant::load`] within `limits` (to read a manifest or pass larger than the defaults).
    pub fn load_with(dir: impl AsRef<Path>, limits: &ReadLimits) -> Result<Variant, RuntimeError> {
        let dir = dir.as_ref();
        let path = plan::manifest_path(dir);
        let manifest = Manifest::read_with(&path, limits)?;
        let plan = Plan::new(&path, &manifest, plan::Sources::Files { dir, limits })?;
        Ok(Variant {
            dir: dir.to_owned(),
            manifest,
            plan: Arc::new(plan),
        })
    }

    /// A variant held in memory: the text of its manifest and each pass's WGSL, in the manifest's
    /// pass order (what [`Variant::load`] reads from a folder; the files the manifest names are
    /// not read). `dir` names it in errors, as `dir/manifest.json`. For a host that writes or
    /// edits the passes itself, and for reproj's own replay.
    pub fn from_sources(
        dir: impl AsRef<Path>,
        manifest: &str,
        sources: &[String],
    ) -> Result<Variant, RuntimeError> {
        let dir = dir.as_ref();
        let path = plan::manifest_path(dir);
        let manifest = Manifest::parse(&path, manifest)?;
        let plan = Plan::new(&path, &manifest, plan::Sources::Given(sources))?;
        Ok(Variant {
            dir: dir.to_owned(),
            manifest,
            plan: Arc::new(plan),
        })
    }

    /// The directory it was loaded from.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The manifest, as read.
    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// The device features the passes need (`required_features`): request them when opening
    /// the device; [`Variant::create`] fails naming the missing ones.
    pub fn required_features(&self) -> wgpu::Features {
        self.plan.required_features
    }

    /// What the application's vertex stage must add for the passes: an `@invariant` clip
    /// position and, at `prev_clip_location`, the previous frame's clip position computed by the
    /// `wgsl` helper with `inputs` (`docs/USAGE.md`, "Your vertex stage"); for a variant that
    /// reads motion vectors, the position alone.
    pub fn vertex(&self) -> &VertexContract {
        &self.manifest.vertex
    }

    /// Whether the passes read the application's motion vectors (manifest `reprojection:
    /// motion_vectors`) instead of a previous clip position from the vertex stage: give them as
    /// [`crate::Setup::motion`].
    pub fn reads_motion_vectors(&self) -> bool {
        self.plan.motion
    }

    /// The bind group the runtime binds (`group`): the application sets no bind group there, and
    /// gives its own bindings of it as [`crate::Setup::shared`] where the variant shares it.
    pub fn group(&self) -> u32 {
        self.plan.group
    }

    /// Whether [`Variant::group`] is also the original shader's (a shader that uses all four
    /// groups): the application's bindings there, below [`Variant::binding_base`], are then
    /// given as [`crate::Setup::shared`].
    pub fn shares_group(&self) -> bool {
        self.plan.binding_base > 0
    }

    /// The first binding number of the runtime's bindings in [`Variant::group`] (0 where the
    /// group is the variant's own).
    pub fn binding_base(&self) -> u32 {
        self.plan.binding_base
    }

    /// The groups of the application's own resources (the original shader's) that some pass
    /// declares: [`Setup::bind_group_layouts`] must give a layout for each.
    pub fn own_groups(&self) -> BTreeSet<u32> {
        self.plan
            .passes
            .iter()
            .flat_map(|p| p.own_groups.keys().copied())
            .collect()
    }

    /// Every group a pass declares (the application's own and the runtime's): the application's
    /// per-object groups (its vertex transforms) go in another.
    pub fn reserved_groups(&self) -> BTreeSet<u32> {
        let mut g = self.own_groups();
        g.insert(self.plan.group);
        g
    }

    /// Number of passes (shaders) a frame draws, in the manifest's order (1 to 3).
    pub fn pass_count(&self) -> usize {
        self.plan.passes.len()
    }

    /// The render passes a frame records, as ranges of the passes: consecutive passes that draw
    /// into the same targets, the later loading every one of them and the depth, share one (a
    /// `2pass` variant records one render pass, a `3pass` two; `docs/PASSES.md`, "One render
    /// pass"). [`crate::FrameInputs::timestamps`] are written per render pass.
    pub fn render_passes(&self) -> Vec<std::ops::Range<usize>> {
        self.plan.render_passes.clone()
    }

    /// Number of render passes a frame records ([`Variant::render_passes`]).
    pub fn render_pass_count(&self) -> usize {
        self.plan.render_passes.len()
    }

    /// Whether the frame must hold what lies behind the variant before [`VariantResources::record`]:
    /// the manifest was written with `--frame-load load`, and its first pass that draws the frame
    /// loads it instead of clearing it to [`crate::FrameTargets::clear_color`].
    pub fn loads_frame_first(&self) -> bool {
        self.manifest.loads_frame_first()
    }

    /// Whether the depth target must hold the application's depth before
    /// [`VariantResources::record`]: the variant was written with `--depth-load load`, and its
    /// first pass tests against what the target holds instead of clearing it (clear it at the
    /// frame's start, then draw your opaque geometry: the variant is hidden behind it).
    pub fn loads_depth_first(&self) -> bool {
        self.manifest.loads_depth_first()
    }

    /// The refresh period Δn the variant was emitted with (the `delta_n` parameter's value).
    pub fn delta_n(&self) -> Option<u32> {
        self.manifest.delta_n()
    }

    /// The Δn of the manifest's run-time schedule (`params.schedule`, written by `reproj emit`
    /// from a profile that records motion) at a frame's on-screen motion in pixels per frame;
    /// `None` without a schedule. Pass it as [`crate::FrameInputs::delta_n`].
    pub fn scheduled_delta_n(&self, pixels_per_frame: f64) -> Option<u32> {
        self.manifest.params.scheduled_delta_n(pixels_per_frame)
    }

    /// Bytes per frame pixel of the textures [`Variant::create`] allocates (payload and depth-copy
    /// ping-pong; the depth attachment is the application's): in the manifests reproj writes
    /// today, two payloads of 2 to 16 bytes and two 4-byte depth copies, 12 to 40 bytes.
    pub fn bytes_per_pixel(&self) -> u64 {
        self.plan
            .textures
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != self.plan.depth_texture)
            .map(|(_, t)| {
                u64::from(t.format.block_copy_size(None).unwrap_or(0)) * u64::from(t.sample_count)
            })
            .sum()
    }

    /// Build the variant on `device` for the application's frame: textures, samplers, the params
    /// buffer, bind groups and one pipeline per pass and vertex stage. wgpu's validation errors
    /// come back as [`RuntimeError::Gpu`] naming the pass.
    pub fn create(
        &self,
        device: &wgpu::Device,
        setup: &Setup<'_>,
    ) -> Result<VariantResources, RuntimeError> {
        VariantResources::new(device, Arc::clone(&self.plan), setup)
    }
}
