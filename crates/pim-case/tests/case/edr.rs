//! An EDR's pre-crash table pasted as text: read with or without a header, converted to the
//! case's speed unit, refused at its line; one record of evidence made from it; written into
//! the case one row to a line.
use pim_case::case::Case;
use pim_case::edr::{evidence_of, parse_table, with_history};
use pim_case::units::SpeedUnit;

/// As a crash data report's table is copied from it: tab-separated, a header, newest last.
const REPORT: &str =
    "Time (sec)\tSpeed, Vehicle Indicated (km/h)\tAccelerator Pedal, % Full\tService Brake
-2.5\t48\t22\tOff
-2.0\t48\t0\tOff
-1.5\t47\t0\tOn
-1.0\t42\t0\tOn
-0.5\t37\t0\tOn
";

#[test]
fn a_reports_table_is_read_by_its_header_and_converted() {
    let rows = parse_table(
        "paste",
        REPORT,
        SpeedUnit::KilometresPerHour,
        SpeedUnit::MilesPerHour,
    )
    .unwrap();
    assert_eq!(rows.len(), 5);
    assert!((rows[0].time - 2.5).abs() < 1e-12);
    assert!((rows[0].speed - 48.0 / 1.609_344).abs() < 1e-9);
    assert_eq!(
        (rows[0].brake, rows[0].accelerator),
        (Some(false), Some(22.0))
    );
    assert_eq!((rows[4].time, rows[4].brake), (0.5, Some(true)));
    // The same table without a header, in the order time, speed, brake, accelerator,
    // comma-separated, newest first: the same rows, oldest first.
    let bare =
        "-0.5, 37, on, 0\n-1.0, 42, on, 0\n-1.5, 47, on, 0\n-2.0, 48, off, 0\n-2.5, 48, off, 22\n";
    let again = parse_table(
        "paste",
        bare,
        SpeedUnit::KilometresPerHour,
        SpeedUnit::MilesPerHour,
    )
    .unwrap();
    assert_eq!(again, rows);
    // Spaces between, a unit in brackets after each name: the header still names them.
    let spaced = "Time (sec) Speed (km/h) Brake\n-1.0 45 On\n-0.5 40 On\n";
    let spaced = parse_table(
        "paste",
        spaced,
        SpeedUnit::KilometresPerHour,
        SpeedUnit::KilometresPerHour,
    )
    .unwrap();
    assert_eq!(spaced.len(), 2);
    assert!((spaced[1].speed - 40.0).abs() < 1e-12);
    assert_eq!(spaced[1].brake, Some(true));
}

#[test]
fn a_bad_row_is_refused_at_its_line() {
    let err = |text: &str| {
        parse_table(
            "paste",
            text,
            SpeedUnit::MilesPerHour,
            SpeedUnit::MilesPerHour,
        )
        .unwrap_err()
        .to_string()
    };
    assert_eq!(
        err("-1.0 30 off\n-0.5 thirty off\n"),
        "paste:2: speed: expected a number, got \"thirty\""
    );
    assert_eq!(
        err("-1.0 30 maybe\n"),
        "paste:1: brake: expected on or off, got \"maybe\""
    );
    assert_eq!(
        err("-1.0 30 off 140\n"),
        "paste:1: accelerator: 140: a percentage, 0 to 100"
    );
    assert_eq!(
        err("-1.0 30\n1.0 29\n"),
        "paste:2: time: 1 s is given twice (first on line 1)"
    );
    assert_eq!(
        err("-1.0\n"),
        "paste:1: speed: every row needs its time and speed"
    );
    assert!(err("\n\n").contains("no rows"));
}

#[test]
fn the_table_is_one_record_the_last_row_carried_to_contact() {
    let kmh = SpeedUnit::KilometresPerHour.to_si();
    let rows = parse_table(
        "paste",
        REPORT,
        SpeedUnit::KilometresPerHour,
        SpeedUnit::KilometresPerHour,
    )
    .unwrap();
    let e = evidence_of(&rows, 2.0, kmh).unwrap();
    // The last row, 0.5 s before contact, braking at the rate of the braked rows: 47 to 37
    // km/h in 1.0 s, 2.778 m/s^2, 0.283 g.
    assert_eq!((e.speed, e.time, e.sigma), (37.0, 0.5, 2.0));
    assert!((e.deceleration - 0.283).abs() < 1e-12, "{}", e.deceleration);
    // Released at the last row: no deceleration is assumed.
    let mut coasting = rows.clone();
    coasting[4].brake = Some(false);
    assert!(evidence_of(&coasting, 2.0, kmh).unwrap().deceleration.abs() < 1e-12);
}

#[test]
fn the_rows_are_written_one_to_a_line_and_the_case_reads_them() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("examples/cases/reconstruction_us.toml")).unwrap();
    let rows = parse_table(
        "paste",
        REPORT,
        SpeedUnit::KilometresPerHour,
        SpeedUnit::MilesPerHour,
    )
    .unwrap();
    let e = evidence_of(&rows, 1.5, SpeedUnit::MilesPerHour.to_si());
    let out = with_history("r.toml", &text, 2, &rows, e).unwrap();
    assert!(
        out.contains(
            "edr = [\n  { speed = 22.991, time = 0.5, deceleration = 0.283, sigma = 1.5 },\n]"
        ),
        "{out}"
    );
    assert!(
        out.contains(
            "edr_history = [\n  { time = 2.5, speed = 29.826, brake = false, accelerator = 22.0 },\n  { time = 2.0, speed = 29.826, brake = false, accelerator = 0.0 },\n"
        ),
        "{out}"
    );
    let case = Case::from_text("r.toml", &out).unwrap();
    let p = case.content.pre_impact.unwrap().vehicle2.unwrap();
    assert_eq!(p.edr_history.len(), 5);
    assert_eq!(p.edr.len(), 1);
    // Without evidence, only the history changes; pasted again, it is replaced.
    let history_only = with_history("r.toml", &text, 2, &rows, None).unwrap();
    assert!(history_only.contains("edr = [ { speed = 27.5"));
    assert_eq!(
        with_history("r.toml", &history_only, 2, &rows, None).unwrap(),
        history_only
    );
}
