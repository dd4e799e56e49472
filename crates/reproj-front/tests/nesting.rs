//! WGSL nested past naga's parser limit is a user error at a place in the file, naming the limit
//! (naga's own error has no position and calls itself internal).

use std::path::Path;

use reproj_front::{FrontError, load_file};

fn error(name: &str) -> FrontError {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name);
    load_file(&path).expect_err("past the nesting limit")
}

#[test]
fn two_hundred_parentheses() {
    let e = error("nested_parens_200.wgsl");
    assert!(e.is_user_error());
    let line = e.to_string();
    // The 198th parenthesis: the statement and the `let`'s expression are two levels more.
    assert!(
        line.ends_with(
            "nested_parens_200.wgsl:4:210: expressions and blocks nest too deeply \
             (the WGSL parser allows 200 levels)"
        ),
        "{line}"
    );
    let rendered = e.diagnostic().expect("a source diagnostic").render();
    assert!(rendered.contains("nesting depth 199 here"), "{rendered}");
    assert!(
        rendered.contains("split the expression with `let`s"),
        "{rendered}"
    );
    assert!(!rendered.contains("internal"), "{rendered}");
}

#[test]
fn five_thousand_parentheses() {
    let e = error("nested_parens_5000.wgsl");
    assert!(e.is_user_error());
    assert!(
        e.to_string().ends_with(
            "nested_parens_5000.wgsl:4:210: expressions and blocks nest too deeply \
                        (the WGSL parser allows 200 levels)"
        ),
        "{e}"
    );
}
