//! Bad arguments: values checked at the door (exit 2 naming the flag and the range) before any
//! rendering, options that contradict each other, unknown subcommands, and output paths that are
//! other people's files (refused before any work, left as they were).

use super::{Case, case};

pub(super) fn cases() -> Vec<Case> {
    let mut v = vec![
        // Arguments.
        case(
            "render zero refresh period",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--node",
                "root",
                "--delta-n",
                "0",
            ],
            "refresh period",
        ),
        case(
            "analyze period 1",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--delta-n",
                "1,4",
            ],
            "refresh period",
        ),
        case(
            "analyze period not a number",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--delta-n",
                "a",
            ],
            "--delta-n",
        ),
        case(
            "analyze unknown node",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--nodes",
                "99999",
                "--delta-n",
                "2,4",
                "--holdout",
                "3",
            ],
            "no node 99999",
        ),
        case(
            "analyze shard out of range",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--shard",
                "3/3",
            ],
            "3/3",
        ),
        case(
            "analyze shard not a shard",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--shard",
                "half",
            ],
            "half",
        ),
        case(
            "analyze set search over fewer than two nodes",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--set-top",
                "1",
            ],
            "--set-top",
        ),
        case(
            "analyze no sets and a set option",
            &[],
            &[
                "analyze",
                "good.wgsl",
                "--session",
                "good.json",
                "--no-sets",
                "--set-max-nodes",
                "2",
            ],
            "--no-sets",
        ),
        case(
            "emit negative budget",
            &[],
            &[
                "emit",
                "--max-error",
                "-1",
                "--profile",
                "good.profile.json",
                "--out",
                "out",
            ],
            "--max-error",
        ),
        case(
            "emit NaN budget",
            &[],
            &[
                "emit",
                "--max-error",
                "NaN",
                "--profile",
                "good.profile.json",
                "--out",
                "out",
            ],
            "--max-error",
        ),
        case(
            "emit node is not a number",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--node",
                "abc",
                "--out",
                "out",
            ],
            "--node abc",
        ),
        case(
            "emit motion without a session",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--motion",
                "ignore",
                "--out",
                "out",
            ],
            "--session",
        ),
        case(
            "render adaptive without a variant",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--adaptive",
            ],
            "--variant",
        ),
        case(
            "profile is a directory",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "variant",
                "--out",
                "out",
            ],
            "variant",
        ),
        case(
            "unknown subcommand",
            &[],
            &["optimize", "good.wgsl"],
            "optimize",
        ),
    ];
    // Numbers checked at the door (exit 2 naming the flag and the range), before any rendering.
    let analyze = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut a = vec!["analyze", "good.wgsl", "--session", "good.json"];
        a.extend_from_slice(extra);
        a
    };
    for (name, extra, expect) in [
        ("analyze odd block", &["--block", "3"][..], "--block"),
        ("analyze zero block", &["--block", "0"][..], "--block"),
        ("analyze huge block", &["--block", "4096"][..], "--block"),
        (
            "analyze zero frames",
            &["--max-frames", "0"][..],
            "--max-frames",
        ),
        (
            "analyze negative epsilon",
            &["--depth-epsilon=-1"][..],
            "--depth-epsilon",
        ),
        (
            "analyze NaN epsilon",
            &["--depth-epsilon", "NaN"][..],
            "--depth-epsilon",
        ),
        (
            "analyze repeated period",
            &["--delta-n", "2,2,2"][..],
            "named twice",
        ),
        (
            "analyze period also held out",
            &["--delta-n", "2,4", "--holdout", "4"][..],
            "named twice",
        ),
        (
            "analyze period far too long",
            &["--delta-n", "1000000"][..],
            "--delta-n",
        ),
        (
            "analyze period past ten sessions",
            &["--delta-n", "2,4", "--holdout", "3,100"][..],
            "more than 10 times",
        ),
        ("analyze no nodes", &["--max-nodes", "0"][..], "--max-nodes"),
        (
            "analyze saving above 1",
            &["--min-saving", "2"][..],
            "--min-saving",
        ),
    ] {
        v.push(case(name, &[], &analyze(extra), expect));
    }
    v.extend([
        case(
            "emit zero longest period",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--max-delta-n",
                "0",
                "--out",
                "out",
            ],
            "--max-delta-n",
        ),
        case(
            "emit NaN budget",
            &[],
            &[
                "emit",
                "--max-error",
                "NaN",
                "--profile",
                "good.profile.json",
                "--out",
                "out",
            ],
            "--max-error",
        ),
        case(
            "emit NaN min speedup",
            &[],
            &[
                "emit",
                "--max-error",
                "0.01",
                "--profile",
                "good.profile.json",
                "--min-speedup",
                "NaN",
                "--out",
                "out",
            ],
            "--min-speedup",
        ),
        case(
            "instance NaN epsilon",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--out",
                "v2",
                "--depth-epsilon",
                "NaN",
            ],
            "--depth-epsilon",
        ),
        case(
            "instance period 0",
            &[],
            &[
                "instance",
                "good.wgsl",
                "--node",
                "root",
                "--out",
                "v2",
                "--delta-n",
                "0",
            ],
            "--delta-n",
        ),
        case(
            "render zero frames",
            &[],
            &[
                "render",
                "good.wgsl",
                "--session",
                "good.json",
                "--max-frames",
                "0",
            ],
            "--max-frames",
        ),
        case(
            "compare zero longest period",
            &[],
            &[
                "compare",
                "good.wgsl",
                "--session",
                "good.json",
                "--speedup",
                "2",
                "--max-delta-n",
                "1",
            ],
            "--max-delta-n",
        ),
        // Other people's files: refused before any work, left as they were.
        case(
            "analyze over a user's file",
            &[("u.txt", "my notes\n")],
            &analyze(&["--out", "u.txt"]),
            "not a reproj.profile",
        ),
        case(
            "analyze over a user's chart name",
            &[("p2.tradeoff.svg", "my notes\n")],
            &analyze(&["--out", "p2.json"]),
            "p2.tradeoff.svg",
        ),
        case(
            "analyze into a directory",
            &[("d/keep.txt", "mine\n")],
            &analyze(&["--out", "d"]),
            "is a directory",
        ),
        case(
            "analyze under a file",
            &[("f", "mine\n")],
            &analyze(&["--out", "f/p.json"]),
            "f/p.json",
        ),
        case(
            "merge over a user's file",
            &[("u.txt", "my notes\n")],
            &["merge", "good.profile.json", "--out", "u.txt"],
            "not a reproj.profile",
        ),
        case(
            "merge over a session",
            &[],
            &["merge", "good.profile.json", "--out", "good.json"],
            "not a reproj.profile",
        ),
        case(
            "report over a user's page",
            &[("u.html", "<html><title>mine</title></html>\n")],
            &["report", "good.profile.json", "--out", "u.html"],
            "u.html",
        ),
    ]);
    v
}
