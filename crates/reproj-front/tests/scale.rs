//! Loading (parse, normalization, node analysis) scales linearly with the length of straight-line
//! code.
//!
//! `load_long_chain` and `parsing_is_linear` run in CI (the second fails if naga's typifier is
//! quadratic again: `vendor/naga/REPROJ-PATCH.md`); the benchmark is ignored and prints the time of
//! each phase, and in release holds 56k lines to 5 s:
//!
//! ```text
//! cargo test --release -p reproj-front --test integration scale:: -- --ignored --nocapture
//! ```

use std::path::Path;
use std::time::Instant;

use reproj_front::{enumerate, normalize, parse_shader};

/// A fragment shader of `lines` chained `let`s, each reading the one before, every fourth also
/// an earlier value and the input.
fn straight_line(lines: usize) -> String {
    let mut src = String::from(
        "@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {\n    \
         var x = p.x;\n    let a0 = sin(x) * 1.01;\n",
    );
    for i in 1..lines {
        let prev = i - 1;
        let line = match i % 4 {
            0 => format!("let a{i} = a{prev} * a{prev} + 0.5;"),
            1 => format!("let a{i} = sin(a{prev}) * 1.01;"),
            2 => format!("let a{i} = a{prev} + a{} * 0.25;", i / 2),
            _ => format!("let a{i} = a{prev} * p.y - x;"),
        };
        src.push_str("    ");
        src.push_str(&line);
        src.push('\n');
    }
    src.push_str(&format!(
        "    return vec4<f32>(a{}, 0.0, 0.0, 1.0);\n}}\n",
        lines - 1
    ));
    src
}

/// A long chain loads whole (in seconds in a debug build; it took minutes when every node searched
/// the whole function): two nodes a line, the output's cost is the whole shader's, and a link of
/// the chain whose operand is read again shares all but its own multiply with the rest.
#[test]
fn load_long_chain() {
    let lines = 20_000;
    let shader = parse_shader(Path::new("scale.wgsl"), straight_line(lines)).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    assert_eq!(table.nodes.len(), 2 * lines + 9);
    assert_eq!(table.root().cost, table.total_cost);
    assert_eq!(table.cacheable().count(), 2 * lines + 1);
    // `a{j} * a{j}`, with `a{j}` read again at line `2 j`.
    let j = 4 * (lines / 16) + 3;
    let link = table
        .nodes
        .iter()
        .find(|n| n.text == format!("a{j} * a{j}"))
        .expect("a link of the chain");
    assert!(link.cacheable);
    // Its own multiply is the only part nothing else needs.
    assert_eq!(link.overlap, link.cost - 1.0);
}

/// The least of three parse times of `src`, in seconds.
fn parse_seconds(src: &str) -> f64 {
    (0..3)
        .map(|_| {
            let t = Instant::now();
            parse_shader(Path::new("scale.wgsl"), src.to_owned()).unwrap();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Eight times the lines parse in about eight times the time. naga 30's typifier, growing one
/// expression at a time from the start of the arena, made it about 64 times (0.23 s for 8k lines,
/// 16 s for 56k, in release); the bound leaves room for a loaded machine.
#[test]
fn parsing_is_linear() {
    let small = parse_seconds(&straight_line(4_000));
    let large = parse_seconds(&straight_line(32_000));
    let ratio = large / small.max(1e-4);
    assert!(
        ratio < 24.0,
        "parsing 8x the lines took {ratio:.1}x the time ({small:.3} s, {large:.3} s): quadratic?"
    );
}

#[test]
#[ignore = "benchmark: run in release with --ignored --nocapture"]
fn bench_straight_line() {
    for lines in [1_000, 2_000, 4_000, 8_000, 16_000, 56_000] {
        let src = straight_line(lines);
        let t0 = Instant::now();
        let shader = parse_shader(Path::new("scale.wgsl"), src).unwrap();
        let t1 = Instant::now();
        let norm = normalize(&shader, &Default::default()).unwrap();
        let t2 = Instant::now();
        let table = enumerate(&shader, &norm);
        let t3 = Instant::now();
        println!(
            "{lines:>6} lines: {:>4} nodes, parse {:.3} s, normalize {:.3} s, enumerate {:.3} s, total {:.3} s",
            table.nodes.len(),
            (t1 - t0).as_secs_f64(),
            (t2 - t1).as_secs_f64(),
            (t3 - t2).as_secs_f64(),
            (t3 - t0).as_secs_f64(),
        );
        if lines == 56_000 && !cfg!(debug_assertions) {
            let total = (t3 - t0).as_secs_f64();
            assert!(total < 5.0, "56k lines load in {total:.1} s (target: 5 s)");
        }
    }
}
