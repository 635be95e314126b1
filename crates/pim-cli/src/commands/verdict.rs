//! What a command's exit status says of its answer, shared by the commands: a reconstruction
//! refused or fitting poorly, an answer ending on a bound, and what `--strict` counts.

use anyhow::Result;
use pim_case::case::Case;

/// The exit status of a reconstruction, after its output: 3 when refused (pointing to the
/// consistency table when there is one), else the `--strict` status, which also counts an
/// impact on a bound and a poor fit (p below 0.05).
pub fn reconstruction_status(
    case: &Case,
    d: &pim_studies::reconstruct::ReconstructionOut,
    strict: bool,
    warnings: usize,
) -> Result<std::process::ExitCode> {
    let table = if d.consistency.as_ref().is_some_and(|c| !c.rows.is_empty()) {
        " (the evidence consistency table above shows which pieces disagree)"
    } else {
        ""
    };
    if d.status != pim_reconstruct::Status::Found {
        eprintln!(
            "pim: {}: no reconstruction: {}{table}",
            case.file,
            d.reason.as_deref().unwrap_or("none found")
        );
        return Ok(std::process::ExitCode::from(crate::error::EXIT_NO_ANSWER));
    }
    let mut why = Vec::new();
    if let Some(b) = &d.best {
        for r in &b.bounds_reached {
            let default = r.source == pim_documents::records::BoundSource::Default;
            eprintln!(
                "pim: warning: {}: the reconstruction's impact ({} branch) ends on a bound: {} at \
                 [bounds] {} ({}); the bound, not the evidence, ends it there",
                case.file,
                b.branch.name(),
                r.at,
                r.bound,
                if default {
                    "a default: set it in [bounds] to choose it"
                } else {
                    "set in [bounds]"
                }
            );
        }
        if b.bounds_reached
            .iter()
            .any(|r| r.source == pim_documents::records::BoundSource::Default)
        {
            why.push("the reconstruction rests on a default bound".into());
        }
        if let Some(p) = b.p_value.filter(|p| *p < pim_reconstruct::POOR_FIT_P) {
            eprintln!(
                "pim: warning: {}: the reconstruction fits poorly (p = {}){table}",
                case.file,
                pim_render::statistics::format_p(p)
            );
            why.push("a poor fit".into());
        }
    }
    Ok(crate::inputs::strict_status(strict, warnings, why))
}

/// Warns of each bound a fitted impact ends on (the bound, not the data, ends it), with what to
/// do; returns how many.
pub fn bound_warnings(file: &str, which: &str, active: &[pim_fit::ActiveConstraint]) -> usize {
    use pim_fit::ActiveConstraint as A;
    let mut n = 0;
    for a in active {
        let hint = match a {
            A::EHigh => "the data want more restitution: widen [bounds] e",
            A::MuLow | A::MuHigh => "widen [bounds] mu",
            A::FrictionLow | A::FrictionHigh => "widen [bounds] friction",
            A::EtLow | A::EtHigh => "widen [bounds] et if it is narrower than [-1, 1]",
            A::VelocityBound(_) => "widen [bounds] velocity / yaw_rate, or check the estimates",
            A::EmLow => "em = -1 is the end of its physical range",
            _ => continue,
        };
        n += 1;
        eprintln!("pim: warning: {file}: {which} ends on a bound: {a}; {hint}");
    }
    n
}
