//! The scene editor's server: its answers, the contact tool, the forms, the figures beside their tables and the saves that never lose the user's work. One test binary.

mod answer;
mod build;
mod contact;
mod edr;
mod figures_print_the_table;
mod form;
mod survey;
mod writes;

use std::path::Path;

/// The text of the example case `name` (`examples/cases/`).
fn example(name: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases");
    std::fs::read_to_string(root.join(name)).unwrap()
}

/// The lines of `new` that differ from `old`'s line at the same place (an edit that changes
/// values only keeps the count of lines).
fn changed_lines<'a>(new: &'a str, old: &str) -> Vec<&'a str> {
    new.lines()
        .zip(old.lines())
        .filter(|(a, b)| a != b)
        .map(|(a, _)| a)
        .collect()
}
