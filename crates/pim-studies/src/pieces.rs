//! The pieces of a case's evidence that the consistency table leaves out and the page
//! switches off: what each is ([`PieceId`]), its name, the rows of the evidence table it
//! holds, and the case without it.

use crate::documents::DocumentError;
use pim_case::case::Case;
use pim_documents::reconstruct_doc::EvidenceSource;

/// One piece (or group) of evidence that can be left out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Piece {
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

/// A piece of a case's evidence as the consistency table leaves it out, by what it is (the
/// page finds a piece drawn on the plan by it; the name is for display): `kind` is `rest`,
/// `mark`, `edr`, `observation`, `estimates` or `prior`; `vehicle` 1 or 2 for a rest, a mark
/// and an EDR record; `index` from 0 the mark, EDR record, observation or prior.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
pub struct PieceId {
    /// What kind of evidence.
    pub kind: &'static str,
    /// Its vehicle (1 or 2), for a rest, a mark and an EDR record.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vehicle: Option<u8>,
    /// Which one of its kind, from 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub index: Option<usize>,
}

impl Piece {
    /// What it is, for readers of a document.
    fn id(self) -> PieceId {
        let v = |k: usize| Some(k as u8 + 1);
        let (kind, vehicle, index) = match self {
            Piece::Rest(k) => ("rest", v(k), None),
            Piece::Mark(k, i) => ("mark", v(k), Some(i)),
            Piece::Edr(k, i) => ("edr", v(k), Some(i)),
            Piece::Observation(i) => ("observation", None, Some(i)),
            Piece::Estimates => ("estimates", None, None),
            Piece::Prior(i) => ("prior", None, Some(i)),
        };
        PieceId {
            kind,
            vehicle,
            index,
        }
    }

    /// Whether the evidence table's row `source` is (part of) this piece.
    fn holds(self, source: EvidenceSource) -> bool {
        use pim_runout::Quantity as Q;
        match (self, source) {
            (Piece::Rest(k), EvidenceSource::Scene { vehicle, what }) => {
                usize::from(vehicle) == k + 1
                    && matches!(what, Q::RestX | Q::RestY | Q::RestHeading)
            }
            (Piece::Mark(k, i), EvidenceSource::Scene { vehicle, what }) => {
                usize::from(vehicle) == k + 1
                    && matches!(what, Q::Mark { index } | Q::MarkHeading { index } if index == i)
            }
            (Piece::Edr(k, i), EvidenceSource::Edr { vehicle, index }) => {
                usize::from(vehicle) == k + 1 && index == i
            }
            (Piece::Observation(i), EvidenceSource::Observation { index }) => index == i,
            (Piece::Estimates, EvidenceSource::Estimate { .. }) => true,
            (Piece::Prior(i), EvidenceSource::ContactPrior { index }) => index == i,
            _ => false,
        }
    }

    pub(crate) fn name(self, case: &Case) -> String {
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
    fn leave_out(self, case: &Case) -> Case {
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
pub(crate) fn pieces(case: &Case) -> Vec<Piece> {
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
pub(crate) fn left_out(case: &Case, without: &[Piece]) -> Case {
    let mut c = case.clone();
    // Later pieces first, so that the indices of earlier ones stay valid.
    let mut sorted = without.to_vec();
    sorted.sort_by_key(|p| std::cmp::Reverse(index_key(*p)));
    for p in sorted {
        c = p.leave_out(&c);
    }
    c
}

/// The names of the pieces of evidence of `case` that can be switched off, in the order of
/// the evidence table (the names of the consistency table's rows: `vehicle1 rest`, `vehicle2
/// mark 1`, `vehicle2 EDR speed 0.5 s before contact`, an observation's name, `the estimates
/// ([estimates])`, `vehicle1.heading at contact (prior)`).
pub fn piece_names(case: &Case) -> Vec<String> {
    pieces(case).into_iter().map(|p| p.name(case)).collect()
}

/// The piece of `case`'s evidence that the evidence table's row `source` belongs to: none
/// for a row no piece holds (a fitted friction, a combination, the crush energy, a trace's
/// points).
pub fn piece_of(case: &Case, source: EvidenceSource) -> Option<PieceId> {
    pieces(case)
        .into_iter()
        .find(|p| p.holds(source))
        .map(Piece::id)
}

/// Each piece of `case`'s evidence that can be switched off: what it is and its name (as
/// [`piece_names`] gives them, in the same order).
pub fn pieces_named(case: &Case) -> Vec<(PieceId, String)> {
    pieces(case)
        .into_iter()
        .map(|p| (p.id(), p.name(case)))
        .collect()
}

/// `case` with the pieces of evidence named `off` switched off (left out, as the consistency
/// table's rows leave them out).
///
/// # Errors
/// A name that is no piece of the case's evidence, with the names it has.
pub fn switched_off(case: &Case, off: &[String]) -> Result<Case, DocumentError> {
    let all = pieces(case);
    let mut chosen = Vec::new();
    for name in off {
        match all.iter().find(|p| &p.name(case) == name) {
            Some(p) => chosen.push(*p),
            None => {
                return Err(DocumentError::Input(format!(
                    "{}: {name:?} is no piece of this case's evidence; its pieces are: {}",
                    case.file,
                    piece_names(case).join(", ")
                )))
            }
        }
    }
    Ok(left_out(case, &chosen))
}

/// A key that orders pieces of one list (marks of one vehicle, EDRs of one vehicle,
/// observations) by their index.
pub(crate) fn index_key(p: Piece) -> (usize, usize, usize) {
    match p {
        Piece::Estimates => (0, 0, 0),
        Piece::Observation(i) => (1, 0, i),
        Piece::Edr(k, i) => (2, k, i),
        Piece::Rest(k) => (3, k, 0),
        Piece::Mark(k, i) => (4, k, i),
        Piece::Prior(i) => (5, 0, i),
    }
}
