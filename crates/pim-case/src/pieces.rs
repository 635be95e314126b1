//! The pieces of a case's evidence, each by what it is ([`Piece`]): the estimates, each
//! observation, each EDR record, each vehicle's rest (its position and heading, or its tyres)
//! and each of its marks, each prior of the pose at contact; each piece's name for the tables
//! and the case without it (what the consistency table leaves out and the page switches off).

use crate::case::Case;

/// One piece (or group) of evidence that can be left out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Piece {
    /// Vehicle `k`'s rest position and heading.
    Rest(usize),
    /// Vehicle `k`'s mark `i`.
    Mark(usize, usize),
    /// Vehicle `k`'s EDR record `i`.
    Edr(usize, usize),
    /// Observation `i` of `[[observations]]`.
    Observation(usize),
    /// The `[estimates]` (with their `[sigma]`).
    Estimates,
    /// The prior of the pose's unknown `i` (`[contact_sigma]`, in the order of
    /// [`Case::contact_unknowns`]).
    Prior(usize),
}

impl Piece {
    /// Its name for the tables (`vehicle1 rest`, `vehicle2 mark 1`, ...).
    pub fn name(self, case: &Case) -> String {
        let c = &case.content;
        match self {
            Piece::Rest(k) => format!("vehicle{} rest", k + 1),
            Piece::Mark(k, i) => format!("vehicle{} mark {}", k + 1, i + 1),
            Piece::Edr(k, i) => {
                let t = c
                    .pre_impact
                    .as_ref()
                    .and_then(|p| if k == 0 { &p.vehicle1 } else { &p.vehicle2 }.as_ref())
                    .and_then(|p| p.edr.get(i))
                    .map_or(0.0, |e| e.time);
                format!("vehicle{} EDR speed {t:.1} s before contact", k + 1)
            }
            Piece::Observation(i) => match c.observations.get(i).and_then(|o| o.name.clone()) {
                Some(n) => n,
                None => format!("observation {}", i + 1),
            },
            Piece::Estimates => "the estimates ([estimates])".to_string(),
            Piece::Prior(i) => match case.contact_unknowns().ok().and_then(|u| u.get(i).cloned()) {
                Some(u) => format!("{} at contact (prior)", u.name),
                None => format!("prior {} of the pose at contact", i + 1),
            },
        }
    }

    /// The case without this piece.
    pub fn leave_out(self, case: &Case) -> Case {
        let mut out = case.clone();
        let c = &mut out.content;
        match self {
            Piece::Rest(k) | Piece::Mark(k, _) => {
                if let Some(slot) = c.scene.as_mut().map(|s| {
                    if k == 0 {
                        &mut s.vehicle1
                    } else {
                        &mut s.vehicle2
                    }
                }) {
                    if let Some(v) = slot.as_mut() {
                        match self {
                            Piece::Rest(_) => {
                                v.rest = None;
                                v.rest_sigma = None;
                                v.rest_tyres.clear();
                                // A count of turns counts to the rest heading: it goes with it.
                                v.turns = None;
                            }
                            Piece::Mark(_, i) => {
                                v.marks.remove(i);
                            }
                            _ => {}
                        }
                        // A vehicle left with no scene evidence has no scene to fit: its
                        // run-out is no longer part of the reconstruction.
                        if v.rest.is_none() && v.rest_tyres.is_empty() && v.marks.is_empty() {
                            *slot = None;
                        }
                    }
                }
            }
            Piece::Edr(k, i) => {
                if let Some(p) = c.pre_impact.as_mut().and_then(|p| {
                    if k == 0 {
                        &mut p.vehicle1
                    } else {
                        &mut p.vehicle2
                    }
                    .as_mut()
                }) {
                    p.edr.remove(i);
                }
            }
            Piece::Observation(i) => {
                c.observations.remove(i);
            }
            Piece::Estimates => {
                c.estimates = None;
                c.sigma = None;
            }
            Piece::Prior(i) => out = case.without_contact_prior(i),
        }
        out
    }
}

/// The pieces of evidence of a case, in the order of the evidence table.
pub fn pieces(case: &Case) -> Vec<Piece> {
    let c = &case.content;
    let mut out = Vec::new();
    if c.estimates.is_some() {
        out.push(Piece::Estimates);
    }
    out.extend((0..c.observations.len()).map(Piece::Observation));
    for k in 0..2 {
        let edr = c
            .pre_impact
            .as_ref()
            .and_then(|p| if k == 0 { &p.vehicle1 } else { &p.vehicle2 }.as_ref())
            .map_or(0, |p| p.edr.len());
        out.extend((0..edr).map(|i| Piece::Edr(k, i)));
    }
    for k in 0..2 {
        let Some(v) = c
            .scene
            .as_ref()
            .and_then(|s| if k == 0 { &s.vehicle1 } else { &s.vehicle2 }.as_ref())
        else {
            continue;
        };
        if v.rest.is_some() || !v.rest_tyres.is_empty() {
            out.push(Piece::Rest(k));
        }
        out.extend((0..v.marks.len()).map(|i| Piece::Mark(k, i)));
    }
    let priors = case.contact_unknowns().map_or(0, |u| u.len());
    out.extend((0..priors).map(Piece::Prior));
    out
}

/// `case` without the pieces `without`.
pub fn left_out(case: &Case, without: &[Piece]) -> Case {
    let mut c = case.clone();
    // Later pieces first, so that the indices of earlier ones stay valid.
    let mut sorted = without.to_vec();
    sorted.sort_by_key(|p| std::cmp::Reverse(index_key(*p)));
    for p in sorted {
        c = p.leave_out(&c);
    }
    c
}

/// A key that orders pieces of one list (marks of one vehicle, EDRs of one vehicle,
/// observations) by their index.
fn index_key(p: Piece) -> (usize, usize, usize) {
    match p {
        Piece::Estimates => (0, 0, 0),
        Piece::Observation(i) => (1, 0, i),
        Piece::Edr(k, i) => (2, k, i),
        Piece::Rest(k) => (3, k, 0),
        Piece::Mark(k, i) => (4, k, i),
        Piece::Prior(i) => (5, 0, i),
    }
}
