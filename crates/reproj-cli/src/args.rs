//! The arguments of every command (clap derive): what `main.rs` parses.
#![cfg_attr(not(feature = "gpu"), allow(dead_code))]

use std::path::PathBuf;

use clap::Args;
use reproj_emit::{Budget, EXTENDED_MAX_DELTA_N};

use crate::values::{
    backend_help, block_choice, budget, delta_n_limit, depth_epsilon, output_path, override_value,
    parse_backend, positive, positive_seconds, refresh_period,
};

mod analyze;
mod bench;
mod compare;
mod input;

pub use analyze::{AnalyzeArgs, MergeArgs};
pub use bench::BenchArgs;
pub use compare::CompareArgs;
pub use input::{ShaderInputArgs, UnrollArg};

/// Arguments of `reproj report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Profile from `reproj analyze`.
    pub profile: PathBuf,
    /// The HTML file to write.
    #[arg(long, value_parser = output_path, default_value = "report.html")]
    pub out: PathBuf,
    /// Session to render the selections with (default: the profile's).
    #[arg(hide = true, long)]
    pub session: Option<PathBuf>,
    /// The shader (default: the profile's; it must be the profiled shader up to comments).
    #[arg(hide = true, long)]
    pub shader: Option<PathBuf>,
    /// Most selections to render frames of (spread over the budget range).
    #[arg(hide = true, long, default_value_t = 8)]
    pub max_rendered: usize,
    /// Stop timing the rendered selections against the original after this many seconds
    /// (checked between rounds; as `bench --max-time`).
    #[arg(hide = true, long, default_value_t = 30.0, value_parser = positive_seconds)]
    pub max_time: f64,
    /// Time them for at least this many rounds (as `bench --min-rounds`: the rounds cycle
    /// through 4 windows of the session, 8 gives each window two).
    #[arg(hide = true, long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub min_rounds: u32,
    /// A `reproj compare` output folder whose table and crops the page shows (repeatable).
    #[arg(long, value_name = "DIR")]
    pub compare: Vec<PathBuf>,
    #[arg(hide = true, long, help = backend_help(), value_parser = parse_backend)]
    pub backend: Option<String>,
    /// Print what was written as JSON (`reproj.report-run`, docs/SCHEMAS.md).
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `reproj render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The shader: WGSL, GLSL (`.glsl`, `.frag`) or SPIR-V (`.spv`), by extension.
    pub shader: PathBuf,
    /// The shader's language, when its extension does not say.
    #[arg(hide = true, long, value_enum)]
    pub lang_in: Option<LangInArg>,
    #[command(flatten)]
    pub input: ShaderInputArgs,
    /// The session file.
    #[arg(long)]
    pub session: PathBuf,
    /// Render the variant caching this node (id or `root`) instead of the original.
    #[arg(long, conflicts_with = "variant")]
    pub node: Option<String>,
    /// Render the variant written in this directory (by `instance` or `emit`: its manifest.json
    /// and passes) instead of the original.
    #[arg(long)]
    pub variant: Option<PathBuf>,
    /// Refresh period of the variant (default: 8 with --node, the manifest's with --variant).
    #[arg(long, value_parser = refresh_period)]
    pub delta_n: Option<u32>,
    /// With --variant: run-time adaptation, as a host would do it: each frame's Δn from the
    /// manifest's schedule (`params.schedule`, written by `emit`) at that frame's on-screen
    /// motion (measured from the session's camera and objects).
    #[arg(long, requires = "variant", conflicts_with = "delta_n")]
    pub adaptive: bool,
    #[command(flatten)]
    pub cache: CacheArgs,
    /// Write PNGs of the frames (and for a variant the hit maps and error maps) here.
    #[arg(long, value_parser = output_path)]
    pub frames: Option<PathBuf>,
    /// With --frames: also write each frame's exact linear RGBA as `frame_NNN.f32` (width × height
    /// × 4 little-endian f32, top row first, no header), to compare renderers beyond 8 bits.
    #[arg(hide = true, long, requires = "frames")]
    pub raw_frames: bool,
    /// Render only the first N frames.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_frames: Option<u32>,
    /// Variants: compute ꟻLIP and SSIM (and with --frames write the ꟻLIP maps) on every Nth
    /// frame (0, N, 2N, ...).
    #[arg(hide = true, long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub metric_stride: u32,
    /// Fragment entry point.
    #[arg(long)]
    pub entry: Option<String>,
    #[arg(hide = true, long, help = backend_help(), value_parser = parse_backend)]
    pub backend: Option<String>,
    /// With a variant: also time it against the original through the timing engine, interleaved
    /// in one run with its 95 % interval (as `reproj bench`, up to 30 s), and report the speedup
    /// (`--speedup`, its former name, is still read).
    #[arg(long = "time", alias = "speedup")]
    pub speedup: bool,
    /// With a variant: draw and time every pass in its own render pass (the JSON records'
    /// `pass_ms`). By default passes that write the same targets share one render pass, as a
    /// host draws them, and only the frame is timed.
    #[arg(hide = true, long)]
    pub pass_times: bool,
    /// Print the report as JSON (`reproj.render`, docs/SCHEMAS.md).
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `reproj emit`.
#[derive(Debug, Args)]
pub struct EmitArgs {
    /// Error budget, in the unit of --metric: with `l2` the mean per-pixel L2 distance in linear
    /// RGB over all pixels (in [0, √3]), with `flip` the mean ꟻLIP error over the covered pixels
    /// (in [0, 1]).
    #[arg(long, value_parser = budget)]
    pub max_error: Budget,
    /// Which measured error the budget bounds: `l2` (the paper's) or `flip` (perceptual).
    #[arg(hide = true, long, default_value = "l2")]
    pub metric: reproj_models::Metric,
    /// Profile from `reproj analyze` (default: the newest *.profile.json here). Give one per
    /// session (`--profile slow.profile.json --profile fast.profile.json`, the same shader
    /// analyzed over each): the selection then holds the budget on every session, the worst case,
    /// and the report gives each session's prediction.
    #[arg(long)]
    pub profile: Vec<PathBuf>,
    /// Output directory (default: out/SHADER_STEM).
    #[arg(long, value_parser = output_path)]
    pub out: Option<PathBuf>,
    /// Largest refresh period to consider.
    #[arg(hide = true, long, default_value_t = EXTENDED_MAX_DELTA_N, value_parser = delta_n_limit)]
    pub max_delta_n: u32,
    /// Cache texel format of the written passes (default: the profile's).
    #[arg(hide = true, long, value_enum)]
    pub cache_format: Option<CacheFormatArg>,
    /// Only consider this strategy (default: every strategy the profile measured).
    #[arg(long, value_enum)]
    pub strategy: Option<StrategyArg>,
    /// Only consider this profiled node (its id, or `root`): Δn is still chosen under the budget,
    /// and the schedule written for it.
    #[arg(long)]
    pub node: Option<String>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Re-render the selection (needs --session) and report measured error and speedup.
    #[arg(long, requires = "session")]
    pub verify: bool,
    /// With --verify: before writing, time together (interleaved with the original, one run) up
    /// to this many nodes whose own best choice under the budget is predicted too close to the
    /// selection's to tell apart, and write the fastest measured (the report's `runoff`). 1: write
    /// the prediction's choice without racing.
    #[arg(hide = true, long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=8), requires = "verify")]
    pub runoff: u32,
    /// Session to verify on (or, without --verify, the session the variant is for). When it is
    /// none of the profiled sessions, its motion is measured and the nearest profile is carried
    /// to it: the budget must hold there too, and a motion outside the profiled ones is a
    /// warning.
    #[arg(long)]
    pub session: Option<PathBuf>,
    /// What --session's motion does to the selection: `carry` (the profiles carried to it, the
    /// budget held there too) or `ignore` (select on the profiled sessions alone; --verify then
    /// only checks).
    #[arg(hide = true, long, value_enum, default_value_t = MotionUse::Carry, requires = "session")]
    pub motion: MotionUse,
    /// Choose for a Δn that changes every frame with the camera's motion (the manifest's
    /// `params.schedule`, which `render --adaptive` and `reproj-host --adaptive` apply): the node
    /// whose schedule is predicted fastest over --session's frames (or the profiled sessions'),
    /// every frame within the budget; --verify then renders and times it adaptively.
    #[arg(long)]
    pub adaptive: bool,
    #[arg(hide = true, long, help = backend_help(), value_parser = parse_backend)]
    pub backend: Option<String>,
    #[command(flatten)]
    pub integration: IntegrationArgs,
    /// The shader to instance instead of the profile's (it must be the profiled shader up to
    /// comments and formatting).
    #[arg(hide = true, long)]
    pub shader: Option<PathBuf>,
    /// Also write every pass in these languages, beside its WGSL (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub lang: Vec<LangArg>,
    /// The value of an `override` constant in the --lang passes, NAME=VALUE (repeatable; the
    /// others keep their defaults).
    #[arg(hide = true, long = "override", value_name = "NAME=VALUE", value_parser = override_value)]
    pub overrides: Vec<(String, f64)>,
    /// Exit with code 3 when the selection's speedup (measured with --verify, else predicted) is
    /// below this: for CI, "nothing under the budget is worth it".
    #[arg(hide = true, long, value_parser = positive)]
    pub min_speedup: Option<f64>,
}

/// Arguments of `reproj session`.
#[derive(Debug, Args)]
pub struct SessionArgs {
    #[command(subcommand)]
    pub command: SessionCommand,
}

/// What `reproj session` does.
#[derive(Debug, clap::Subcommand)]
pub enum SessionCommand {
    /// Write a starting session for a shader: every uniform, texture, storage buffer and depth
    /// texture its fragment entry point reads, with values guessed from their names (listed on
    /// stderr), over a turning torus — so that `reproj render` runs at once.
    Init(SessionInitArgs),
}

/// Arguments of `reproj session init`.
#[derive(Debug, Args)]
pub struct SessionInitArgs {
    /// The shader: WGSL, GLSL (`.glsl`, `.frag`) or SPIR-V (`.spv`), by extension.
    pub shader: PathBuf,
    /// The shader's language, when its extension does not say.
    #[arg(hide = true, long, value_enum)]
    pub lang_in: Option<LangInArg>,
    #[command(flatten)]
    pub input: ShaderInputArgs,
    /// Fragment entry point (needed when the module has several).
    #[arg(long)]
    pub entry: Option<String>,
    /// Write the session to this file (printed on stdout when left out).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Replace `--out` when it exists.
    #[arg(hide = true, long)]
    pub force: bool,
    /// Frames in the session.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: u32,
    /// Render size, width and height in pixels.
    #[arg(long, num_args = 2, value_names = ["W", "H"], default_values_t = [256u32, 256u32],
          value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub resolution: Vec<u32>,
}

/// Arguments of `reproj nodes`.
#[derive(Debug, Args)]
pub struct NodesArgs {
    /// The shader: WGSL, GLSL (`.glsl`, `.frag`) or SPIR-V (`.spv`), by extension.
    pub shader: PathBuf,
    /// The shader's language, when its extension does not say.
    #[arg(hide = true, long, value_enum)]
    pub lang_in: Option<LangInArg>,
    #[command(flatten)]
    pub input: ShaderInputArgs,
    /// Fragment entry point (needed when the module has several).
    #[arg(long)]
    pub entry: Option<String>,
    #[command(flatten)]
    pub unroll: UnrollArg,
    /// Print JSON (schema: docs/SCHEMAS.md#nodes) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Include culled nodes, with their reasons.
    #[arg(long)]
    pub all: bool,
}

/// Cache texel format.
/// `emit --motion`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MotionUse {
    Carry,
    Ignore,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CacheFormatArg {
    /// The narrowest 32-bit float format that holds the node (r32float, rg32float, rgba32float).
    F32,
    /// The narrowest 16-bit float format that holds the node (the paper's precision).
    F16,
    Rgba32float,
    Rg32float,
    R32float,
    Rgba16float,
    Rg16float,
    R16float,
}

/// At how many training periods `analyze` replays each node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SamplingArg {
    Adaptive,
    Every,
}

/// How a variant's passes are laid out (docs/PASSES.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum StrategyArg {
    /// The paper's three passes: reproject, recompute, shade.
    #[value(name = "3pass")]
    ThreePass,
    /// Reproject and shade the hits, then the whole shader at the misses.
    #[value(name = "2pass")]
    TwoPass,
    /// One pass: reproject, compute the node inline on a miss, shade; two color targets.
    Fused,
}

/// How pass 1 reconstructs the previous payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ReconstructArg {
    /// One filtered fetch (the paper's bilinear reconstruction).
    Bilinear,
    /// The nearest texel (cheaper, blockier; needs no filtering).
    Nearest,
    /// Catmull-Rom in five filtered fetches, clamped to the 2×2 nearest texels (nine fetches:
    /// dearer, sharper; a value carried over many frames blurs less).
    #[value(name = "catmull-rom")]
    CatmullRom,
    /// analyze only: per node, race catmull-rom against bilinear at equal error and keep the
    /// faster beyond doubt (recorded per node in the profile).
    Auto,
}

/// How a variant caches: shared by `instance`, `render` and `analyze`.
#[derive(Debug, Clone, Copy, Args)]
pub struct CacheArgs {
    /// Variant strategy (instance and render: default 3pass; analyze: default every strategy
    /// that can win).
    #[arg(long, value_enum)]
    pub strategy: Option<StrategyArg>,
    /// Refresh block size k (1 or even, so blocks align with 2×2 quads; default 8 for fused, 4
    /// otherwise). analyze also takes `auto`: per node, race a larger block (32, at most an
    /// eighth of the frame) against the default at one Δn (the longest at most half the session)
    /// and keep it where it measures more accurate and not slower (recorded in the profile).
    #[arg(hide = true, long, value_parser = block_choice)]
    pub block: Option<crate::values::BlockArg>,
    /// Relative depth tolerance of the cache hit test.
    #[arg(hide = true, long, default_value_t = 0.01, value_parser = depth_epsilon)]
    pub depth_epsilon: f32,
    /// Cache texel format.
    #[arg(hide = true, long, value_enum, default_value = "f32")]
    pub cache_format: CacheFormatArg,
    /// Payload reconstruction in pass 1 (`auto`: analyze chooses per node by measurement).
    #[arg(hide = true, long, value_enum, default_value = "bilinear")]
    pub reconstruct: ReconstructArg,
}

/// How the written passes fit into a host engine: shared by `instance` and `emit`.
#[derive(Debug, Clone, Args)]
pub struct IntegrationArgs {
    /// Bind group of the variant's added bindings (default: the lowest one the shader does not
    /// use, else its highest; at most 3). A group the shader uses is shared: the added bindings
    /// go past its own.
    #[arg(long)]
    pub group: Option<u32>,
    /// What the engine drew before that the first passes keep instead of clearing: `frame` (its
    /// color) and `depth` (its opaque geometry, so the variant is hidden behind it);
    /// comma-separated. Default: both cleared, as a standalone pass would.
    #[arg(long, value_enum, value_delimiter = ',', value_name = "TARGETS")]
    pub load: Vec<LoadTarget>,
    /// How the first pass that writes the frame color starts it (as `--load frame`).
    #[arg(hide = true, long, value_enum, default_value = "clear")]
    pub frame_load: FrameLoadArg,
    /// How the first pass starts the depth target (as `--load depth`).
    #[arg(hide = true, long, value_enum, default_value = "clear")]
    pub depth_load: FrameLoadArg,
    /// Where the lookup finds a fragment in the previous frame: the `vertex` stage's extra output
    /// (the previous clip position), or the engine's `motion-vectors` texture (.xy = uv_current −
    /// uv_previous, texture UV, y down; docs/PASSES.md).
    #[arg(long, value_enum, default_value = "vertex")]
    pub reproject: ReprojectArg,
}

/// How the frame (or depth) target starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FrameLoadArg {
    Clear,
    Load,
}

/// A target the engine drew before (`--load`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LoadTarget {
    Frame,
    Depth,
}

impl IntegrationArgs {
    /// Whether the first pass loads the frame color (`--load frame` or `--frame-load load`).
    pub fn loads_frame(&self) -> bool {
        self.load.contains(&LoadTarget::Frame) || self.frame_load == FrameLoadArg::Load
    }

    /// Whether the first pass loads the depth (`--load depth` or `--depth-load load`).
    pub fn loads_depth(&self) -> bool {
        self.load.contains(&LoadTarget::Depth) || self.depth_load == FrameLoadArg::Load
    }
}

/// Where the previous position comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ReprojectArg {
    Vertex,
    MotionVectors,
}

/// Input language of the shader.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LangInArg {
    Wgsl,
    /// GLSL fragment shader, compiled by glslang (glslangValidator; naga's GLSL front end where
    /// glslang is not installed).
    Glsl,
    /// SPIR-V binary.
    Spv,
}

/// Language the passes are written in besides WGSL.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LangArg {
    /// WGSL only (always written: the manifest and the replay use it).
    Wgsl,
    /// GLSL 4.50 (`.frag`, the pass's entry point).
    Glsl,
    /// HLSL, shader model 5.1 (`.hlsl`).
    Hlsl,
    /// Metal Shading Language 2.1 (`.metal`).
    Msl,
    /// SPIR-V binary (`.spv`).
    Spv,
}

/// Arguments of `reproj instance`.
#[derive(Debug, Args)]
pub struct InstanceArgs {
    /// The shader: WGSL, GLSL (`.glsl`, `.frag`) or SPIR-V (`.spv`), by extension.
    pub shader: PathBuf,
    /// The shader's language, when its extension does not say.
    #[arg(hide = true, long, value_enum)]
    pub lang_in: Option<LangInArg>,
    #[command(flatten)]
    pub input: ShaderInputArgs,
    /// Node id from `reproj nodes`, or `root` for the final color; several ids separated by
    /// commas (`3,7`) cache those nodes together, packed in one payload of at most 4 floats.
    #[arg(long)]
    pub node: String,
    #[command(flatten)]
    pub unroll: UnrollArg,
    /// Output directory (created if needed).
    #[arg(long, value_parser = output_path)]
    pub out: PathBuf,
    /// Fragment entry point (needed when the module has several).
    #[arg(long)]
    pub entry: Option<String>,
    /// Default refresh period Δn written to the manifest (the passes take it at run time).
    #[arg(long, default_value_t = 8, value_parser = refresh_period)]
    pub delta_n: u32,
    #[command(flatten)]
    pub cache: CacheArgs,
    #[command(flatten)]
    pub integration: IntegrationArgs,
    /// Also write every pass in these languages, beside its WGSL (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub lang: Vec<LangArg>,
    /// The value of an `override` constant in the --lang passes, NAME=VALUE (repeatable; the
    /// others keep their defaults).
    #[arg(hide = true, long = "override", value_name = "NAME=VALUE", value_parser = override_value)]
    pub overrides: Vec<(String, f64)>,
    /// Print what was written as JSON (`reproj.instance`: the files and the manifest).
    #[arg(long)]
    pub json: bool,
}
