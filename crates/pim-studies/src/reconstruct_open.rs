//! What a reconstruction leaves open: counts of turns the evidence does not decide between,
//! flat directions of the velocities, more unknowns than evidence, and the frictions the
//! scenes cannot separate from the speeds (the document's `undetermined`).

use pim_reconstruct::{Outcome, Reconstruction, Tried};

/// Each thing the evidence leaves undetermined or the search does not prove, in words.
pub(crate) fn undetermined(
    r: &Reconstruction,
    runout: &pim_runout::Settings,
    outcome: &Outcome,
) -> Vec<String> {
    let mut undetermined = Vec::new();
    if let Some(b) = &outcome.best {
        let counts = b.counts();
        let close: Vec<String> = outcome
            .within(1.0)
            .iter()
            .filter(|t| t.counts != counts)
            .map(|t| {
                format!(
                    "{:?} (chi-square {:.3})",
                    t.counts,
                    match t.state {
                        Tried::Refined { cost, .. } => cost,
                        _ => f64::NAN,
                    }
                )
            })
            .collect();
        if !close.is_empty() {
            undetermined.push(format!(
                "the counts of turns: other combinations fit within a chi-square of 1 of the \
                 best: {}",
                close.join(", ")
            ));
        }
        if !b.solution.undetermined.is_empty() {
            undetermined.push(format!(
                "the velocity components {} (the cost is flat along a combination of them)",
                b.solution
                    .undetermined
                    .iter()
                    .map(|c| c.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if b.degrees_of_freedom < 0 {
            undetermined.push(format!(
                "more unknowns than evidence ({} degrees of freedom): the answer is one of many",
                b.degrees_of_freedom
            ));
        }
    }
    undetermined.extend(crate::reconstruct_friction::notes(
        r,
        runout,
        outcome.best.as_ref(),
    ));
    undetermined
}
