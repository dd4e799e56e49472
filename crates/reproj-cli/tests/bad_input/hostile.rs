//! Hostile inputs that the case table cannot hold: named pipes, devices, files past the
//! size limits, an expression chain that overflowed the stack, and stdout that cannot be
//! written. Each runs the real binary under a time limit (a hang fails the test rather than
//! blocking it), and must end with its exit code and a message naming the file.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::root;

/// Longest any case may run: far past a refusal, far short of a hang.
const LIMIT: Duration = Duration::from_secs(60);

/// Run `reproj ARGS` in `dir` with `env` under [`LIMIT`]: exit code and stderr. A run past the
/// limit is killed and fails the test.
fn run_bounded(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_reproj"))
        .args(args)
        .current_dir(dir)
        .env("NODEVICE_SELECT", "1")
        .envs(env.iter().copied())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run reproj");
    // Read on its own thread: a long diagnostic would fill the pipe and block the child.
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut err = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut err).unwrap();
        err
    });
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return (status.code().unwrap_or(-1), reader.join().unwrap());
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("reproj {args:?} ran past {LIMIT:?}: it hangs");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// A folder with the good shader and session of the corpus.
fn good_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let data = root().join("crates/reproj-replay/tests/data");
    std::fs::copy(data.join("tiny.wgsl"), dir.path().join("good.wgsl")).unwrap();
    std::fs::copy(data.join("tiny_moving.json"), dir.path().join("good.json")).unwrap();
    dir
}

fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo")
        .arg(path)
        .status()
        .is_ok_and(|s| s.success());
    assert!(ok, "mkfifo {}", path.display());
}

/// The good session with `edit` applied, written as `name`.
fn session_with(dir: &Path, name: &str, edit: &dyn Fn(&mut serde_json::Value)) {
    let text = std::fs::read_to_string(dir.join("good.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    edit(&mut v);
    std::fs::write(dir.join(name), v.to_string()).unwrap();
}

/// Exit 2, one `error` line holding `expect`, no panic.
fn refused(args: &[&str], (code, err): (i32, String), expect: &str) {
    assert_eq!(code, 2, "{args:?}: {err}");
    assert!(err.contains(expect), "{args:?}: no `{expect}` in:\n{err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    let errors = err.lines().filter(|l| l.starts_with("error")).count();
    assert_eq!(errors, 1, "{args:?}: {err}");
}

fn render(session: &'static str) -> Vec<&'static str> {
    vec![
        "render",
        "good.wgsl",
        "--session",
        session,
        "--max-frames",
        "2",
    ]
}

#[test]
fn named_pipes_are_refused_without_blocking() {
    let dir = good_dir();
    let d = dir.path();
    mkfifo(&d.join("pipe.wgsl"));
    mkfifo(&d.join("pipe.json"));
    mkfifo(&d.join("pipe.png"));
    session_with(d, "tex.json", &|v| {
        v["textures"]["albedo_map"] = serde_json::json!({"file": "pipe.png"})
    });
    let args = ["nodes", "pipe.wgsl"];
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "pipe.wgsl: it is a named pipe",
    );
    let args = render("pipe.json");
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "pipe.json: it is a named pipe",
    );
    let args = render("tex.json");
    refused(&args, run_bounded(d, &args, &[]), "it is a named pipe");
}

#[test]
fn devices_are_refused_before_reading() {
    let dir = good_dir();
    let d = dir.path();
    let args = ["nodes", "/dev/urandom"];
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "/dev/urandom: it is a device",
    );
    let args = render("/dev/urandom");
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "/dev/urandom: it is a device",
    );
    // `/dev/zero` as a mesh once the session may name it: was an 8 GB allocation and an abort.
    session_with(d, "zero.json", &|v| {
        v["geometry"]["objects"][0]["mesh"] = serde_json::json!({"obj": {"path": "/dev/zero"}})
    });
    let mut args = render("zero.json");
    args.push("--allow-outside-paths");
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "/dev/zero: it is a device",
    );
}

#[test]
fn files_past_the_size_limit_are_refused_naming_size_and_limit() {
    let dir = good_dir();
    let d = dir.path();
    // A sparse file: 17 MiB that take no disk.
    let big = std::fs::File::create(d.join("big.wgsl")).unwrap();
    big.set_len(17 << 20).unwrap();
    let args = ["nodes", "big.wgsl"];
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "big.wgsl: 17825792 bytes is over the 16 MiB limit for a shader",
    );
    // The one variable lowers (or raises) every limit.
    let session = std::fs::read(d.join("good.json")).unwrap();
    let mut padded = session.clone();
    padded.extend(std::iter::repeat_n(b' ', 2 << 20));
    std::fs::write(d.join("padded.json"), padded).unwrap();
    let args = render("padded.json");
    refused(
        &args,
        run_bounded(d, &args, &[("REPROJ_MAX_INPUT_MB", "1")]),
        "is over the 1 MiB limit",
    );
}

