//! The structure of the workspace's source: no import cycle between the files of a crate, no
//! source file longer than [`MAX_LINES`] outside its tests, and no function longer than
//! [`MAX_FN_LINES`] (those longer when the limit was set may only shrink: [`LONG_FUNCTIONS`]),
//! evidence never told apart by its name, the frame never tested and the raw sections never
//! read above pim-case, and one damped least-squares iteration ([`DAMPED_HOME`]).
//!
//! A file imports another when it names an item that the other defines: through `use` (the
//! `crate::`, `self::`, `super::` and child-module paths of Rust 2018) or an inline
//! `crate::`/`super::` path. Re-exports are followed to the file that defines the item, so
//! `crate::Name` re-exported by `lib.rs` is an arrow to the defining file, not to `lib.rs`; a
//! module's declaration (`mod x;`) is not an import. Run alone with
//! `cargo test --release --test structure -- --nocapture` to see every crate's arrows counted.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The longest source file allowed, in lines before its `#[cfg(test)]` module.
const MAX_LINES: usize = 650;

/// The library and binary crates whose files are checked (their `src` folders).
const CRATES: [&str; 12] = [
    "crates/pim-core",
    "crates/pim-runout",
    "crates/pim-reconstruct",
    "crates/pim-crush",
    "crates/pim-fit",
    "crates/pim-case",
    "crates/pim-documents",
    "crates/pim-studies",
    "crates/pim-serve",
    "crates/pim-render",
    "crates/pim-cli",
    "crates/pim-py",
];

/// One source file: its module path, what it defines and re-exports, and its imports.
#[derive(Debug, Default)]
struct File {
    /// Module path from the crate root, e.g. `["inner", "constraints"]`.
    module: Vec<String>,
    /// Names of items defined here (functions, types, traits, constants, statics, macros).
    defines: BTreeSet<String>,
    /// Child modules declared here (`mod x;` or `mod x { ... }`).
    children: BTreeSet<String>,
    /// `name -> absolute path` of what `use` brings into scope (re-exports included).
    uses: BTreeMap<String, Vec<String>>,
    /// Whether a `use` of a name is public (a re-export that others may name through).
    reexports: BTreeSet<String>,
    /// Every absolute path named (by `use` or inline).
    paths: Vec<Vec<String>>,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

/// The text before a file's inline test module (`#[cfg(test)] mod name {`); a test module
/// kept in a file of its own (`#[cfg(test)] mod tests;`) ends nothing.
fn before_tests(text: &str) -> &str {
    let mut from = 0;
    while let Some(i) = text[from..].find("#[cfg(test)]") {
        let at = from + i;
        let after = text[at + "#[cfg(test)]".len()..].trim_start();
        let after = ["pub(crate) ", "pub(super) ", "pub "]
            .iter()
            .find_map(|v| after.strip_prefix(v))
            .unwrap_or(after);
        let inline = after
            .strip_prefix("mod ")
            .and_then(|r| r.find(['{', ';']).map(|j| r.as_bytes()[j] == b'{'))
            .unwrap_or(false);
        if inline {
            return &text[..at];
        }
        from = at + 1;
    }
    text
}

/// The source text without comments, string literals and inline test modules.
fn code_of(text: &str) -> String {
    let text = before_tests(text);
    let mut out = String::with_capacity(text.len());
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                newline(b[i], &mut out);
                i += 1;
            }
            i += 2;
        } else if b[i] == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    i += 1;
                }
                if i < b.len() {
                    newline(b[i], &mut out);
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if b[i] == b'\'' && b.get(i + 2) == Some(&b'\'') {
            // A char literal such as '{' (lifetimes have no closing quote two bytes on).
            i += 3;
        } else if b[i] == b'\'' && b.get(i + 1) == Some(&b'\\') {
            i += 2;
            while i < b.len() && b[i] != b'\'' {
                i += 1;
            }
            i += 1;
        } else {
            out.push(b[i] as char);
            i += 1;
        }
    }
    out
}

