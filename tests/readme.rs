//! The README's Rust examples are the crate's doc examples (which
//! `cargo test` runs): every line of every ```` ```rust ```` block of
//! README.md must appear, in order, among the doc lines of src/lib.rs.

use std::fs;

#[test]
fn readme_rust_examples_are_the_tested_doc_examples() {
    let readme = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let lib = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/lib.rs")).unwrap();
    let docs: Vec<&str> =
        lib.lines().filter_map(|l| l.strip_prefix("//!")).map(|l| l.strip_prefix(' ').unwrap_or(l)).collect();
    let mut blocks = 0;
    let mut rest = readme.as_str();
    while let Some(start) = rest.find("```rust\n") {
        let body = &rest[start + 8..];
        let end = body.find("```").expect("unterminated ```rust block in README.md");
        let mut at = 0;
        for line in body[..end].lines().filter(|l| !l.trim().is_empty()) {
            match docs[at..].iter().position(|d| *d == line) {
                Some(i) => at += i + 1,
                None => panic!("README.md line not in src/lib.rs's doc examples (in order): {line:?}"),
            }
        }
        blocks += 1;
        rest = &body[end + 3..];
    }
    assert_eq!(blocks, 2, "README.md should hold the std and the no_std example");
}
