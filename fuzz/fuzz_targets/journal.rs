//! Arbitrary bytes as an analysis journal (JSON Lines), read as `Journal::open` reads a file:
//! lossy UTF-8, the header checked against the analysis' key, every record that parses and whose
//! numbers are measurements kept, the others dropped. Then what is kept is written back as
//! `Journal::open` rewrites the file, and that text must read back to the same records. Errors
//! are fine; a panic is a bug.
#![no_main]

use libfuzzer_sys::fuzz_target;
use reproj_models::journal::{header_line, original_line, parse, record_line};

/// The key of the seed journals (`run.sh` writes them with it); fuzzed inputs may keep it.
const KEY: &str = "fuzz";

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let parsed = parse(&text, KEY);
    if !parsed.header_matches {
        assert!(parsed.done.is_empty() && parsed.original.is_none() && parsed.dropped == 0);
        return;
    }
    // Rewritten as `Journal::open` does, the journal reads back whole: nothing dropped.
    let mut again = header_line(KEY);
    if let Some(o) = &parsed.original {
        again.push_str(&original_line(o));
    }
    for (k, r) in &parsed.done {
        again.push_str(&record_line(k, r));
    }
    let reread = parse(&again, KEY);
    assert!(reread.header_matches, "{again}");
    assert_eq!(
        reread.dropped, 0,
        "a rewritten journal drops lines:\n{again}"
    );
    assert_eq!(reread.done.len(), parsed.done.len(), "{again}");
    assert!(
        reread.done == parsed.done,
        "records change through a rewrite:\n{again}"
    );
    assert!(reread.original == parsed.original, "{again}");
});
