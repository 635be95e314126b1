//! An EDR's table pasted in the page: imported into the text as `pim edr` imports it, and the
//! answer's plan carrying the speeds before contact beside it.

use crate::example;
use pim_case::edr::Import;
use pim_case::units::SpeedUnit;
use pim_serve::{answer, import_edr, EdrImport};

#[test]
fn a_pasted_table_is_imported_and_its_figure_answered() {
    let text = example("reconstruction_us.toml");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let table = std::fs::read_to_string(root.join("examples/scene/suv_precrash.txt")).unwrap();
    let ask = EdrImport {
        table,
        import: Import {
            vehicle: 2,
            unit: Some(SpeedUnit::KilometresPerHour),
            sigma: None,
            record: true,
        },
    };
    let out = import_edr("r.toml", &text, &ask).unwrap();
    // The same text `pim edr` writes (the guide shows it).
    assert!(out.contains(
        "edr = [\n  { speed = 27.34, time = 0.5, deceleration = 0.0, sigma = 1.01 },\n]"
    ));
    assert_eq!(out.matches("brake = false").count(), 5);
    let a = answer("r.toml", &out).unwrap();
    let svg = a.plan.speed_history.expect("the figure");
    assert!(svg.contains("vehicle 2: speed before contact"));
    assert_eq!(svg.matches("<circle").count(), 6);
    // Vehicle 1 has no EDR: one panel. A case with no EDR has no figure.
    assert!(!svg.contains("vehicle 1: speed before contact"));
    let line = "edr = [ { speed = 27.5, time = 0.5, deceleration = 0.0, sigma = 1.5 } ]   # mph, s before contact, g, mph\n";
    let none = answer("r.toml", &text.replacen(line, "", 1)).unwrap();
    assert!(none.plan.speed_history.is_none());
    // A bad table is refused at its line.
    let bad = EdrImport {
        table: "-1.0 30 off\n-0.5 30 maybe\n".into(),
        ..ask
    };
    let e = import_edr("r.toml", &text, &bad).unwrap_err().to_string();
    assert!(
        e.contains("the pasted table:2: brake: expected on or off"),
        "{e}"
    );
}
