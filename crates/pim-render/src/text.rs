//! Text that every table and drawing shares: a case's title, and lines wrapped for a key.

/// Splits text into lines of at most `width` characters at spaces.
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut out = Vec::new();
    for para in text.lines() {
        let mut cur = String::new();
        for word in para.split_whitespace() {
            if !cur.is_empty() && cur.len() + 1 + word.len() > width {
                out.push(std::mem::take(&mut cur));
            }
            if !cur.is_empty() {
                cur.push(' ');
            }
            cur.push_str(word);
        }
        if !cur.is_empty() {
            out.push(cur);
        }
    }
    out
}

/// The title of a case's tables and drawings: the file, its title and the vehicles'
/// descriptions.
pub fn case_title(case: &pim_case::case::Case) -> String {
    let mut t = match case.title() {
        Some(t) => format!("{} ({t})", case.file),
        None => case.file.clone(),
    };
    if let Some((a, b)) = case.descriptions() {
        t.push_str(&format!("\nvehicle1: {a}; vehicle2: {b}"));
    }
    t
}
