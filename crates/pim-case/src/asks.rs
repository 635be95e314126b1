//! What a case asks, from what it gives: its whole reconstruction (scene evidence), a solve
//! (its coefficients and nothing to fit), or the fit of its impact. The faces decide through
//! `pim_studies::question::Question`, which reads these.

use crate::case::Case;

impl Case {
    /// True when the case's `[scene]` gives evidence (a rest position, a rest by its tyres or a
    /// mark) for a vehicle: the case asks for its whole reconstruction.
    pub fn has_scene_evidence(&self) -> bool {
        self.content.scene.as_ref().is_some_and(|s| {
            [&s.vehicle1, &s.vehicle2]
                .into_iter()
                .flatten()
                .any(|v| v.rest.is_some() || !v.rest_tyres.is_empty() || !v.marks.is_empty())
        })
    }

    /// True when the case gives its coefficients and a state to solve from (`[initial]`
    /// forward, `[final]` backward): `pim solve` answers it.
    pub fn solvable(&self) -> bool {
        let c = &self.content;
        c.coefficients.is_some() && (c.initial.is_some() || c.final_.is_some())
    }

    /// True when the case states the separation velocities (`[final]`).
    pub fn states_final(&self) -> bool {
        self.content.final_.is_some()
    }

    /// True when the case gives the vehicles' damage (`[damage]`): the crush energy is
    /// evidence of the fit.
    pub fn has_damage(&self) -> bool {
        self.content.damage.is_some()
    }

    /// True when the case gives its coefficients and nothing to fit (no estimates, known
    /// components or observations): it asks for a solve, as `pim solve` answers it (and `pim
    /// fit` refuses it).
    pub fn asks_only_a_solve(&self) -> bool {
        let c = &self.content;
        c.coefficients.is_some()
            && c.estimates.is_none()
            && c.known.is_none()
            && c.observations.is_empty()
    }
}
