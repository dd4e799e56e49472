//! Every integration-test file of the workspace runs. A crate with several test files has one test
//! binary, `tests/tests.rs`, whose modules they are, and sets `autotests = false`: cargo then
//! compiles only what that root declares, and would pass over a new file without a word.

use std::collections::BTreeSet;
use std::path::Path;

#[test]
fn every_test_file_is_a_module_of_its_crates_test_binary() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut checked = Vec::new();
    for dir in std::fs::read_dir(&crates).unwrap() {
        let dir = dir.unwrap().path();
        let Ok(manifest) = std::fs::read_to_string(dir.join("Cargo.toml")) else {
            continue;
        };
        if !manifest.lines().any(|l| l.trim() == "autotests = false") {
            continue;
        }
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        let tests = dir.join("tests");
        let root = std::fs::read_to_string(tests.join("tests.rs"))
            .unwrap_or_else(|e| panic!("{name}: autotests = false without tests/tests.rs: {e}"));
        let declared: BTreeSet<&str> = root
            .lines()
            .filter_map(|l| l.trim().strip_prefix("mod ")?.strip_suffix(';'))
            .collect();
        for entry in std::fs::read_dir(&tests).unwrap() {
            let path = entry.unwrap().path();
            let file = path.file_name().unwrap().to_string_lossy().into_owned();
            let module = if path.is_dir() {
                assert!(
                    !path.join("main.rs").exists(),
                    "{name}: tests/{file}/main.rs is never compiled (autotests = false): name it \
                     mod.rs and declare `mod {file};` in tests/tests.rs"
                );
                if !path.join("mod.rs").exists() {
                    continue; // data, fixtures, snapshots, or files a module names by #[path]
                }
                file.as_str()
            } else {
                match file.strip_suffix(".rs") {
                    Some("tests") | None => continue,
                    Some(m) => m,
                }
            };
            assert!(
                declared.contains(module),
                "{name}: tests/{file} is not declared in tests/tests.rs (`mod {module};`), so it \
                 never runs"
            );
        }
        checked.push(name);
    }
    assert!(
        checked.contains(&"reproj-cli".to_owned()),
        "this crate's own tests are checked: {checked:?}"
    );
}
