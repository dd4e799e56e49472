//! Files in and out, one way for every reproj command.
//!
//! - [`write_file`] writes one file atomically: a temporary file in the same directory, flushed to
//!   disk, then renamed over the target. A reader sees the old file or the new one, never a torn one.
//! - [`check_target`] checks, before any work, that an output file can be written and that only
//!   reproj's own output of that kind would be replaced ([`Owner`]); [`write_owned_file`] checks
//!   again and writes.
//! - [`write_files`] writes a set of files that belong together: all or none are replaced.
//! - [`StagedDir`] writes a whole output directory (a variant, an `emit` result, rendered frames)
//!   into a temporary sibling and swaps it in on [`StagedDir::commit`]; dropped without a commit it
//!   removes itself, so a failure anywhere leaves the previous directory exactly as it was.
//! - [`read_json`] / [`parse_json`] read a versioned JSON document (`"schema"` + `"version"`) into
//!   a typed value with one error format ([`ReadError`]): the file, and the field or line and column.
//! - [`read_input`] reads any user file (shader, session, mesh, image): only a regular file, within
//!   a size limit per [`InputKind`], so a pipe, a device or a huge file is refused, not waited on.
//!
//! - [`remove_registered`] removes every temporary file, staged directory and lock of the process
//!   (for a signal handler); [`sweep_stale`] removes those of processes that are gone;
//!   [`OutputLock`] lets one process at a time write an output.
//!
//! Tests make a write fail mid-way through the `REPROJ_IO_FAIL` environment variable (see
//! [`FAIL_ENV`]), so each writer's "a failure keeps the previous output" is checked through the
//! real binary.

mod cleanup;
mod error;
mod holder;
mod input;
mod json;
mod owner;
mod write;

pub use cleanup::{OutputLock, cleanup_started, remove_registered, sweep_stale};
pub use input::{InputError, InputKind, MAX_INPUT_ENV, check_input, read_input, read_input_string};
pub use json::{Kind, ReadError, parse_json, read_json};
pub use owner::{Owner, check_target, write_owned_file};
pub use write::{FAIL_ENV, Replace, StagedDir, WriteError, write_file, write_files};

/// FNV-1a 64-bit hash of some bytes, as 16 hex digits: a stable fingerprint of the shader and
/// session a profile was measured on, and of the shader a variant was made from (not a
/// cryptographic hash).
pub fn content_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}
