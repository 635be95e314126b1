//! `pim predict-dv`: Brach 1984's delta-V prediction for every test of a data file.

use super::print_out;
use crate::args::{Format, PredictArgs};
use crate::error::{Failure, EXIT_OK};
use crate::inputs::load_ricsac;
use anyhow::Result;
use pim_case::units::UnitSystem;
use pim_studies::predict::TestPrediction;
use std::fmt::Write as _;
use std::process::ExitCode;

fn table(file: &str, e: f64, rows: &[TestPrediction], u: UnitSystem) -> String {
    let v = |x: f64| u.speed(x);
    let mut t = format!(
        "{file}: delta-V predicted from the impact speeds, masses and energy loss (Brach 1984 \
         eq. 14, 16, 17; e = {e} in eq. 17)\n\n"
    );
    let _ = writeln!(
        t,
        "test      L  loss  mu_m(pm) | dV1 meas  eq14  eq14(2/3)  eq17 | dV2 meas  eq14  eq14(2/3)  eq17"
    );
    for r in rows {
        let (a, b) = (&r.delta_v1, &r.delta_v2);
        let _ = writeln!(
            t,
            "{:>4} {:>6.4} {:>5.3} {:>9.3} | {:>8.2} {:>5.2} {:>10.2} {:>5.2} | {:>8.2} {:>5.2} {:>10.2} {:>5.2}",
            r.test,
            r.l,
            r.energy_loss_fraction,
            r.mu_m_point_mass,
            v(a.measured),
            v(a.eq14),
            v(a.eq14_two_thirds),
            v(a.eq17),
            v(b.measured),
            v(b.eq14),
            v(b.eq14_two_thirds),
            v(b.eq17)
        );
    }
    let _ = writeln!(
        t,
        "(delta-V in {}; loss: fraction of the kinetic energy, rotation included, lost between \
         the measured contact and separation velocities)",
        u.speed_label()
    );
    t
}

/// `pim predict-dv`.
pub fn run(a: &PredictArgs) -> Result<ExitCode> {
    if !(a.e.is_finite() && (0.0..=1.0).contains(&a.e)) {
        return Err(Failure::Input(format!("--e {}: must be in [0, 1]", a.e)).into());
    }
    let file = a.data.display().to_string();
    let tests = load_ricsac(&a.data)?;
    let rows = pim_studies::predict::predict_all(&file, &tests, a.e)?;
    let record = super::json_sorted(&pim_documents::schema::PredictionsOut {
        tests: rows.clone(),
    })?;
    let units = a.units.map_or(UnitSystem::Si, Into::into);
    let text = table(&file, a.e, &rows, units);
    if let Some(dir) = &a.out {
        let out = super::output::OutDir::create(dir)?;
        out.write("predict_dv.json", &record)?;
        out.write("predict_dv.txt", &text)?;
        let figure = pim_render::predict_figure::figure(&rows)
            .map_err(|e| Failure::Output(format!("{}: figure: {e}", dir.display())))?;
        super::write_figures(&out, &[figure])?;
        out.commit()?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &text,
    })?;
    Ok(ExitCode::from(EXIT_OK))
}
