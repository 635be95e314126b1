//! The pieces of a case's evidence that the consistency table leaves out and the page
//! switches off: what each is ([`PieceId`]), its name, the rows of the evidence table it
//! holds, and the case without it.

use crate::documents::DocumentError;
use pim_case::case::Case;
pub(crate) use pim_case::pieces::{left_out, pieces, Piece};
use pim_documents::reconstruct_doc::EvidenceSource;

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

/// What a piece is and which rows of the evidence table it holds.
pub(crate) trait Identified {
    /// What it is, for readers of a document.
    fn id(self) -> PieceId;
    /// Whether the evidence table's row `source` is (part of) this piece.
    fn holds(self, source: EvidenceSource) -> bool;
}

impl Identified for Piece {
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
