//! The GPU memory a shader's own arrays take, checked before any GPU work.
//!
//! Every invocation of a fragment shader has its own copy of its `private` globals and of the
//! `function` locals of the functions it runs; a GPU backs them with scratch memory for every
//! invocation it keeps in flight, and each workgroup has its own `workgroup` globals. A shader
//! with a 16M-element private array asks for gigabytes: the driver took 18 seconds and 7 GB before
//! the process died without a word. [`check_memory`] refuses such a module when it is read, naming
//! the largest variable, its size, the budget and how to raise it.
//!
//! The count is static and conservative: the bytes of every private global the entry point uses
//! and of the locals of every function it can call (all at once, as if the deepest call chain
//! held them all), times [`INVOCATIONS_IN_FLIGHT`]; workgroup globals count once per
//! [`WORKGROUP_SIZE`] invocations.

use std::path::{Path, PathBuf};

use naga::{AddressSpace, Block, Handle, Module, Statement, TypeInner};

/// The environment variable that replaces the budget, in MiB.
pub const MAX_SHADER_MEMORY_ENV: &str = "REPROJ_MAX_SHADER_MEMORY_MB";

/// The default budget, in MiB.
pub const DEFAULT_BUDGET_MIB: u64 = 2048;

/// Invocations a GPU is taken to keep in flight at once, each with its own private memory. A
/// large GPU keeps more (up to about 2,048 per multiprocessor); this is a floor, so the budget
/// refuses only what no GPU can hold: 32 KiB per invocation by default.
pub const INVOCATIONS_IN_FLIGHT: u64 = 65_536;

/// Invocations that share one copy of the workgroup globals.
pub const WORKGROUP_SIZE: u64 = 64;

/// A module whose arrays ask for more GPU memory than the budget.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{path}: `{variable}` ({space}) takes {variable_bytes} bytes per {per}; the entry point `{entry}` needs {per_invocation} bytes per invocation{workgroup}, {total_mib} MiB for {INVOCATIONS_IN_FLIGHT} invocations in flight, over the GPU memory budget of {budget_mib} MiB (set {MAX_SHADER_MEMORY_ENV} to raise it, or make the array smaller)",
    per = if *space == "workgroup" { "workgroup" } else { "invocation" },
    workgroup = if *per_workgroup > 0 { format!(" and {per_workgroup} bytes per workgroup") } else { String::new() },
)]
pub struct OverBudget {
    pub path: PathBuf,
    pub entry: String,
    /// The largest variable: a global's name, or `function::local`.
    pub variable: String,
    /// `private`, `function` or `workgroup`.
    pub space: &'static str,
    pub variable_bytes: u64,
    pub per_invocation: u64,
    pub per_workgroup: u64,
    pub total_mib: u64,
    pub budget_mib: u64,
}

/// The budget in MiB: [`MAX_SHADER_MEMORY_ENV`] when set to a positive whole number, else
/// [`DEFAULT_BUDGET_MIB`].
pub fn budget_mib() -> u64 {
    std::env::var(MAX_SHADER_MEMORY_ENV)
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .filter(|&m| m > 0)
        .unwrap_or(DEFAULT_BUDGET_MIB)
}

/// [`check_memory`] of a parsed shader against [`budget_mib`]: what every reader of a shader file
/// calls (the front end's [`crate::load::load_file_with`], and a variant's passes).
pub fn check_shader(path: &Path, shader: &crate::Shader) -> Result<(), Box<OverBudget>> {
    check_memory(path, &shader.module, &shader.info, budget_mib())
}

