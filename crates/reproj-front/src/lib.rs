//! The reproj front end.
//!
//! Reads a WGSL, GLSL or SPIR-V fragment shader with naga and turns it into what the rest of the pipeline works on:
//! one normalized fragment function whose output color is the root of an expression DAG (helpers
//! inlined, local loads forwarded in straight-line code), and the list of candidate nodes of that DAG,
//! each cacheable or culled with a reason. Results live in side tables keyed by naga
//! `Handle<Expression>`; the IR is only rebuilt, never annotated.

#[cfg(feature = "compose")]
pub mod compose;
pub mod cost;
pub mod depth;
pub mod diagnostic;
pub mod directives;
pub mod enables;
mod exits;
pub mod fill_in;
pub mod glslang;
mod graph;
pub mod input;
pub mod ir;
pub mod liveness;
pub mod load;
pub mod memory;
pub mod names;
pub mod nodes;
pub mod normalize;
pub mod parse;
pub mod rebuild;
pub mod shader;
pub mod unroll;
pub mod wgsl;

pub use diagnostic::{Message, SourceDiagnostic};
pub use directives::{HiddenEntries, HiddenEntry};
pub use input::{DefValue, DefsPreset, InputWarning, ShaderInput, parse_def};
pub use load::{CullSummary, LoadOptions, Loaded, load, load_file, load_file_as, load_file_with};
pub use nodes::{CullReason, Node, NodeTable, enumerate};
pub use normalize::{NormalizeOptions, Normalized, normalize};
pub use parse::{parse_glsl, parse_glsl_with, parse_shader, parse_spirv};
pub use shader::{FrontError, Lang, Shader, validator};
pub use unroll::{UnrollOptions, Unrolled, unroll};
pub use wgsl::write_wgsl;
