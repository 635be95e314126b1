//! How the toolkit's named choices are read from text.

/// The value of `all` whose `name` is `s` (ASCII case ignored), or an error naming the accepted
/// names: how every named choice of the toolkit (moment form, cost function, branch, model) is
/// read, by every front end.
pub fn parse_name<T: Copy>(
    s: &str,
    all: &[T],
    name: fn(T) -> &'static str,
) -> std::result::Result<T, String> {
    let s = s.trim();
    all.iter()
        .copied()
        .find(|&v| name(v).eq_ignore_ascii_case(s))
        .ok_or_else(|| {
            let names: Vec<String> = all.iter().map(|&v| format!("{:?}", name(v))).collect();
            format!("{s:?} is not one of {}", names.join(", "))
        })
}