/// Refuse `module` (read from `path`) when one of its entry points' private, function and
/// workgroup variables take more than `budget_mib` MiB of GPU memory, counted as the module
/// documentation says. `info` is the module's validation info (which globals each entry uses).
pub fn check_memory(
    path: &Path,
    module: &Module,
    info: &naga::valid::ModuleInfo,
    budget_mib: u64,
) -> Result<(), Box<OverBudget>> {
    let budget = budget_mib.saturating_mul(1 << 20);
    for (i, ep) in module.entry_points.iter().enumerate() {
        let uses = info.get_entry_point(i);
        // (name, space, bytes) of every variable the entry point holds.
        let mut vars: Vec<(String, &'static str, u64)> = Vec::new();
        for (h, g) in module.global_variables.iter() {
            let space = match g.space {
                AddressSpace::Private => "private",
                AddressSpace::WorkGroup => "workgroup",
                _ => continue,
            };
            if uses[h].is_empty() {
                continue;
            }
            let name = g
                .name
                .clone()
                .unwrap_or_else(|| format!("global {}", h.index()));
            vars.push((name, space, type_bytes(module, g.ty)));
        }
        let mut locals = |f: &naga::Function, fname: &str| {
            for (_, l) in f.local_variables.iter() {
                let name = l.name.as_deref().unwrap_or("_");
                vars.push((
                    format!("{fname}::{name}"),
                    "function",
                    type_bytes(module, l.ty),
                ));
            }
        };
        locals(&ep.function, &ep.name);
        for f in called(module, &ep.function) {
            let func = &module.functions[f];
            locals(func, func.name.as_deref().unwrap_or("_"));
        }
        let sum = |workgroup: bool| -> u64 {
            vars.iter()
                .filter(|v| (v.1 == "workgroup") == workgroup)
                .fold(0u64, |a, v| a.saturating_add(v.2))
        };
        let (per_invocation, per_workgroup) = (sum(false), sum(true));
        let total = per_invocation
            .saturating_mul(INVOCATIONS_IN_FLIGHT)
            .saturating_add(per_workgroup.saturating_mul(INVOCATIONS_IN_FLIGHT / WORKGROUP_SIZE));
        if total <= budget {
            continue;
        }
        let Some((variable, space, variable_bytes)) = vars.into_iter().max_by_key(|v| v.2) else {
            continue;
        };
        return Err(Box::new(OverBudget {
            path: path.to_owned(),
            entry: ep.name.clone(),
            variable,
            space,
            variable_bytes,
            per_invocation,
            per_workgroup,
            total_mib: total.div_ceil(1 << 20),
            budget_mib,
        }));
    }
    Ok(())
}

/// The bytes a value of type `ty` takes, in 64 bits (an array of arrays can pass 4 GiB, where
/// naga's own `size` is a `u32`); a runtime-sized array counts one element.
fn type_bytes(module: &Module, ty: Handle<naga::Type>) -> u64 {
    match &module.types[ty].inner {
        TypeInner::Array { base, size, stride } => {
            let count = match size {
                naga::ArraySize::Constant(n) => u64::from(n.get()),
                _ => 1,
            };
            let stride = u64::from(*stride).max(type_bytes(module, *base));
            count.saturating_mul(stride)
        }
        TypeInner::Struct { members, span } => members
            .iter()
            .map(|m| u64::from(m.offset).saturating_add(type_bytes(module, m.ty)))
            .max()
            .unwrap_or(0)
            .max(u64::from(*span)),
        inner => u64::from(inner.size(module.to_ctx())),
    }
}

/// Every function `f` can call, directly or not (each once). Walked with work lists, not
/// recursion: a module's nesting and call depth are the user's.
fn called(module: &Module, f: &naga::Function) -> Vec<Handle<naga::Function>> {
    let mut seen: Vec<Handle<naga::Function>> = Vec::new();
    let mut functions = vec![f];
    while let Some(func) = functions.pop() {
        let mut blocks: Vec<&Block> = vec![&func.body];
        while let Some(block) = blocks.pop() {
            for s in block.iter() {
                match s {
                    Statement::Call { function, .. } if !seen.contains(function) => {
                        seen.push(*function);
                        functions.push(&module.functions[*function]);
                    }
                    Statement::Block(b) => blocks.push(b),
                    Statement::If { accept, reject, .. } => blocks.extend([accept, reject]),
                    Statement::Switch { cases, .. } => blocks.extend(cases.iter().map(|c| &c.body)),
                    Statement::Loop {
                        body, continuing, ..
                    } => blocks.extend([body, continuing]),
                    _ => {}
                }
            }
        }
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(wgsl: &str, budget_mib: u64) -> Result<(), Box<OverBudget>> {
        let module = naga::front::wgsl::parse_str(wgsl).unwrap();
        let info = crate::parse::validator().validate(&module).unwrap();
        check_memory(Path::new("a.wgsl"), &module, &info, budget_mib)
    }

    const SMALL: &str = "
        var<private> lut: array<vec4<f32>, 64>;
        @fragment fn main() -> @location(0) vec4<f32> { return lut[3]; }";

    #[test]
    fn a_small_array_passes() {
        check(SMALL, DEFAULT_BUDGET_MIB).unwrap();
        // 64 × 16 bytes × 65,536 invocations = 64 MiB: over a budget of 32.
        let e = check(SMALL, 32).unwrap_err();
        assert_eq!(
            (e.variable_bytes, e.per_invocation, e.total_mib),
            (1024, 1024, 64)
        );
    }

    #[test]
    fn a_huge_private_array_is_refused_naming_it_its_size_and_the_budget() {
        let e = check(
            "var<private> big: array<f32, 16777216>;
             @fragment fn main() -> @location(0) vec4<f32> { big[7] = 1.0; return vec4(big[7]); }",
            DEFAULT_BUDGET_MIB,
        )
        .unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.starts_with("a.wgsl: `big` (private) takes 67108864 bytes per invocation"),
            "{msg}"
        );
        assert!(
            msg.contains("over the GPU memory budget of 2048 MiB"),
            "{msg}"
        );
        assert!(msg.contains(MAX_SHADER_MEMORY_ENV), "{msg}");
        assert_eq!(e.total_mib, 4 << 20);
    }

    #[test]
    fn locals_of_called_functions_count_and_unused_globals_do_not() {
        let src = "
            var<private> unused: array<f32, 16777216>;
            fn helper(i: i32) -> f32 {
                var scratch: array<vec4<f32>, 100000>;
                scratch[i] = vec4(1.0);
                return scratch[i].x;
            }
            fn middle(i: i32) -> f32 { if i > 0 { return helper(i); } return 0.0; }
            @fragment fn main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
                return vec4(middle(i32(p.x)));
            }";
        let e = check(src, DEFAULT_BUDGET_MIB).unwrap_err();
        assert_eq!(e.variable, "helper::scratch");
        assert_eq!((e.space, e.variable_bytes), ("function", 1_600_000));
        // The budget raised past it: accepted.
        check(src, 200_000).unwrap();
    }

    #[test]
    fn arrays_of_arrays_past_4_gib_do_not_wrap() {
        let module = naga::front::wgsl::parse_str(
            "var<private> a: array<array<f32, 65536>, 65536>;
             @fragment fn main() -> @location(0) vec4<f32> { return vec4(a[1][2]); }",
        )
        .unwrap();
        let (h, g) = module.global_variables.iter().next().unwrap();
        assert_eq!(type_bytes(&module, g.ty), 1 << 34, "{h:?}");
    }
}
