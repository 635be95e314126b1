//! The text `pim solve` prints of a solved case: the velocities and results table in the case's
//! units and frame, the model's line, the damage's lines.

use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_studies::documents::Solved;

/// What `pim solve` prints of `solved` (titled `title`), in `units` and the case's `frame` (an
/// SAE case was solved mirrored into the natural form: it is shown in its own frame).
pub fn solved_table(title: &str, solved: &Solved, units: UnitSystem, frame: Convention) -> String {
    let Solved {
        impact,
        report,
        forward,
        document,
    } = solved;
    let shown = &frame.shown(report);
    let mut table = crate::tables::solve_table(
        title,
        impact,
        shown,
        document.model.as_ref(),
        *forward,
        units,
        frame,
    );
    if let Some(m) = &document.model {
        let line = crate::tables::model_line(m);
        if let Some(at) = table.find("solved forwards") {
            table.insert_str(at, &line);
        }
    }
    if let Some(d) = &document.damage {
        table.push('\n');
        table.push_str(&crate::damage::damage_lines(d, units));
    }
    table
}
