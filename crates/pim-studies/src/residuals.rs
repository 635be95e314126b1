//! Each estimate and observation of a fit against its fitted value: the table a reader judges
//! a fit by.
//!
//! For every term of the cost, `residual = fitted - given`; with standard deviations (`[sigma]`
//! or an observation's `sigma`) the normalised residual `residual / sigma` is a number of
//! standard deviations, and the squares of the normalised residuals add up to the chi-square.
//! `share` is the term's part of the cost, `weight residual^2 / cost`. All values SI (m/s,
//! rad/s) in the natural frame, like the rest of the JSON.

use pim_case::case::Case;
pub use pim_documents::residuals::Residual;
use pim_fit::{FitProblem, Knowledge, COMPONENT_NAMES};

/// The residual table of a fitted solution of `problem` (the problem built from `case`, whose
/// observations it names); `unit` is the weight of one standard deviation when the case gives
/// sigmas (see [`crate::fitcase::sigma_unit`]).
pub fn residuals(
    case: &Case,
    problem: &FitProblem,
    solution: &pim_fit::Solution,
    unit: Option<f64>,
) -> Vec<Residual> {
    let u = pim_fit::state_vector(&solution.initial, &solution.separation);
    let mut out = Vec::new();
    let mut push =
        |name: String, kind: String, yaw: bool, lateral, given: f64, fitted: f64, w: f64| {
            let sigma = unit.map(|unit| (unit / w).sqrt());
            let r = fitted - given;
            out.push(Residual {
                name,
                kind,
                unit: if yaw { "rad/s" } else { "m/s" },
                given,
                fitted,
                residual: r,
                weight: w,
                sigma,
                normalised: sigma.map(|s| r / s),
                share: (solution.cost > 0.0).then(|| w * r * r / solution.cost),
                lateral,
            });
        };
    for (k, know) in problem.components.iter().enumerate() {
        if let Knowledge::Estimated { value, weight } = *know {
            push(
                COMPONENT_NAMES[k].to_string(),
                "estimate".into(),
                pim_fit::Component(k).is_yaw_rate(),
                k % 3 != 0,
                value,
                u[k],
                weight,
            );
        }
    }
    for (i, o) in problem.observations.iter().enumerate() {
        let fitted = o.row(&problem.impact).dot(&u);
        push(
            case.observation_label(i),
            o.kind.name().into(),
            false,
            o.kind.is_lateral(),
            o.value,
            fitted,
            o.weight,
        );
    }
    out
}