/// Keeps a skipped comment's or string's line breaks, so that the code's lines are the
/// source's.
fn newline(c: u8, out: &mut String) {
    if c == b'\n' {
        out.push('\n');
    }
}

fn ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The leaves of a `use` tree: `(full path, the name it binds)`.
fn use_tree(prefix: &[String], tree: &str, out: &mut Vec<(Vec<String>, String)>) {
    let tree = tree.trim();
    if tree.is_empty() {
        return;
    }
    if let Some(open) = tree.find('{') {
        let head: Vec<String> = tree[..open]
            .split("::")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
        let mut p = prefix.to_vec();
        p.extend(head);
        let mut depth = 0;
        let mut start = 0;
        for (i, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    use_tree(&p, &inner[start..i], out);
                    start = i + 1;
                }
                _ => {}
            }
        }
        use_tree(&p, &inner[start..], out);
        return;
    }
    let (path, alias) = match tree.split_once(" as ") {
        Some((a, b)) => (a, Some(b.trim().to_string())),
        None => (tree, None),
    };
    let mut p = prefix.to_vec();
    p.extend(
        path.split("::")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from),
    );
    if p.last().is_some_and(|l| l == "self") {
        p.pop();
    }
    let name = alias.unwrap_or_else(|| p.last().cloned().unwrap_or_default());
    out.push((p, name));
}

/// Makes a path absolute from the module `here`, or `None` for another crate's path.
fn absolute(here: &[String], children: &BTreeSet<String>, p: &[String]) -> Option<Vec<String>> {
    let first = p.first()?;
    let mut base: Vec<String> = match first.as_str() {
        "crate" => return Some(p[1..].to_vec()),
        "self" => here.to_vec(),
        "super" => {
            let mut b = here.to_vec();
            let mut k = 0;
            while p.get(k).is_some_and(|s| s == "super") {
                b.pop();
                k += 1;
            }
            b.extend(p[k..].iter().cloned());
            return Some(b);
        }
        _ if children.contains(first) => {
            let mut b = here.to_vec();
            b.extend(p.iter().cloned());
            return Some(b);
        }
        _ => return None,
    };
    base.extend(p[1..].iter().cloned());
    Some(base)
}

