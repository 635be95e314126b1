//! Which question a case asks, decided once for every face.
//!
//! A case with scene evidence (`[scene]` rest positions or marks) asks for its whole
//! reconstruction: the scene, the impact and the pre-impact evidence in one fit. With a cost
//! preset (`--cost`, `cost=`) the same case asks for the fit of its contact estimates alone.
//! A case that gives its coefficients and nothing to fit asks for a solve. Every other case
//! asks for the fit of its impact. `pim fit`, `pim uncertainty`, `pim report`,
//! `pim batch` and the Python package all decide through [`Question::of`], and show the notes
//! it gives.

use pim_case::case::Case;
use pim_fit::CostPreset;

/// The question a case asks under a cost choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Question {
    /// The fit of the impact (its estimates, observations and known components).
    Impact,
    /// The whole reconstruction ([`crate::reconstruct`], [`crate::consistency::answer`]).
    Reconstruction,
    /// The solve of the six equations from the case's coefficients and a state
    /// ([`crate::documents::solve`]): a case with its coefficients and nothing to fit.
    Solve,
}

/// A question and what a face says of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Asked {
    /// The question.
    pub question: Question,
    /// Notes to show with the answer: evidence of the case this question does not use.
    pub notes: Vec<String>,
}

impl Question {
    /// The question `case` asks with the cost preset `cost` (`None`: the case's own cost).
    pub fn of(case: &Case, cost: Option<CostPreset>) -> Asked {
        let scene = case.has_scene_evidence();
        let mut notes = Vec::new();
        let question = if scene && cost.is_none() {
            if let Ok(impact) = case.impact() {
                if let Ok((_, Some(note))) = crate::damage_fit::CrushEnergy::of_case(case, &impact)
                {
                    notes.push(note);
                }
            }
            Question::Reconstruction
        } else if !scene && case.asks_only_a_solve() {
            Question::Solve
        } else {
            if scene {
                notes.push(format!(
                    "{}: with --cost the fit reads the estimates only; without it the case's \
                     scene ([scene]) is fitted too, through the run-outs",
                    case.file
                ));
            }
            Question::Impact
        };
        Asked { question, notes }
    }
}

#[cfg(test)]
mod tests {
    use super::{Question, Question::*};
    use pim_case::case::Case;

    fn example(name: &str) -> Case {
        let path = format!("{}/../../examples/cases/{name}", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        Case::from_text(&path, &text).unwrap()
    }

    /// Each question decided by the case: coefficients and nothing to fit a solve, estimates a
    /// fit, scene evidence a reconstruction (its estimates alone with a cost preset).
    #[test]
    fn every_question_is_decided_from_the_case() {
        for (name, cost, asked) in [
            ("side_impact.toml", None, Solve),
            ("ricsac7_us.toml", None, Solve),
            ("ricsac7_fit.toml", None, Impact),
            ("reconstruction_us.toml", None, Reconstruction),
            (
                "reconstruction_us.toml",
                Some(pim_fit::CostPreset::Q2),
                Impact,
            ),
        ] {
            assert_eq!(Question::of(&example(name), cost).question, asked, "{name}");
        }
    }
}
