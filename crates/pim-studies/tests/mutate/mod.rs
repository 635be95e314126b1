//! Mutations of input text shared by the fuzz tests of the parsers (pim-studies) and of the
//! command (pim-cli, which includes this file by path): hostile numbers and where a text's
//! numbers stand.
#![allow(dead_code)] // each test file uses its own subset

use proptest::prelude::*;

/// A value that careless or hostile input puts where a number belongs.
pub fn hostile_number() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("1e308".to_string()),
        Just("-1e308".to_string()),
        Just("5e-324".to_string()),
        Just("0.0".to_string()),
        Just("-0.0".to_string()),
        Just("1e-300".to_string()),
        Just("99999999999999999999".to_string()),
        Just("\"12\"".to_string()),
        Just("[1.0, 2.0]".to_string()),
        Just("[1.0, 2.0, 3.0]".to_string()),
        Just("{ a = 1 }".to_string()),
        Just("{ uniform = [-1e308, 1e308] }".to_string()),
        Just("".to_string()),
        (-1e4..1e4f64).prop_map(|v| format!("{v:?}")),
        (-100.0..100.0f64).prop_map(|v| format!("{v:?}")),
        any::<i64>().prop_map(|v| v.to_string()),
    ]
}

/// Byte ranges of the numbers of a text.
pub fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if (b[i].is_ascii_digit() || b[i] == b'-') && (i == 0 || !b[i - 1].is_ascii_alphanumeric())
        {
            let start = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit() || b[i] == b'.' || b[i] == b'e' || b[i] == b'-')
            {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// The text with its `k`-th number (modulo their count) replaced by `new`.
pub fn replace_number(text: &str, k: usize, new: &str) -> String {
    let n = numbers(text);
    if n.is_empty() {
        return text.to_string();
    }
    let (a, b) = n[k % n.len()];
    format!("{}{}{}", &text[..a], new, &text[b..])
}
