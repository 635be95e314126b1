//! The RICSAC data loader rejects malformed files with a message naming file, line and column.
use pim_case::ricsac::parse;

fn good() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/ricsac.csv"
    ))
    .unwrap()
}

fn err(text: &str) -> String {
    match parse("d.csv", text) {
        Ok(_) => panic!("accepted a bad file"),
        Err(e) => e.to_string(),
    }
}

/// Replaces cell `col` (0-based) of data line `line` (1 = first data row).
fn set_cell(text: &str, line: usize, col: usize, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut cells: Vec<String> = lines[line].split(',').map(str::to_string).collect();
    cells[col] = value.to_string();
    lines[line] = cells.join(",");
    lines.join("\n") + "\n"
}

#[test]
fn the_bundled_file_loads() {
    let t = parse("d.csv", &good()).unwrap();
    assert_eq!(t.len(), 11);
    assert_eq!(t[0].line, 2);
}

#[test]
fn bad_cells_name_line_and_column() {
    let g = good();
    for (line, col, value, needles) in [
        (
            3,
            4,
            "abc",
            vec![
                "d.csv:4:",
                "column 5 `mass1_kg`",
                "expected a number",
                "`abc`",
            ],
        ),
        (
            1,
            17,
            "NaN",
            vec!["d.csv:2:", "`vi1x_mps`", "between -100 and 100 m/s"],
        ),
        (
            1,
            18,
            "inf",
            vec!["d.csv:2:", "`vi1y_mps`", "between -100 and 100 m/s"],
        ),
        (
            2,
            4,
            "-5",
            vec!["d.csv:3:", "`mass1_kg`", "between 100 and 1000000 kg"],
        ),
        (
            2,
            7,
            "0",
            vec![
                "d.csv:3:",
                "`yaw_inertia2_kgm2`",
                "between 10 and 250000000 kg m^2",
            ],
        ),
        (
            2,
            11,
            "-0.5",
            vec!["d.csv:3:", "`d2_m`", "between 0 and 30 m"],
        ),
        (
            2,
            14,
            "forty",
            vec!["d.csv:3:", "`phi1_deg`", "expected a number"],
        ),
        (1, 0, "1.5", vec!["d.csv:2:", "`test`", "whole"]),
        (1, 9, "", vec!["d.csv:2:", "`heading2_deg`"]),
    ] {
        let msg = err(&set_cell(&g, line, col, value));
        for n in needles {
            assert!(msg.contains(n), "`{n}` not in: {msg}");
        }
    }
}

#[test]
fn structural_problems_are_reported() {
    let g = good();
    let header = g.lines().next().unwrap();
    // Duplicate test number.
    let dup = set_cell(&g, 2, 0, "1");
    let msg = err(&dup);
    assert!(
        msg.contains("test 1 appears twice (lines 2 and 3)"),
        "{msg}"
    );
    // Columns in a different order.
    let swapped = g.replacen(
        "mass1_kg,yaw_inertia1_kgm2",
        "yaw_inertia1_kgm2,mass1_kg",
        1,
    );
    let msg = err(&swapped);
    assert!(
        msg.contains("d.csv:1: column 5 is `yaw_inertia1_kgm2`, expected `mass1_kg`"),
        "{msg}"
    );
    // Missing column.
    let cut = g.replacen(",dv2_measured_mps", "", 1);
    assert!(err(&cut).contains("missing column 31 `dv2_measured_mps`"));
    // Extra column.
    let extra = g.replacen("dv2_measured_mps", "dv2_measured_mps,notes", 1);
    assert!(err(&extra).contains("extra column 32 `notes`"));
    // Short row.
    let short: String = g
        .lines()
        .take(2)
        .map(|l| format!("{l}\n"))
        .collect::<String>()
        + "5,x\n";
    assert!(err(&short).contains("d.csv:3: the row has 2 fields, the header 31"));
    // Empty file, header only.
    assert!(err("").contains("empty"));
    assert!(err(&format!("{header}\n")).contains("no data rows"));
    // Not CSV at all.
    assert!(err("\u{0}\u{1}binary junk").contains("d.csv:1:"));
}

#[test]
fn no_ricsac_test_draws_a_plausibility_warning() {
    // Each test of the bundled data as a case (as the batch's draws see it): real crashes,
    // so any warning would be a false alarm.
    let tests = pim_case::ricsac::parse("data/ricsac.csv", &good()).unwrap();
    assert!(tests.len() >= 10);
    for t in &tests {
        let case = t.case(&format!("data/ricsac.csv test {}", t.test)).unwrap();
        assert_eq!(case.warnings(), Vec::<String>::new(), "test {}", t.test);
    }
}