/// A flat chain of 20,000 additions overflowed the stack in `reproj nodes`.
#[test]
fn a_long_flat_expression_chain_is_refused_not_a_stack_overflow() {
    let dir = good_dir();
    let d = dir.path();
    let sum = vec!["1.0"; 20_000].join(" + ");
    std::fs::write(
        d.join("chain.wgsl"),
        format!(
            "@fragment\nfn main() -> @location(0) vec4<f32> {{\n    let x = {sum};\n    return vec4<f32>(x);\n}}\n"
        ),
    )
    .unwrap();
    let args = ["nodes", "chain.wgsl"];
    refused(&args, run_bounded(d, &args, &[]), "levels deep");
}

/// A `.vert` file is a vertex shader: said so, not parsed as WGSL.
#[test]
fn another_glsl_stage_is_refused_by_its_extension() {
    let dir = good_dir();
    let d = dir.path();
    std::fs::write(
        d.join("s.vert"),
        "#version 450\nvoid main() { gl_Position = vec4(0.0); }\n",
    )
    .unwrap();
    let args = ["nodes", "s.vert"];
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "reproj optimizes fragment shaders",
    );
}

/// Output that cannot be written to stdout: its own exit code (5) and message, never 0 or 1.
#[test]
fn a_full_or_closed_stdout_exits_5() {
    let dir = good_dir();
    let d = dir.path();
    let bin = env!("CARGO_BIN_EXE_reproj");
    for redirect in ["> /dev/full", ">&-"] {
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!("exec '{bin}' nodes good.wgsl {redirect}"))
            .current_dir(d)
            .env("NODEVICE_SELECT", "1")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(5), "{redirect}: {err}");
        assert!(
            err.contains("could not write the output to stdout"),
            "{redirect}: {err}"
        );
    }
    // `> /dev/null` is a place the user chose: not an error.
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("exec '{bin}' nodes good.wgsl > /dev/null"))
        .current_dir(d)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
}

/// A 16M-element private array segfaulted `render` after 18 s at 7 GB: refused when the shader
/// is read, by every command, naming the variable, its size, the budget and how to raise it.
#[test]
fn a_private_array_past_the_gpu_memory_budget_is_refused_when_read() {
    let dir = good_dir();
    let d = dir.path();
    std::fs::write(
        d.join("big.wgsl"),
        "var<private> big: array<f32, 16777216>;\n@fragment\nfn main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    big[u32(p.x)] = p.y;\n    return vec4<f32>(big[u32(p.y)]);\n}\n",
    )
    .unwrap();
    let expect = "big.wgsl: `big` (private) takes 67108864 bytes per invocation";
    for args in [
        vec!["nodes", "big.wgsl"],
        vec![
            "render",
            "big.wgsl",
            "--session",
            "good.json",
            "--max-frames",
            "2",
        ],
    ] {
        let (code, err) = run_bounded(d, &args, &[]);
        refused(&args, (code, err.clone()), expect);
        assert!(
            err.contains("over the GPU memory budget of 2048 MiB")
                && err.contains("REPROJ_MAX_SHADER_MEMORY_MB"),
            "{args:?}: {err}"
        );
    }
    // Raised past it: read (nodes lists it).
    let args = ["nodes", "big.wgsl"];
    let (code, err) = run_bounded(d, &args, &[("REPROJ_MAX_SHADER_MEMORY_MB", "8000000")]);
    assert_eq!(code, 0, "{err}");
}

/// An OBJ of NaN vertices gave a mesh that "covers no pixel", the NaN never named: refused,
/// naming the file, the line and the number.
#[test]
fn an_obj_with_a_nan_vertex_is_refused_naming_line_and_value() {
    let dir = good_dir();
    let d = dir.path();
    std::fs::write(d.join("nan.obj"), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    session_with(d, "nan.json", &|v| {
        v["geometry"]["objects"][0]["mesh"] = serde_json::json!({"obj": {"path": "nan.obj"}})
    });
    let args = render("nan.json");
    refused(
        &args,
        run_bounded(d, &args, &[]),
        "nan.obj:2: vertex position `nan` is not a finite number",
    );
}
