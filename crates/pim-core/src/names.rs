//! How the toolkit's named choices are read from text.

/// A name that is none of a choice's names.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{given:?} is not one of {}", quoted(.accepted))]
pub struct UnknownName {
    /// The name given (trimmed).
    pub given: String,
    /// The names accepted, in their order.
    pub accepted: Vec<&'static str>,
}

fn quoted(names: &[&'static str]) -> String {
    let names: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    names.join(", ")
}

/// The value of `all` whose `name` is `s` (ASCII case ignored), or an error naming the accepted
/// names: how every named choice of the toolkit (moment form, cost function, branch, model) is
/// read, by every front end.
pub fn parse_name<T: Copy>(
    s: &str,
    all: &[T],
    name: fn(T) -> &'static str,
) -> std::result::Result<T, UnknownName> {
    let s = s.trim();
    all.iter()
        .copied()
        .find(|&v| name(v).eq_ignore_ascii_case(s))
        .ok_or_else(|| UnknownName {
            given: s.to_string(),
            accepted: all.iter().map(|&v| name(v)).collect(),
        })
}