fn parse(module: Vec<String>, text: &str) -> File {
    let code = code_of(text);
    let mut f = File {
        module,
        ..File::default()
    };
    // Definitions and child modules.
    let words: Vec<&str> = code
        .split(|c: char| !ident(c) && c != '!')
        .filter(|w| !w.is_empty())
        .collect();
    for w in words.windows(2) {
        match w[0] {
            "fn" | "struct" | "enum" | "trait" | "type" | "const" | "static" | "union" => {
                f.defines.insert(w[1].to_string());
            }
            "mod" => {
                f.children.insert(w[1].to_string());
            }
            "macro_rules!" => {
                f.defines.insert(w[1].to_string());
            }
            _ => {}
        }
    }
    // `use` declarations (public ones are re-exports).
    let mut rest = code.as_str();
    while let Some(i) = rest.find("use ") {
        let before = &rest[..i];
        let boundary = before.chars().last().is_none_or(|c| !ident(c) && c != ':');
        let Some(end) = rest[i..].find(';') else {
            break;
        };
        if boundary {
            let public = before.trim_end().ends_with("pub") || before.trim_end().ends_with(')');
            let mut leaves = Vec::new();
            use_tree(&[], &rest[i + 4..i + end], &mut leaves);
            for (p, name) in leaves {
                if let Some(abs) = absolute(&f.module, &f.children, &p) {
                    if public {
                        f.reexports.insert(name.clone());
                    }
                    f.uses.insert(name, abs.clone());
                    f.paths.push(abs);
                }
            }
        }
        rest = &rest[i + end..];
    }
    // Inline paths: `crate::a::b`, `super::x`, and names brought in by `use` followed by `::`.
    let chars: Vec<char> = code.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        if ident(chars[i]) && (i == 0 || !(ident(chars[i - 1]) || chars[i - 1] == ':')) {
            let mut j = i;
            let mut segs = Vec::new();
            loop {
                let s = j;
                while j < chars.len() && ident(chars[j]) {
                    j += 1;
                }
                segs.push(chars[s..j].iter().collect::<String>());
                if j + 2 < chars.len()
                    && chars[j] == ':'
                    && chars[j + 1] == ':'
                    && ident(chars[j + 2])
                {
                    j += 2;
                } else {
                    break;
                }
            }
            if segs.len() > 1 && matches!(segs[0].as_str(), "crate" | "super" | "self") {
                if let Some(abs) = absolute(&f.module, &f.children, &segs) {
                    f.paths.push(abs);
                }
            } else if segs.len() > 1 && f.children.contains(&segs[0]) {
                let mut abs = f.module.clone();
                abs.extend(segs.iter().cloned());
                f.paths.push(abs);
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    f
}

/// The source files of a crate, by module path.
fn crate_files(dir: &Path) -> BTreeMap<Vec<String>, (PathBuf, File)> {
    let src = dir.join("src");
    let mut paths = Vec::new();
    rust_files(&src, &mut paths);
    let mut files = BTreeMap::new();
    for p in paths {
        let rel = p.strip_prefix(&src).unwrap();
        let mut module: Vec<String> = rel
            .with_extension("")
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        if matches!(
            module.last().map(String::as_str),
            Some("mod" | "lib" | "main")
        ) {
            module.pop();
        }
        // A test module kept in its own file is part of the tests.
        if module.last().is_some_and(|m| m == "tests") {
            continue;
        }
        let text = std::fs::read_to_string(&p).unwrap();
        files.insert(module.clone(), (p, parse(module, &text)));
    }
    files
}

/// The file that defines what `path` names, following re-exports (at most 8 hops).
fn resolve(
    files: &BTreeMap<Vec<String>, (PathBuf, File)>,
    path: &[String],
    hops: usize,
) -> Option<Vec<String>> {
    if hops > 8 {
        return None;
    }
    // The longest prefix of the path that is a module file.
    let mut k = path.len();
    while k > 0 && !files.contains_key(&path[..k]) {
        k -= 1;
    }
    let module = path[..k].to_vec();
    let (_, f) = files.get(&module)?;
    let Some(name) = path.get(k) else {
        return Some(module);
    };
    if f.defines.contains(name) {
        return Some(module);
    }
    if let Some(target) = f.uses.get(name) {
        if f.reexports.contains(name) || hops == 0 {
            let mut t = target.clone();
            t.extend(path[k + 1..].iter().cloned());
            return resolve(files, &t, hops + 1);
        }
    }
    Some(module)
}

/// Strongly connected components with more than one file (Tarjan).
fn cycles(edges: &BTreeMap<usize, BTreeSet<usize>>, n: usize) -> Vec<Vec<usize>> {
    struct T<'a> {
        edges: &'a BTreeMap<usize, BTreeSet<usize>>,
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(t: &mut T, v: usize) {
        t.index[v] = Some(t.next);
        t.low[v] = t.next;
        t.next += 1;
        t.stack.push(v);
        t.on[v] = true;
        let succ: Vec<usize> = t.edges.get(&v).into_iter().flatten().copied().collect();
        for w in succ {
            match t.index[w] {
                None => {
                    visit(t, w);
                    t.low[v] = t.low[v].min(t.low[w]);
                }
                Some(iw) if t.on[w] => t.low[v] = t.low[v].min(iw),
                _ => {}
            }
        }
        if Some(t.low[v]) == t.index[v] {
            let mut c = Vec::new();
            while let Some(w) = t.stack.pop() {
                t.on[w] = false;
                c.push(w);
                if w == v {
                    break;
                }
            }
            if c.len() > 1 {
                t.out.push(c);
            }
        }
    }
    let mut t = T {
        edges,
        index: vec![None; n],
        low: vec![0; n],
        on: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            visit(&mut t, v);
        }
    }
    t.out
}

#[test]
fn no_import_cycle_between_the_files_of_a_crate() {
    let mut problems = Vec::new();
    for krate in CRATES {
        let dir = root().join(krate);
        if !dir.exists() {
            continue;
        }
        let files = crate_files(&dir);
        let keys: Vec<Vec<String>> = files.keys().cloned().collect();
        let index: BTreeMap<&Vec<String>, usize> =
            keys.iter().enumerate().map(|(i, k)| (k, i)).collect();
        let mut edges: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
        let mut names: BTreeMap<(usize, usize), BTreeSet<String>> = BTreeMap::new();
        for (k, (_, f)) in &files {
            let from = index[k];
            for p in &f.paths {
                let Some(target) = resolve(&files, p, 0) else {
                    continue;
                };
                let Some(&to) = index.get(&target) else {
                    continue;
                };
                if to != from {
                    edges.entry(from).or_default().insert(to);
                    names
                        .entry((from, to))
                        .or_default()
                        .insert(p.last().cloned().unwrap_or_default());
                }
            }
        }
        let arrows: usize = edges.values().map(BTreeSet::len).sum();
        println!("{krate}: {} files, {arrows} arrows", files.len());
        for c in cycles(&edges, keys.len()) {
            let set: BTreeSet<usize> = c.iter().copied().collect();
            let mut text = format!("{krate}: import cycle between {} files:", c.len());
            for &a in &c {
                for &b in edges.get(&a).into_iter().flatten() {
                    if set.contains(&b) {
                        let file = |i: usize| {
                            files[&keys[i]]
                                .0
                                .strip_prefix(root())
                                .unwrap()
                                .display()
                                .to_string()
                        };
                        text.push_str(&format!(
                            "\n  {} -> {}: {:?}",
                            file(a),
                            file(b),
                            names[&(a, b)]
                        ));
                    }
                }
            }
            problems.push(text);
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn no_source_file_is_longer_than_the_limit() {
    let mut long = Vec::new();
    for krate in CRATES {
        let dir = root().join(krate);
        for (_, (path, _)) in crate_files(&dir) {
            let text = std::fs::read_to_string(&path).unwrap();
            let n = before_tests(&text).lines().count();
            if n > MAX_LINES {
                long.push(format!(
                    "{}: {n} lines (limit {MAX_LINES})",
                    path.strip_prefix(root()).unwrap().display()
                ));
            }
        }
    }
    assert!(long.is_empty(), "{}", long.join("\n"));
}

/// Evidence is told apart by its typed identity (`pim_runout::Quantity`, the evidence table's
/// `EvidenceSource`, the consistency table's `PieceId`), never by its display name: no
/// library code outside tests compares a `.name` field with a string.
#[test]
fn no_evidence_is_matched_by_its_name() {
    const PATTERNS: [&str; 4] = [
        ".name.contains(",
        ".name.starts_with(",
        ".name.ends_with(",
        ".name == ",
    ];
    let mut found = Vec::new();
    for krate in CRATES {
        let dir = root().join(krate);
        for (_, (path, _)) in crate_files(&dir) {
            let text = std::fs::read_to_string(&path).unwrap();
            let code = code_of(before_tests(&text));
            for (n, line) in code.lines().enumerate() {
                if let Some(p) = PATTERNS.iter().find(|p| line.contains(*p)) {
                    found.push(format!(
                        "{}:{}: `{p}`: tell evidence apart by its typed identity",
                        path.strip_prefix(root()).unwrap().display(),
                        n + 1
                    ));
                }
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// The frame a case is written in is decided in one place: above pim-case no library code
/// tests it (`== Convention::Sae`, a match on it); each conversion between the natural frame,
/// the written one and the page is a method of `pim_core::Convention` (`sign`, `shown`,
/// `to_page`, `from_page`, `angle_from_page`, ...).
#[test]
fn no_frame_is_tested_above_the_case() {
    let tests = |line: &str| {
        ["Sae", "Natural", "Brach"].iter().any(|c| {
            line.contains(&format!("== Convention::{c}"))
                || line.contains(&format!("!= Convention::{c}"))
                || line.contains(&format!("Convention::{c} =>"))
                || line.contains(&format!("== pim_core::Convention::{c}"))
                || line.contains(&format!("pim_core::Convention::{c} =>"))
        })
    };
    let mut found = Vec::new();
    for krate in ABOVE_THE_CASE {
        for (_, (path, _)) in crate_files(&root().join(krate)) {
            let text = std::fs::read_to_string(&path).unwrap();
            let code = code_of(before_tests(&text));
            for (n, line) in code.lines().enumerate().filter(|(_, l)| tests(l)) {
                found.push(format!(
                    "{}:{}: `{}`: convert with a method of pim_core::Convention",
                    path.strip_prefix(root()).unwrap().display(),
                    n + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// The crates above pim-case: they take the case resolved, not its raw sections.
const ABOVE_THE_CASE: [&str; 7] = [
    "crates/pim-reconstruct",
    "crates/pim-documents",
    "crates/pim-studies",
    "crates/pim-render",
    "crates/pim-cli",
    "crates/pim-serve",
    "crates/pim-py",
];

/// The crates above pim-case take the case resolved, never its raw sections
/// (`case.content`): a value read there belongs in pim-case, read once with its default and
/// its range (an accessor of `Case`, a resolved section such as `pre_impact_vehicles`, the
/// inputs a study draws in `pim_case::drawn`, the evidence's pieces in `pim_case::pieces`).
#[test]
fn no_raw_section_is_read_above_the_case() {
    let mut found = Vec::new();
    for krate in ABOVE_THE_CASE {
        for (_, (path, _)) in crate_files(&root().join(krate)) {
            let text = std::fs::read_to_string(&path).unwrap();
            let code = code_of(before_tests(&text));
            for (n, line) in code.lines().enumerate() {
                let reads = line.match_indices(".content").any(|(i, _)| {
                    !line[i + ".content".len()..]
                        .starts_with(|c: char| c.is_alphanumeric() || c == '_')
                });
                if reads {
                    found.push(format!(
                        "{}:{}: `{}`: read the case resolved (pim-case), not its raw sections",
                        path.strip_prefix(root()).unwrap().display(),
                        n + 1,
                        line.trim()
                    ));
                }
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// The one damped least-squares iteration: `pim_core::damped` moves Marquardt's damping; no
/// other library code updates a damping from itself (`lambda *= 4.0`, `lambda = if lambda ==
/// 0.0 { .. } else { lambda * 10.0 }`, `*lambda /= 3.0`): a second Levenberg-Marquardt loop
/// implements `pim_core::damped::Damped` instead.
const DAMPED_HOME: &str = "crates/pim-core/src/damped.rs";

/// The lines of `code` that update a damping (`lambda`, `damping`) from itself.
fn damping_updates(code: &str) -> Vec<usize> {
    let mut found = Vec::new();
    for (n, line) in code.lines().enumerate() {
        let t = line.trim_start().trim_start_matches('*');
        for name in ["lambda", "damping"] {
            let Some(rest) = t.strip_prefix(name) else {
                continue;
            };
            let rest = rest.trim_start();
            let update = ["*=", "/=", "+=", "-="]
                .iter()
                .any(|op| rest.starts_with(op))
                || rest.strip_prefix('=').is_some_and(|rhs| {
                    !rhs.starts_with('=')
                        && rhs.match_indices(name).any(|(i, _)| {
                            let before = rhs[..i].chars().next_back();
                            let after = rhs[i + name.len()..].chars().next();
                            !before.is_some_and(ident) && !after.is_some_and(ident)
                        })
                });
            if update {
                found.push(n + 1);
            }
        }
    }
    found
}

#[test]
fn one_damped_least_squares_loop() {
    let mut found = Vec::new();
    for krate in CRATES {
        for (_, (path, _)) in crate_files(&root().join(krate)) {
            let file = path.strip_prefix(root()).unwrap().display().to_string();
            if file == DAMPED_HOME {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for n in damping_updates(&code_of(&text)) {
                found.push(format!(
                    "{file}:{n}: a damping updated from itself: a second damped least-squares \
                     loop (implement pim_core::damped::Damped)"
                ));
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn the_damping_rule_sees_a_second_loop() {
    let code = code_of(
        "fn f() {\n    lambda *= 4.0;\n    let lambda = 1e-3;\n    *lambda = (*lambda / 3.0).max(1e-9);\n    \
         lambda = if lambda == 0.0 { 1e-3 } else { lambda * 10.0 };\n    lambdas = lambda;\n}\n",
    );
    assert_eq!(damping_updates(&code), [2, 4, 5]);
}

#[test]
fn the_name_rule_sees_a_name_compared() {
    let code = code_of("fn f(r: &R) -> bool { r.name.contains(\"heading\") }\n");
    assert!(code.contains(".name.contains("));
}

/// The longest function allowed, in lines from its `fn` to its closing brace.
const MAX_FN_LINES: usize = 120;

/// The functions already over [`MAX_FN_LINES`] when the limit was set, each with its length
/// then: a ratchet. Each may only shrink; a function over the limit that is not listed, or
/// longer than listed, fails, and so does a listed one brought within the limit (it leaves the
/// list). `PIM_LONG_FUNCTIONS=1 cargo test --release --test structure -- --nocapture` prints
/// the list as it stands.
const LONG_FUNCTIONS: &[(&str, &str, usize)] = &[];

/// Each function of `code` (comments and strings blanked, its lines the source's): its name
/// and its length in lines, from the line of its `fn` to that of its closing brace. A
/// declaration without a body (a trait's) is not a function here.
fn functions(code: &str) -> Vec<(String, usize)> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(j) = code[from..].find("fn ") {
        let at = from + j;
        from = at + 3;
        if at > 0 && ident(b[at - 1] as char) {
            continue;
        }
        let name: String = code[at + 3..].chars().take_while(|c| ident(*c)).collect();
        let Some(k) = code[at..].find(['{', ';']) else {
            break;
        };
        if name.is_empty() || b[at + k] == b';' {
            continue;
        }
        let open = at + k;
        let mut depth = 0usize;
        let mut end = code.len() - 1;
        for (m, c) in code[open..].bytes().enumerate() {
            match c {
                b'{' => depth += 1,
                b'}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + m;
                        break;
                    }
                }
                _ => {}
            }
        }
        out.push((name, code[at..=end].matches('\n').count() + 1));
    }
    out
}

#[test]
fn no_function_is_longer_than_the_limit() {
    let mut found: Vec<(String, String, usize)> = Vec::new();
    for krate in CRATES {
        let dir = root().join(krate);
        for (_, (path, _)) in crate_files(&dir) {
            let text = std::fs::read_to_string(&path).unwrap();
            let file = path.strip_prefix(root()).unwrap().display().to_string();
            for (name, n) in functions(&code_of(&text)) {
                if n > MAX_FN_LINES {
                    found.push((file.clone(), name, n));
                }
            }
        }
    }
    if std::env::var_os("PIM_LONG_FUNCTIONS").is_some() {
        for (f, name, n) in &found {
            println!("    (\"{f}\", \"{name}\", {n}),");
        }
    }
    let mut problems = Vec::new();
    for (f, name, n) in &found {
        match LONG_FUNCTIONS
            .iter()
            .find(|(lf, ln, _)| lf == f && ln == name)
        {
            None => problems.push(format!("{f}: fn {name}: {n} lines (limit {MAX_FN_LINES})")),
            Some((_, _, was)) if n > was => problems.push(format!(
                "{f}: fn {name}: {n} lines, longer than the {was} it was allowed (it may only \
                 shrink, to {MAX_FN_LINES})"
            )),
            Some(_) => {}
        }
    }
    for (f, name, _) in LONG_FUNCTIONS {
        if !found.iter().any(|(ff, nn, _)| ff == f && nn == name) {
            problems.push(format!(
                "{f}: fn {name} is within {MAX_FN_LINES} lines now (or gone): take it off \
                 LONG_FUNCTIONS"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_function_lengths_are_measured_from_fn_to_its_brace() {
    let code = code_of(
        "/// A doc.\nfn a() {\n    let s = \"}\\n{\";\n    if x { y }\n}\ntrait T { fn b(&self); }\n\
         impl U { pub(crate) fn c(\n    x: u8,\n) -> u8 {\n    x\n} }\nlet f: fn(u8) = g;\n",
    );
    assert_eq!(
        functions(&code),
        [("a".to_string(), 4), ("c".to_string(), 5)]
    );
}

#[test]
fn the_checker_sees_a_cycle_and_a_re_export() {
    // Two modules naming each other form a cycle; a name re-exported by the root resolves to
    // the file that defines it.
    let lib = parse(vec![], "mod a;\nmod b;\npub use a::Thing;\n");
    let a = parse(
        vec!["a".into()],
        "use crate::b::other;\npub struct Thing;\n",
    );
    let b = parse(
        vec!["b".into()],
        "pub fn other() {}\nfn f() { crate::Thing; }\n",
    );
    let mut files = BTreeMap::new();
    for f in [lib, a, b] {
        files.insert(f.module.clone(), (PathBuf::new(), f));
    }
    assert_eq!(
        resolve(&files, &["Thing".to_string()], 0),
        Some(vec!["a".to_string()])
    );
    let edges: BTreeMap<usize, BTreeSet<usize>> =
        [(1, BTreeSet::from([2])), (2, BTreeSet::from([1]))].into();
    assert_eq!(cycles(&edges, 3).len(), 1);
    let b_paths = &files[&vec!["b".to_string()]].1.paths;
    assert!(b_paths.contains(&vec!["Thing".to_string()]));
}

/// The Rust files under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The tests of `text` ignored as long (an `#[ignore]` whose reason starts `long`): the name of
/// the `fn` after each.
fn long_tests(text: &str) -> Vec<String> {
    text.match_indices("#[ignore = \"long")
        .filter_map(|(i, _)| {
            let rest = &text[i..];
            let f = rest.find("fn ")? + 3;
            let name: String = rest[f..].chars().take_while(|&c| ident(c)).collect();
            Some(name)
        })
        .collect()
}

/// Every test of the long tier (ignored by the README's test command as long) is run by
/// `tests/long`, so none is left out of both.
#[test]
fn every_long_test_is_run_by_the_long_tier() {
    let script = std::fs::read_to_string(root().join("tests/long")).unwrap();
    let words: BTreeSet<&str> = script
        .split(|c: char| !(ident(c) || c == ':'))
        .flat_map(|w| w.rsplit("::").next())
        .collect();
    let mut files = Vec::new();
    rust_files(&root().join("tests"), &mut files);
    for krate in CRATES {
        rust_files(&root().join(krate).join("tests"), &mut files);
    }
    let mut marked = 0;
    let mut missing = Vec::new();
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        for name in long_tests(&text) {
            marked += 1;
            if !words.contains(name.as_str()) {
                missing.push(format!("{}: {name}", path.display()));
            }
        }
    }
    assert!(marked > 0, "no long test found");
    assert!(
        missing.is_empty(),
        "long tests that tests/long does not run:\n{}",
        missing.join("\n")
    );
}
